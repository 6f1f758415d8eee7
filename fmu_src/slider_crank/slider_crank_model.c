/* SliderCrank as a model of the generic FMI layers (fmu_model.h): the paper's rigid slider-crank
 * with the crank-rod joint open (Eqs. 38-44), whose loads are the inputs.
 *
 * The state is y = [q, q_dot] (18 values).  At exitInitializationMode (and when a state variable
 * is read before) y is the ideal mechanism's consistent state at the start time.  Co-Simulation:
 * doStep(t, h) integrates y over [t, t + h] in ceil(h / max_internal_step) RK4 steps with the
 * load inputs held or (load_coupling 1) linearised about the joint's evaluated inputs.  Model Exchange: y are the continuous states, their derivatives the kernels'
 * right-hand side.  All the arithmetic is in the compiled kernels (slider_crank_kernels.h); this
 * file holds the memory, the variables and the checks.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fmu_model.h"
#include "model_variables.h"
#include "slider_crank_kernels.h"

#define N_Y (2 * N_COORDINATES)

struct FmuModel {
    FmuHost host;                      /* first (fmu_new_instance) */
    double time;
    double inputs[N_INPUTS];
    double parameters[N_PARAMETERS];   /* FMU parameter values */
    int parameters_changed;            /* since mp was packed */
    int state_stale;                   /* y is not yet the initial state for these parameters and start time */
    int derivatives_stale;             /* dy does not belong to the current time, y and inputs */
    double mp[N_MECHANISM_PARAMETERS];
    double y[N_Y], dy[N_Y];
    /* the kernels' scratch: the mechanism's workspace (minv is M^-1) and the RK4 stages */
    double jac[N_COORDINATES * N_COORDINATES], schur[N_COORDINATES * N_COORDINATES];
    double phi[N_COORDINATES], phi_dot[N_COORDINATES], gamma[N_COORDINATES], minv[N_COORDINATES];
    double force[N_COORDINATES], stages[4 * N_Y];
    double linearisation[N_LINEARISATION], loads[6];   /* load_coupling linearised: F0 + J (u - u0), its loads */
};

/* ------------------------------------------------------------------ lifetime */
static void reset(FmuModel *model)
{
    model->time = 0.0;
    memset(model->inputs, 0, sizeof model->inputs);
    for (int i = 0; i < N_PARAMETERS; i++)
        model->parameters[i] = PARAMETERS[i].start;
    model->parameters_changed = model->state_stale = model->derivatives_stale = 1;
    memset(model->y, 0, sizeof model->y);
    memset(model->dy, 0, sizeof model->dy);
}

FmuModel *model_new(const char *name, int logging_on, FmuLogFunction *log, FmuAllocateFunction *allocate,
                    FmuReleaseFunction *release, void *environment)
{
    FmuModel *model = fmu_new_instance(sizeof *model, name, logging_on, log, allocate, release, environment);
    if (model != NULL)
        reset(model);
    return model;
}

void model_free(FmuModel *model)
{
    if (model != NULL)
        fmu_free_instance(model);
}

FmuHost *model_host(FmuModel *model) { return &model->host; }

int model_reset(FmuModel *model)
{
    reset(model);
    return 1;
}

double model_time(const FmuModel *model) { return model->time; }

void model_set_start_time(FmuModel *model, double time)
{
    model->time = time;
    model->state_stale = model->derivatives_stale = 1;
}

/* ------------------------------------------------------------------ the kernels */
/* Check and pack the parameters; then, if stale, the initial state at the current time. */
static int prepare(FmuModel *model, const char *function)
{
    int32_t status = 0;
    if (model->parameters_changed) {
        if (!fmu_parameters_valid(&model->host, PARAMETERS, N_PARAMETERS, model->parameters, function))
            return 0;
        int32_t problem = 0;
        slider_crank_parameters(&problem, NULL, model->parameters, model->mp, model->minv);
        if (problem != 0) {
            int row = (int)(problem % LOAD_TABLE_ROW_BASE);
            const char *text = LOAD_TABLE_PROBLEMS[problem / LOAD_TABLE_ROW_BASE - 1];
            if (row > 0)
                fmu_log(&model->host, FMU_ERROR, "%s: slider-load table, row %d: %s", function, row, text);
            else
                fmu_log(&model->host, FMU_ERROR, "%s: slider-load table: slider_force_table_rows=%g is invalid: %s",
                        function, model->parameters[P_LOAD_TABLE_ROWS], text);
            return 0;
        }
        model->parameters_changed = 0;
        model->derivatives_stale = 1;
    }
    if (model->state_stale) {
        slider_crank_initial_state(&status, NULL, model->time, model->mp, model->jac, model->schur, model->phi,
                                   model->phi_dot, model->gamma, model->minv, model->force, model->y);
        model->state_stale = 0;
        model->derivatives_stale = 1;
    }
    return 1;
}

/* 1 if every input is finite; else logs them ("<what>: undefined for non-finite inputs (...)"). */
static int inputs_finite(const FmuModel *model, const char *what)
{
    char text[512];
    size_t used = 0;
    text[0] = '\0';
    for (int i = 0; i < N_INPUTS; i++)
        if (!isfinite(model->inputs[i]) && used < sizeof text) {
            int n = snprintf(text + used, sizeof text - used, "%s%s=%g", used ? ", " : "", VARIABLES[i].name,
                             model->inputs[i]);
            if (n < 0)
                break;
            used += (size_t)n;
        }
    if (used == 0)
        return 1;
    fmu_log(&model->host, FMU_ERROR, "%s: undefined for non-finite inputs (%s)", what, text);
    return 0;
}

/* dy at the current time, state and inputs (Eq. 44). */
static int derivatives(FmuModel *model, const char *function)
{
    if (!prepare(model, function))
        return 0;
    if (!model->derivatives_stale)
        return 1;
    if (!inputs_finite(model, function))
        return 0;
    int32_t status = 0;
    slider_crank_derivative(&status, NULL, model->time, model->y, model->mp, model->inputs, model->jac, model->schur,
                            model->phi, model->phi_dot, model->gamma, model->minv, model->force, model->dy);
    model->derivatives_stale = 0;
    return 1;
}

int model_exit_initialization(FmuModel *model, const char *function) { return prepare(model, function); }

/* ------------------------------------------------------------------ values: VR = position in VARIABLES */
void model_variable_name(const FmuModel *model, int fmi_version, unsigned vr, char *out, size_t size)
{
    (void)model;
    if (vr < N_VARIABLES)
        snprintf(out, size, "%s", VARIABLES[vr].name);
    else if (fmi_version == 3 && vr == FMI3_VR_TIME)
        snprintf(out, size, "time");
    else
        snprintf(out, size, "<no variable with valueReference %u>", vr);
}

size_t model_float64_count(const FmuModel *model, int fmi_version, unsigned vr)
{
    (void)model;
    return vr < N_VARIABLES || (fmi_version == 3 && vr == FMI3_VR_TIME);
}

const char *model_array_sizes(const FmuModel *model, char *out, size_t size)
{
    (void)model;
    if (size > 0)
        out[0] = '\0';
    return out;
}

int model_get_float64(FmuModel *model, int fmi_version, unsigned vr, double *values, const char *function)
{
    if (vr >= N_VARIABLES) {
        if (fmi_version != 3 || vr != FMI3_VR_TIME)
            return -1;
        values[0] = model->time;
        return 1;
    }
    const VariableInfo *v = &VARIABLES[vr];
    switch (v->source) {
    case SOURCE_INPUT:
        values[0] = model->inputs[v->index];
        return 1;
    case SOURCE_PARAMETER:
        values[0] = model->parameters[v->index];
        return 1;
    case SOURCE_STATE:
        if (!prepare(model, function))
            return 0;
        values[0] = model->y[v->index];
        return 1;
    case SOURCE_JOINT: {
        if (!prepare(model, function))
            return 0;
        double kinematics[12];
        int32_t status = 0;
        slider_crank_joint_kinematics(&status, NULL, model->y, model->mp, kinematics);
        values[0] = kinematics[v->index];
        return 1;
    }
    default: { /* SOURCE_DERIVATIVE */
        char what[128];
        snprintf(what, sizeof what, "%s of %s", function, v->name);
        if (!derivatives(model, what))
            return 0;
        values[0] = model->dy[v->index];
        return 1;
    }
    }
}

int model_set_float64(FmuModel *model, int fmi_version, unsigned vr, double value, int parameters_settable,
                      const char *function)
{
    (void)fmi_version;
    (void)function;
    if (vr >= N_VARIABLES)
        return -1;
    const VariableInfo *v = &VARIABLES[vr];
    if (v->source == SOURCE_INPUT) {
        model->inputs[v->index] = value;
        model->derivatives_stale = 1;
    } else if (v->source == SOURCE_PARAMETER) {
        if (!parameters_settable)
            return -2;
        model->parameters[v->index] = value;
        model->parameters_changed = model->state_stale = 1;
    } else {
        return -1;
    }
    return 1;
}

/* No Integer, structural or directional-derivative support: fmu_src/fmi/fmu_model_defaults.c. */

/* ------------------------------------------------------------------ Co-Simulation */
/* y over [t, t + h] in ceil(h / max_internal_step) RK4 steps, the loads held at their inputs' values or (load_coupling
 * 1) linearised. */
int model_do_step(FmuModel *model, double t, double h, const char *function)
{
    char what[128];
    snprintf(what, sizeof what, "%s: step at t=%.17g s rejected", function, t);
    if (!inputs_finite(model, what))
        return FMU_DISCARD;
    if (!(h >= 0.0 && isfinite(h))) {
        fmu_log(&model->host, FMU_ERROR, "%s: step rejected: step size %g s is not a finite value >= 0", function, h);
        return FMU_DISCARD;
    }
    if (!prepare(model, function))
        return FMU_ERROR;
    double steps = ceil(h / model->parameters[P_MAX_INTERNAL_STEP]);
    if (steps > 1e9) {
        fmu_log(&model->host, FMU_ERROR, "%s: step rejected: h=%g s would take %.3g internal steps of at most "
                "max_internal_step=%g s (allowed up to 1e9)", function, h, steps,
                model->parameters[P_MAX_INTERNAL_STEP]);
        return FMU_DISCARD;
    }
    if (h > 0.0) {
        double y[N_Y];
        memcpy(y, model->y, sizeof y);
        int32_t status = 0;
        slider_crank_step(&status, NULL, t, h, (int64_t)steps, model->parameters[P_LOAD_COUPLING] == 1.0, model->y,
                          model->mp, model->inputs, model->jac, model->schur, model->phi, model->phi_dot, model->gamma,
                          model->minv, model->force, model->dy, model->stages, model->linearisation, model->loads);
        for (int k = 0; k < N_Y; k++)
            if (!isfinite(model->y[k])) {
                memcpy(model->y, y, sizeof y);
                model->derivatives_stale = 1;
                fmu_log(&model->host, FMU_ERROR, "%s: step from t=%.17g s over h=%g s rejected: the state became "
                        "non-finite (%s)", function, t, h, STATE_NAMES[k]);
                return FMU_DISCARD;
            }
    }
    model->time = t + h;
    model->derivatives_stale = h > 0.0 ? 0 : 1;
    return FMU_OK;
}

/* ------------------------------------------------------------------ Model Exchange */
int model_set_time(FmuModel *model, double time, const char *function)
{
    if (!isfinite(time)) {
        fmu_log(&model->host, FMU_ERROR, "%s: time=%g is not finite", function, time);
        return 0;
    }
    model->time = time;
    model->derivatives_stale = 1;
    return 1;
}

int model_get_continuous_states(FmuModel *model, double *x, const char *function)
{
    if (!prepare(model, function))
        return 0;
    memcpy(x, model->y, sizeof model->y);
    return 1;
}

int model_set_continuous_states(FmuModel *model, const double *x, const char *function)
{
    if (!prepare(model, function))
        return 0;
    memcpy(model->y, x, sizeof model->y);
    model->derivatives_stale = 1;
    return 1;
}

int model_get_derivatives(FmuModel *model, double *dx, const char *function)
{
    if (!derivatives(model, function))
        return 0;
    memcpy(dx, model->dy, sizeof model->dy);
    return 1;
}

int model_get_event_indicators(FmuModel *model, double *z, const char *function)
{
    (void)model, (void)z, (void)function;
    return 1;
}

int model_event_update(FmuModel *model, const char *function)
{
    (void)model, (void)function;
    return 1;
}

int model_completed_integrator_step(FmuModel *model, const char *function)
{
    (void)model, (void)function;
    return FMU_OK;
}

/* ------------------------------------------------------------------ FMU state */
/* The project's one state format (wearjoint/core/state_format.py, its kernels compiled into this
 * binary): little-endian, versioned header, CRC-32C; a SliderCrank state's head is the time, the
 * initialised flag, the inputs, the parameters and y; it has no contact memory (written as zeros)
 * and no bushing points.  In memory a state is its head. */
enum { HEAD_TIME, HEAD_INITIALISED, HEAD_INPUTS, HEAD_PARAMETERS = HEAD_INPUTS + N_INPUTS,
       HEAD_Y = HEAD_PARAMETERS + N_PARAMETERS, HEAD_END = HEAD_Y + N_Y };
_Static_assert(HEAD_END == STATE_N_HEAD, "the state head's layout and STATE_N_HEAD (fmu/slider_crank.py) disagree");
static const double NO_MEMORY[STATE_N_MEMORY] = {0.0};

size_t model_state_size(const FmuModel *model)
{
    (void)model;
    return STATE_N_HEAD * sizeof(double);
}

void model_get_state(const FmuModel *model, double *head, int initialised)
{
    head[HEAD_TIME] = model->time;
    head[HEAD_INITIALISED] = initialised ? 1.0 : 0.0;
    memcpy(head + HEAD_INPUTS, model->inputs, sizeof model->inputs);
    memcpy(head + HEAD_PARAMETERS, model->parameters, sizeof model->parameters);
    memcpy(head + HEAD_Y, model->y, sizeof model->y);
}

int model_set_state(FmuModel *model, const double *head, int *initialised, const char *function)
{
    model->time = head[HEAD_TIME];
    *initialised = head[HEAD_INITIALISED] == 1.0;
    memcpy(model->inputs, head + HEAD_INPUTS, sizeof model->inputs);
    memcpy(model->parameters, head + HEAD_PARAMETERS, sizeof model->parameters);
    memcpy(model->y, head + HEAD_Y, sizeof model->y);
    model->parameters_changed = model->derivatives_stale = 1;
    model->state_stale = !*initialised;
    return prepare(model, function);
}

size_t model_serialized_state_size(const FmuModel *model, const double *head)
{
    (void)model, (void)head;
    int64_t size = 0;
    wearjoint_state_size(&size, NULL, STATE_N_HEAD, 0);
    return (size_t)size;
}

void model_serialize_state(const FmuModel *model, const double *head, unsigned char *bytes)
{
    int32_t status = 0;
    wearjoint_write_state(&status, NULL, bytes, (int64_t)model_serialized_state_size(model, head),
                          STATE_CONTENTS_MECHANISM, head, STATE_N_HEAD, NO_MEMORY, NO_MEMORY, 0);
}

int model_deserialize_state(FmuModel *model, const unsigned char *bytes, size_t size, double *head,
                            const char *function)
{
    double values[4] = {0.0, 0.0, 0.0, 0.0}, memory[STATE_N_MEMORY];
    int32_t problem = 0, status = 0;
    wearjoint_check_header(&problem, NULL, bytes, (int64_t)size, STATE_CONTENTS_MECHANISM, STATE_N_HEAD, 0, values);
    if (problem == 0) {
        wearjoint_read_state(&status, NULL, bytes, (int64_t)size, head, STATE_N_HEAD, memory, memory, 0);
        wearjoint_check_values(&problem, NULL, head, STATE_N_HEAD, memory, memory, 0, 0.0, 0.0, values);
    }
    if (problem != 0) {
        char message[512];
        fmu_log(&model->host, FMU_ERROR, "%s: %s", function, fmu_state_problem(STATE_PROBLEMS[problem],
                STATE_PROBLEM_KINDS[problem], values, message, sizeof message));
        return 0;
    }
    if (!fmu_parameters_valid(&model->host, PARAMETERS, N_PARAMETERS, head + HEAD_PARAMETERS, function))
        return 0;
    for (int k = 0; k < N_Y; k++)
        if (!isfinite(head[HEAD_Y + k])) {
            fmu_log(&model->host, FMU_ERROR, "%s: the state's coordinates and velocities must be finite (%s=%g)",
                    function, STATE_NAMES[k], head[HEAD_Y + k]);
            return 0;
        }
    return 1;
}
