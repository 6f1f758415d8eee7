/* ClearanceWearJoint as a model of the generic FMI layers (fmu_model.h): the joint's variables by
 * value reference (FMI 2.0: the wear profile as scalars wear_depth[1..N_d]; FMI 3.0: one Float64
 * array sized by the structural parameter n_points, then the independent time), on the
 * FMI-independent joint of joint_instance.c.
 *
 * Semantics (docs/model.md §5): the forces are direct feed-through, evaluated at the first read
 * of a joint output after an input changed; Co-Simulation accepts a step with the inputs held at
 * its start (wear, contact onsets); Model Exchange has no continuous states and one event
 * indicator, the signed penetration (a contact onset is a state event, where the approach
 * velocity is stored), and applies wear at each completed integrator step.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fmu_model.h"
#include "joint_instance.h"

struct FmuModel {
    JointInstance *joint;
    uint64_t configured_n_points;   /* FMI 3.0 Configuration Mode: the value set for n_points */
};

/* ------------------------------------------------------------------ lifetime */
FmuModel *model_new(const char *name, int logging_on, FmuLogFunction *log, FmuAllocateFunction *allocate,
                    FmuReleaseFunction *release, void *environment)
{
    JointInstance *joint = joint_new(name, N_POINTS, logging_on, log, allocate, release, environment);
    if (joint == NULL)
        return NULL;
    FmuModel *model = allocate(environment, 1, sizeof *model);
    if (model == NULL) {
        joint_log(joint, FMU_ERROR, "fmiInstantiate: out of memory");
        joint_free(joint);
        return NULL;
    }
    model->joint = joint;
    model->configured_n_points = N_POINTS;
    return model;
}

void model_free(FmuModel *model)
{
    if (model == NULL)
        return;
    FmuHost host = model->joint->host;
    joint_free(model->joint);
    host.release(host.environment, model);
}

FmuHost *model_host(FmuModel *model) { return &model->joint->host; }

/* Back to the start values, n_points (FMI 3.0) too. */
int model_reset(FmuModel *model)
{
    if (!joint_resize(model->joint, N_POINTS))
        return 0;
    model->configured_n_points = N_POINTS;
    return 1;
}

double model_time(const FmuModel *model) { return model->joint->time; }

void model_set_start_time(FmuModel *model, double time)
{
    model->joint->time = model->joint->last_accepted_time = time;
}

int model_exit_initialization(FmuModel *model, const char *function)
{
    if (!joint_pack_parameters(model->joint, function))
        return 0;
    model->joint->last_accepted_time = model->joint->time;
    return 1;
}

/* ------------------------------------------------------------------ values */
void model_variable_name(const FmuModel *model, int fmi_version, unsigned vr, char *out, size_t size)
{
    if (vr < N_INPUTS)
        snprintf(out, size, "%s", INPUT_NAMES[vr]);
    else if (vr < VR_FIRST_PARAMETER + N_PARAMETERS)
        snprintf(out, size, "%s", PARAMETERS[vr - VR_FIRST_PARAMETER].name);
    else if (vr == VR_N_POINTS)
        snprintf(out, size, "n_points");
    else if (vr < VR_FIRST_OUTPUT + N_SCALAR_OUTPUTS)
        snprintf(out, size, "%s", OUTPUTS[vr - VR_FIRST_OUTPUT].name);
    else if (fmi_version == 2 && vr < VR_FIRST_WEAR_DEPTH + N_PROFILE_OUTPUTS)
        snprintf(out, size, "wear_depth[%u]", (unsigned)((vr - VR_FIRST_WEAR_DEPTH) * PROFILE_STRIDE + 1));
    else if (fmi_version == 3 && vr == FMI3_VR_WEAR_DEPTH)
        snprintf(out, size, "wear_depth");
    else if (fmi_version == 3 && vr == FMI3_VR_TIME)
        snprintf(out, size, "time");
    else
        snprintf(out, size, "<no variable with valueReference %u>", vr);
}

/* A Real parameter (choice = 0) or an enumeration (choice = 1). */
static int is_parameter(unsigned vr, int choice)
{
    return vr >= VR_FIRST_PARAMETER && vr < VR_FIRST_PARAMETER + N_PARAMETERS &&
           (PARAMETERS[vr - VR_FIRST_PARAMETER].n_choices > 0) == choice;
}

static int is_scalar_output(unsigned vr) { return vr >= VR_FIRST_OUTPUT && vr < VR_FIRST_OUTPUT + N_SCALAR_OUTPUTS; }

/* The scalars keep their FMI 2.0 value references in FMI 3.0 (FMI3_VR_FIRST_INPUT is 0). */
size_t model_float64_count(const FmuModel *model, int fmi_version, unsigned vr)
{
    if (vr < N_INPUTS || is_parameter(vr, 0) || is_scalar_output(vr))
        return 1;
    if (fmi_version == 2)
        return vr >= VR_FIRST_WEAR_DEPTH && vr < VR_FIRST_WEAR_DEPTH + N_PROFILE_OUTPUTS;
    if (vr == FMI3_VR_WEAR_DEPTH)
        return (size_t)model->joint->n_points;
    return vr == FMI3_VR_TIME;
}

const char *model_array_sizes(const FmuModel *model, char *out, size_t size)
{
    snprintf(out, size, " (wear_depth has n_points=%lld)", (long long)model->joint->n_points);
    return out;
}

int model_get_float64(FmuModel *model, int fmi_version, unsigned vr, double *values, const char *function)
{
    JointInstance *joint = model->joint;
    if (vr < N_INPUTS) {
        values[0] = joint->inputs[vr];
    } else if (is_parameter(vr, 0)) {
        values[0] = joint->parameters[vr - VR_FIRST_PARAMETER];
    } else if (is_scalar_output(vr)) {
        const OutputInfo *o = &OUTPUTS[vr - VR_FIRST_OUTPUT];
        if (o->source == OUTPUT_FROM_RESULT) {
            /* evaluated at the first joint output after an input changed, then current */
            if (!joint_evaluate(joint, function, o->name))
                return 0;
            values[0] = joint->result[o->index];
        } else {
            if (!joint_wear_summary(joint, function))
                return 0;
            values[0] = o->source == OUTPUT_MAX_WEAR_DEPTH ? joint->max_wear_depth : joint->worn_volume;
        }
    } else if (fmi_version == 2 && model_float64_count(model, 2, vr) == 1) {
        values[0] = joint->wear_depth[(vr - VR_FIRST_WEAR_DEPTH) * PROFILE_STRIDE];
    } else if (fmi_version == 3 && vr == FMI3_VR_WEAR_DEPTH) {
        memcpy(values, joint->wear_depth, (size_t)joint->n_points * sizeof(double));
    } else if (fmi_version == 3 && vr == FMI3_VR_TIME) {
        values[0] = joint->time;
    } else {
        return -1;
    }
    return 1;
}

int model_set_float64(FmuModel *model, int fmi_version, unsigned vr, double value, int parameters_settable,
                      const char *function)
{
    (void)fmi_version;
    (void)function;
    if (vr < N_INPUTS) {
        joint_set_input(model->joint, (int)vr, value);
    } else if (is_parameter(vr, 0)) {
        if (!parameters_settable)
            return -2;
        joint_set_parameter(model->joint, (int)(vr - VR_FIRST_PARAMETER), value);
    } else {
        return -1;
    }
    return 1;
}

/* FMI 2.0 Integer: n_points and the enumerations; FMI 3.0 Int64: the enumerations. */
int model_get_integer(FmuModel *model, int fmi_version, unsigned vr, int64_t *value, const char *function)
{
    (void)function;
    if (fmi_version == 2 && vr == VR_N_POINTS)
        *value = model->joint->n_points;
    else if (is_parameter(vr, 1))
        *value = (int64_t)model->joint->parameters[vr - VR_FIRST_PARAMETER];
    else
        return -1;
    return 1;
}

int model_set_integer(FmuModel *model, int fmi_version, unsigned vr, int64_t value, int parameters_settable,
                      const char *function)
{
    JointInstance *joint = model->joint;
    if (fmi_version == 2 && vr == VR_N_POINTS) {
        if (value == joint->n_points)
            return 1;
        joint_log(joint, FMU_ERROR,
                  "%s: n_points is fixed at %lld when the FMU is built; rebuild it for %d points (wearjoint "
                  "build-fmu --n-points %d)", function, (long long)joint->n_points, (int)value, (int)value);
        return 0;
    }
    if (!is_parameter(vr, 1))
        return -1;
    if (!parameters_settable)
        return -2;
    /* checked at exitInitializationMode, like every parameter */
    joint_set_parameter(joint, (int)(vr - VR_FIRST_PARAMETER), (double)value);
    return 1;
}

/* FMI 3.0: the structural parameter n_points, readable in every state. */
int model_get_structural(FmuModel *model, unsigned vr, int configuration, uint64_t *value)
{
    if (vr != FMI3_VR_N_POINTS)
        return -1;
    *value = configuration ? model->configured_n_points : (uint64_t)model->joint->n_points;
    return 1;
}

int model_set_structural(FmuModel *model, unsigned vr, uint64_t value, int configuration, int settable,
                         const char *state, const char *function)
{
    JointInstance *joint = model->joint;
    if (vr != FMI3_VR_N_POINTS)
        return -1;
    if (!configuration) {
        if (value == (uint64_t)joint->n_points && settable)
            return 1;   /* its current value: nothing changes */
        joint_log(joint, FMU_ERROR,
                  "%s: the structural parameter n_points (now %lld) can be changed in Configuration Mode only "
                  "(fmi3EnterConfigurationMode after instantiation), not in state %s", function,
                  (long long)joint->n_points, state);
        return 0;
    }
    if (value < FMI3_N_POINTS_MIN || value > FMI3_N_POINTS_MAX) {
        joint_log(joint, FMU_ERROR, "%s: structural parameter n_points=%llu is invalid: allowed an integer in [%d, %d]",
                  function, (unsigned long long)value, FMI3_N_POINTS_MIN, FMI3_N_POINTS_MAX);
        return 0;
    }
    model->configured_n_points = value;
    return 1;
}

void model_enter_configuration(FmuModel *model) { model->configured_n_points = (uint64_t)model->joint->n_points; }

/* Re-size the bushing to the n_points set; inputs, parameters and the time set before are kept. */
int model_exit_configuration(FmuModel *model)
{
    JointInstance *joint = model->joint;
    if ((int64_t)model->configured_n_points == joint->n_points)
        return 1;
    double inputs[N_INPUTS], parameters[N_PARAMETERS];
    double time = joint->time;
    memcpy(inputs, joint->inputs, sizeof inputs);
    memcpy(parameters, joint->parameters, sizeof parameters);
    if (!joint_resize(joint, (int64_t)model->configured_n_points))
        return 0;   /* out of memory (logged): the old size stays */
    for (int i = 0; i < N_INPUTS; i++)
        joint_set_input(joint, i, inputs[i]);
    for (int i = 0; i < N_PARAMETERS; i++)
        joint_set_parameter(joint, i, parameters[i]);
    joint->time = joint->last_accepted_time = time;
    return 1;
}

/* ------------------------------------------------------------------ directional derivatives */
/* The number of values of output ``vr`` (an FMI 3.0 array: its size) and, in *row, its derivatives with respect
 * to the inputs (NULL: none, the wear); 0 if ``vr`` is no output. */
static size_t output_derivatives(const FmuModel *model, int fmi_version, unsigned vr, const double **row)
{
    *row = NULL;
    if (is_scalar_output(vr)) {
        const OutputInfo *o = &OUTPUTS[vr - VR_FIRST_OUTPUT];
        if (o->source == OUTPUT_FROM_RESULT)
            *row = model->joint->jacobian + (size_t)o->index * N_INPUTS;
        return 1;
    }
    if (fmi_version == 2)
        return vr >= VR_FIRST_WEAR_DEPTH && vr < VR_FIRST_WEAR_DEPTH + N_PROFILE_OUTPUTS;
    return vr == FMI3_VR_WEAR_DEPTH ? (size_t)model->joint->n_points : 0;
}

/* 1 if ``accepted``; else logs that the ``what`` ``vr`` (named) is invalid and what is allowed. */
static int derivative_variable(const FmuModel *model, int fmi_version, unsigned vr, int accepted, const char *what,
                               const char *allowed, const char *function)
{
    if (accepted)
        return 1;
    char name[96];
    model_variable_name(model, fmi_version, vr, name, sizeof name);
    joint_log(model->joint, FMU_ERROR, "%s: %s %s (valueReference %u) is invalid: allowed %s", function, what, name,
              vr, allowed);
    return 0;
}

/* sensitivity = J seed: J the derivatives of the unknowns (outputs) with respect to the knowns (inputs); the
 * forces, torques and contact geometry are the kernels' exact derivatives, the wear outputs do not depend on the
 * inputs (0). */
int model_directional_derivative(FmuModel *model, int fmi_version, const unsigned *unknowns, size_t n_unknowns,
                                 const unsigned *knowns, size_t n_knowns, const double *seed, double *sensitivity,
                                 const char *function)
{
    const double *row;
    const char *needs_jacobian = NULL;   /* the first unknown that depends on the inputs */
    for (size_t j = 0; j < n_knowns; j++)
        if (!derivative_variable(model, fmi_version, knowns[j], knowns[j] < N_INPUTS, "known",
                                 "an input (the 12 kinematic inputs)", function))
            return 0;
    for (size_t i = 0; i < n_unknowns; i++) {
        int output = output_derivatives(model, fmi_version, unknowns[i], &row) > 0;
        if (!derivative_variable(model, fmi_version, unknowns[i], output, "unknown", "an output", function))
            return 0;
        if (row != NULL && needs_jacobian == NULL)
            needs_jacobian = OUTPUTS[unknowns[i] - VR_FIRST_OUTPUT].name;
    }
    if (needs_jacobian != NULL && !joint_jacobian(model->joint, function, needs_jacobian))
        return 0;
    size_t k = 0;
    for (size_t i = 0; i < n_unknowns; i++) {
        size_t count = output_derivatives(model, fmi_version, unknowns[i], &row);
        double sum = 0.0;
        for (size_t j = 0; row != NULL && j < n_knowns; j++)
            sum += row[knowns[j]] * seed[j];
        for (size_t z = 0; z < count; z++)
            sensitivity[k++] = sum;
    }
    return 1;
}

/* ------------------------------------------------------------------ Co-Simulation */
/* Accept the step with the inputs held at t: wear and contact-onset bookkeeping. */
int model_do_step(FmuModel *model, double t, double h, const char *function)
{
    JointInstance *joint = model->joint;
    double previous = joint->time;
    joint->time = t;
    int status = joint_accept_step(joint, h, 1, function);
    if (status > JOINT_WARNING) {
        joint->time = previous;
        return status;
    }
    joint->time = joint->last_accepted_time = t + h;
    return status;   /* a warning: the step is accepted */
}

/* ------------------------------------------------------------------ Model Exchange: no continuous states */
int model_set_time(FmuModel *model, double time, const char *function)
{
    return joint_set_time(model->joint, time, function);
}

int model_get_continuous_states(FmuModel *model, double *x, const char *function)
{
    (void)model, (void)x, (void)function;
    return 1;
}

int model_set_continuous_states(FmuModel *model, const double *x, const char *function)
{
    (void)model, (void)x, (void)function;
    return 1;
}

int model_get_derivatives(FmuModel *model, double *dx, const char *function)
{
    (void)model, (void)dx, (void)function;
    return 1;
}

/* The signed penetration of the deepest bushing point at the current inputs. */
int model_get_event_indicators(FmuModel *model, double *z, const char *function)
{
    return joint_event_indicator(model->joint, function, &z[0]);
}

/* A contact begins or ends: the contact-onset bookkeeping at the current inputs. */
int model_event_update(FmuModel *model, const char *function)
{
    return joint_update_contact_memory(model->joint, function);
}

/* Wear and the onset bookkeeping over the step since the last completed one, at the current inputs. */
int model_completed_integrator_step(FmuModel *model, const char *function)
{
    return joint_completed_integrator_step(model->joint, function);
}

/* ------------------------------------------------------------------ FMU state */
size_t model_state_size(const FmuModel *model) { return joint_state_size(model->joint); }

void model_get_state(const FmuModel *model, double *state, int initialised)
{
    joint_get_state(model->joint, state, initialised);
}

int model_set_state(FmuModel *model, const double *state, int *initialised, const char *function)
{
    return joint_set_state(model->joint, state, initialised, function);
}

size_t model_serialized_state_size(const FmuModel *model, const double *state)
{
    (void)model;
    return joint_serialized_state_size(state);
}

void model_serialize_state(const FmuModel *model, const double *state, unsigned char *bytes)
{
    (void)model;
    joint_serialize_state(state, bytes);
}

int model_deserialize_state(FmuModel *model, const unsigned char *bytes, size_t size, double *state,
                            const char *function)
{
    return joint_deserialize_state(model->joint, bytes, size, state, function);
}
