/* ClearanceWearJoint's variables by value reference (fmu_model.h, "Values"; the joint's data: joint_model.h):
 * names, counts, gets and sets, the FMI 3.0 structural parameter n_points and the directional derivatives.
 * FMI 2.0 has the wear profile as scalars wear_depth[1..N_d]; FMI 3.0 one Float64 array sized by the
 * structural parameter n_points, then the independent time.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "joint_model.h"

/* ------------------------------------------------------------------ values */
/* The inputs that are not finite, as name=value, into out. */
void describe_non_finite_inputs(const FmuModel *model, char *out, size_t size)
{
    size_t used = 0;
    out[0] = '\0';
    for (int i = 0; i < N_INPUTS && used < size; i++)
        if (model->non_finite_inputs & (1u << i)) {
            int n = snprintf(out + used, size - used, "%s%s=%g", used ? ", " : "", INPUT_NAMES[i], model->inputs[i]);
            if (n < 0)
                break;
            used += (size_t)n;
        }
}

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
        return (size_t)model->n_points;
    return vr == FMI3_VR_TIME;
}

const char *model_array_sizes(const FmuModel *model, char *out, size_t size)
{
    snprintf(out, size, " (wear_depth has n_points=%lld)", (long long)model->n_points);
    return out;
}

int model_get_float64(FmuModel *model, int fmi_version, unsigned vr, double *values, const char *function)
{
    /* a linearising master reads the N_DERIVATIVE_OUTPUTS derivatives every step: those of the current evaluation,
     * finite, without the table's tests; the OUTPUT_FROM_JACOBIAN branch below the others (evaluated, checked and
     * logged by joint_jacobian) */
    unsigned derivative = vr - VR_FIRST_DERIVATIVE;
    if (derivative < N_DERIVATIVE_OUTPUTS && !model->forces_stale && !model->parameters_changed &&
        !model->jacobian_stale) {
        double value = model->jacobian[OUTPUTS[vr - VR_FIRST_OUTPUT].index];
        if (isfinite(value)) {
            model->jacobian_read = 1;
            values[0] = value;
            return 1;
        }
    }
    if (vr < N_INPUTS) {
        values[0] = model->inputs[vr];
    } else if (is_parameter(vr, 0)) {
        values[0] = model->parameters[vr - VR_FIRST_PARAMETER];
    } else if (is_scalar_output(vr)) {
        const OutputInfo *o = &OUTPUTS[vr - VR_FIRST_OUTPUT];
        /* evaluated at the first joint output after an input changed, then current: a host reads many outputs of
         * one evaluation, each checked here without a call */
        int current = !model->forces_stale && !model->parameters_changed;
        if (o->source == OUTPUT_FROM_RESULT) {
            if (!current && !joint_evaluate(model, function, o->name))
                return 0;
            values[0] = model->result[o->index];
        } else if (o->source == OUTPUT_FROM_JACOBIAN) {   /* those the fast path above did not answer */
            if (!joint_jacobian(model, function, o->name))
                return 0;
            values[0] = model->jacobian[o->index];
        } else if (o->source == OUTPUT_FROM_INPUT) {
            values[0] = model->inputs[o->index];
        } else {
            if (!joint_wear_summary(model, function))
                return 0;
            values[0] = o->source == OUTPUT_MAX_WEAR_DEPTH ? model->max_wear_depth : model->worn_volume;
        }
    } else if (fmi_version == 2 && model_float64_count(model, 2, vr) == 1) {
        values[0] = model->wear_depth[(vr - VR_FIRST_WEAR_DEPTH) * PROFILE_STRIDE];
    } else if (fmi_version == 3 && vr == FMI3_VR_WEAR_DEPTH) {
        memcpy(values, model->wear_depth, (size_t)model->n_points * sizeof(double));
    } else if (fmi_version == 3 && vr == FMI3_VR_TIME) {
        values[0] = model->time;
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
        joint_set_input(model, (int)vr, value);
    } else if (is_parameter(vr, 0)) {
        if (!parameters_settable)
            return -2;
        joint_set_parameter(model, (int)(vr - VR_FIRST_PARAMETER), value);
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
        *value = model->n_points;
    else if (is_parameter(vr, 1))
        *value = (int64_t)model->parameters[vr - VR_FIRST_PARAMETER];
    else
        return -1;
    return 1;
}

int model_set_integer(FmuModel *model, int fmi_version, unsigned vr, int64_t value, int parameters_settable,
                      const char *function)
{
    if (fmi_version == 2 && vr == VR_N_POINTS) {
        if (value == model->n_points)
            return 1;
        fmu_log(&model->host, FMU_ERROR,
                "%s: n_points is fixed at %lld when the FMU is built; rebuild it for %d points (wearjoint "
                "build-fmu --n-points %d)", function, (long long)model->n_points, (int)value, (int)value);
        return 0;
    }
    if (!is_parameter(vr, 1))
        return -1;
    if (!parameters_settable)
        return -2;
    /* checked at exitInitializationMode, like every parameter */
    joint_set_parameter(model, (int)(vr - VR_FIRST_PARAMETER), (double)value);
    return 1;
}

/* FMI 3.0: the structural parameter n_points, readable in every state. */
int model_get_structural(FmuModel *model, unsigned vr, int configuration, uint64_t *value)
{
    if (vr != FMI3_VR_N_POINTS)
        return -1;
    *value = configuration ? model->configured_n_points : (uint64_t)model->n_points;
    return 1;
}

int model_set_structural(FmuModel *model, unsigned vr, uint64_t value, int configuration, int settable,
                         const char *state, const char *function)
{
    if (vr != FMI3_VR_N_POINTS)
        return -1;
    if (!configuration) {
        if (value == (uint64_t)model->n_points && settable)
            return 1;   /* its current value: nothing changes */
        fmu_log(&model->host, FMU_ERROR,
                "%s: the structural parameter n_points (now %lld) can be changed in Configuration Mode only "
                "(fmi3EnterConfigurationMode after instantiation), not in state %s", function,
                (long long)model->n_points, state);
        return 0;
    }
    if (value < FMI3_N_POINTS_MIN || value > FMI3_N_POINTS_MAX) {
        fmu_log(&model->host, FMU_ERROR, "%s: structural parameter n_points=%llu is invalid: allowed an integer in "
                "[%d, %d]", function, (unsigned long long)value, FMI3_N_POINTS_MIN, FMI3_N_POINTS_MAX);
        return 0;
    }
    model->configured_n_points = value;
    return 1;
}

/* ------------------------------------------------------------------ directional derivatives */
/* The number of values of output ``vr`` (an FMI 3.0 array: its size), in *row its derivatives with respect to the
 * inputs from the kernels' Jacobian (NULL: none, the wear and the evaluated inputs) and in *input the input an
 * evaluated input repeats (else -1); 0 if ``vr`` is no output or one of the derivatives (whose own derivatives are
 * not provided). */
static size_t output_derivatives(const FmuModel *model, int fmi_version, unsigned vr, const double **row, int *input)
{
    *row = NULL;
    *input = -1;
    if (is_scalar_output(vr)) {
        const OutputInfo *o = &OUTPUTS[vr - VR_FIRST_OUTPUT];
        if (o->source == OUTPUT_FROM_RESULT)
            *row = model->jacobian + (size_t)o->index * N_INPUTS;
        else if (o->source == OUTPUT_FROM_INPUT)
            *input = o->index;
        return o->source != OUTPUT_FROM_JACOBIAN;
    }
    if (fmi_version == 2)
        return vr >= VR_FIRST_WEAR_DEPTH && vr < VR_FIRST_WEAR_DEPTH + N_PROFILE_OUTPUTS;
    return vr == FMI3_VR_WEAR_DEPTH ? (size_t)model->n_points : 0;
}

/* 1 if ``accepted``; else logs that the ``what`` ``vr`` (named) is invalid and what is allowed. */
static int derivative_variable(const FmuModel *model, int fmi_version, unsigned vr, int accepted, const char *what,
                               const char *allowed, const char *function)
{
    if (accepted)
        return 1;
    char name[96];
    model_variable_name(model, fmi_version, vr, name, sizeof name);
    fmu_log(&model->host, FMU_ERROR, "%s: %s %s (valueReference %u) is invalid: allowed %s", function, what, name,
            vr, allowed);
    return 0;
}

/* sensitivity = J seed: J the derivatives of the unknowns (outputs) with respect to the knowns (inputs); the
 * forces, torques and contact geometry are the kernels' exact derivatives, an evaluated input's is 1 for its input,
 * the wear outputs do not depend on the inputs (0). */
int model_directional_derivative(FmuModel *model, int fmi_version, const unsigned *unknowns, size_t n_unknowns,
                                 const unsigned *knowns, size_t n_knowns, const double *seed, double *sensitivity,
                                 const char *function)
{
    const double *row;
    int input;
    const char *needs_jacobian = NULL;   /* the first unknown that depends on the inputs */
    for (size_t j = 0; j < n_knowns; j++)
        if (!derivative_variable(model, fmi_version, knowns[j], knowns[j] < N_INPUTS, "known",
                                 "an input (the 12 kinematic inputs)", function))
            return 0;
    for (size_t i = 0; i < n_unknowns; i++) {
        int output = output_derivatives(model, fmi_version, unknowns[i], &row, &input) > 0;
        if (!derivative_variable(model, fmi_version, unknowns[i], output, "unknown",
                                 "an output but the derivatives d_*_d_* (their own derivatives are not provided)",
                                 function))
            return 0;
        if (row != NULL && needs_jacobian == NULL)
            needs_jacobian = OUTPUTS[unknowns[i] - VR_FIRST_OUTPUT].name;
    }
    if (needs_jacobian != NULL && !joint_jacobian(model, function, needs_jacobian))
        return 0;
    size_t k = 0;
    for (size_t i = 0; i < n_unknowns; i++) {
        size_t count = output_derivatives(model, fmi_version, unknowns[i], &row, &input);
        double sum = 0.0;
        for (size_t j = 0; j < n_knowns; j++)
            sum += row != NULL ? row[knowns[j]] * seed[j] : (int)knowns[j] == input ? seed[j] : 0.0;
        for (size_t z = 0; z < count; z++)
            sensitivity[k++] = sum;
    }
    return 1;
}
