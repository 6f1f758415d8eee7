/* One clearance/wear joint as an FMU instance holds it (see joint_instance.h). */
#include "joint_instance.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "joint_kernels.h"

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "the kernels write the state's float64 values in the machine's byte order: little-endian only"
#endif

static int kernel_ok(const JointInstance *joint, const char *kernel, int32_t status)
{
    if (status == 0)
        return 1;
    fmu_log(&joint->host, JOINT_ERROR, "%s", kernel);
    return 0;
}

static void describe_non_finite_inputs(const JointInstance *joint, char *out, size_t size)
{
    size_t used = 0;
    out[0] = '\0';
    for (int i = 0; i < N_INPUTS && used < size; i++)
        if (joint->non_finite_inputs & (1u << i)) {
            int n = snprintf(out + used, size - used, "%s%s=%g", used ? ", " : "", INPUT_NAMES[i], joint->inputs[i]);
            if (n < 0)
                break;
            used += (size_t)n;
        }
}

/* ------------------------------------------------------------------ lifetime */
static int allocate_arrays(JointInstance *joint, int64_t n_points)
{
    int64_t n_blocks = (n_points + BLOCK_SIZE - 1) / BLOCK_SIZE;
    double *arrays = joint->host.allocate(joint->host.environment, (size_t)(7 * n_points + n_blocks), sizeof(double));
    unsigned char *mask = joint->host.allocate(joint->host.environment, (size_t)n_points, 1);
    if (arrays == NULL || mask == NULL) {
        if (arrays != NULL)
            joint->host.release(joint->host.environment, arrays);
        if (mask != NULL)
            joint->host.release(joint->host.environment, mask);
        joint_log(joint, JOINT_ERROR, "out of memory for %lld bushing points", (long long)n_points);
        return 0;
    }
    if (joint->phi != NULL)
        joint->host.release(joint->host.environment, joint->phi);
    if (joint->mask != NULL)
        joint->host.release(joint->host.environment, joint->mask);
    joint->n_points = n_points;
    joint->n_blocks = n_blocks;
    joint->phi = arrays;
    joint->cos_phi = arrays + n_points;
    joint->sin_phi = arrays + 2 * n_points;
    joint->wear_depth = arrays + 3 * n_points;
    joint->work = arrays + 4 * n_points;
    joint->block_min = arrays + 6 * n_points;     /* work: 2 n_points */
    joint->mask = mask;
    int32_t status = 0;
    wearjoint_bushing_points(&status, NULL, joint->phi, joint->cos_phi, joint->sin_phi, n_points);
    return 1;
}

JointInstance *joint_new(const char *name, int64_t n_points, int logging_on, FmuLogFunction *log,
                         FmuAllocateFunction *allocate, FmuReleaseFunction *release, void *environment)
{
    JointInstance *joint = fmu_new_instance(sizeof *joint, name, logging_on, log, allocate, release, environment);
    if (joint == NULL)
        return NULL;
    if (!allocate_arrays(joint, n_points)) {
        joint_free(joint);
        return NULL;
    }
    joint_reset(joint);
    return joint;
}

void joint_free(JointInstance *joint)
{
    if (joint == NULL)
        return;
    if (joint->phi != NULL)
        joint->host.release(joint->host.environment, joint->phi);
    if (joint->mask != NULL)
        joint->host.release(joint->host.environment, joint->mask);
    fmu_free_instance(joint);
}

int joint_resize(JointInstance *joint, int64_t n_points)
{
    if (n_points != joint->n_points && !allocate_arrays(joint, n_points))
        return 0;
    joint_reset(joint);
    return 1;
}

void joint_reset(JointInstance *joint)
{
    joint->time = joint->last_accepted_time = 0.0;
    memset(joint->inputs, 0, sizeof joint->inputs);
    joint->non_finite_inputs = 0;
    for (int i = 0; i < N_PARAMETERS; i++)
        joint->parameters[i] = PARAMETERS[i].start;
    joint->parameters_changed = 1;
    joint->forces_stale = joint->wear_summary_stale = joint->jacobian_stale = 1;
    joint->onsets_accepted = joint->warned_wear_step = joint->started = 0;
    memset(joint->memory, 0, sizeof joint->memory);
    joint->memory[M_START_FORCE] = NO_START_FORCE;
    memset(joint->result, 0, sizeof joint->result);
    memset(joint->wear_depth, 0, (size_t)joint->n_points * sizeof(double));
    memset(joint->block_min, 0, (size_t)joint->n_blocks * sizeof(double));
}

/* ------------------------------------------------------------------ inputs and parameters */
void joint_set_input(JointInstance *joint, int index, double value)
{
    if (!(value == joint->inputs[index]))
        joint->onsets_accepted = 0;
    joint->inputs[index] = value;
    if (isfinite(value))
        joint->non_finite_inputs &= ~(1u << index);
    else
        joint->non_finite_inputs |= 1u << index;
    joint->forces_stale = 1;
}

void joint_set_parameter(JointInstance *joint, int index, double value)
{
    joint->parameters[index] = value;
    joint->parameters_changed = 1;
}

/* 1 if every parameter is allowed; else logs the first that is not (name, value, allowed range). */
static int parameters_valid(const JointInstance *joint, const double *values, const char *when)
{
    return fmu_parameters_valid(&joint->host, PARAMETERS, N_PARAMETERS, values, when);
}

int joint_pack_parameters(JointInstance *joint, const char *when)
{
    if (!joint->parameters_changed)
        return 1;
    if (!parameters_valid(joint, joint->parameters, when))
        return 0;
    memset(joint->joint_parameters, 0, sizeof joint->joint_parameters);
    for (int i = 0; i < N_PARAMETERS; i++)
        joint->joint_parameters[PARAMETERS[i].slot] = joint->parameters[i];
    int32_t status = 0;
    if (!kernel_ok(joint, "wearjoint_complete_parameters failed",
                   wearjoint_complete_parameters(&status, NULL, joint->joint_parameters)))
        return 0;
    joint->parameters_changed = 0;
    joint->forces_stale = joint->wear_summary_stale = 1;
    return 1;
}

/* ------------------------------------------------------------------ the kernels */
/* 1 if the n values per result slot of ``values`` (the result: 1, the jacobian: N_INPUTS) are finite for every
 * output read from the result; else logs the first that is not. */
static int outputs_finite(const JointInstance *joint, const double *values, int n, const char *what,
                          const char *function, const char *output)
{
    double probe = 0.0;   /* 0 unless a value is infinite or NaN: then look for the output that is */
    for (int i = 0; i < N_RESULT * n; i++)
        probe += values[i] * 0.0;
    if (probe == 0.0)
        return 1;
    for (int i = 0; i < N_SCALAR_OUTPUTS; i++) {   /* finite inputs so large that the geometry overflows */
        for (int m = 0; m < n && OUTPUTS[i].source == OUTPUT_FROM_RESULT; m++) {
            double value = values[OUTPUTS[i].index * n + m];
            if (isfinite(value))
                continue;
            double largest = 0.0;
            for (int k = 0; k < N_INPUTS; k++)
                largest = fabs(joint->inputs[k]) > largest ? fabs(joint->inputs[k]) : largest;
            joint_log(joint, JOINT_ERROR, "%s of %s: %s %s=%g is not finite for inputs up to |%g|: allowed "
                      "inputs whose contact geometry stays finite", function, output, what, OUTPUTS[i].name, value,
                      largest);
            return 0;
        }
    }
    return 1;
}

int joint_evaluate(JointInstance *joint, const char *function, const char *output)
{
    if (!joint->forces_stale && !joint->parameters_changed)
        return 1;
    if (!joint_pack_parameters(joint, function))
        return 0;
    if (!joint->forces_stale)
        return 1;
    if (joint->non_finite_inputs) {
        char inputs[512];
        describe_non_finite_inputs(joint, inputs, sizeof inputs);
        joint_log(joint, JOINT_ERROR, "%s of %s: undefined for non-finite inputs (%s)", function, output, inputs);
        return 0;
    }
    int32_t status = 0;
    if (!kernel_ok(joint, "wearjoint_evaluate failed",
                   wearjoint_evaluate(&status, NULL, joint->inputs, joint->joint_parameters, joint->cos_phi,
                                      joint->sin_phi, joint->wear_depth, joint->block_min, joint->memory,
                                      joint->result, joint->mask, joint->n_points, joint->n_blocks)))
        return 0;
    if (!outputs_finite(joint, joint->result, 1, "output", function, output))
        return 0;
    joint->forces_stale = 0;
    joint->jacobian_stale = 1;
    return 1;
}

/* The derivatives at the evaluation in result (the same kernels, the same evaluation written to scratch). */
int joint_jacobian(JointInstance *joint, const char *function, const char *output)
{
    if (!joint_evaluate(joint, function, output))
        return 0;
    if (!joint->jacobian_stale)
        return 1;
    double result[N_RESULT];
    memcpy(result, joint->result, sizeof result);   /* its deepest point seeds the search */
    int32_t status = 0;
    if (!kernel_ok(joint, "wearjoint_jacobian failed",
                   wearjoint_jacobian(&status, NULL, joint->inputs, joint->joint_parameters, joint->cos_phi,
                                      joint->sin_phi, joint->wear_depth, joint->block_min, joint->memory, result,
                                      joint->jacobian, joint->n_points, joint->n_blocks)))
        return 0;
    if (!outputs_finite(joint, joint->jacobian, N_INPUTS, "the derivative of output", function, output))
        return 0;
    joint->jacobian_stale = 0;
    return 1;
}

int joint_wear_summary(JointInstance *joint, const char *function)
{
    if (!joint_pack_parameters(joint, function))
        return 0;
    if (!joint->wear_summary_stale)
        return 1;
    double largest = joint->wear_depth[0];
    for (int64_t k = 1; k < joint->n_points; k++)
        largest = joint->wear_depth[k] > largest ? joint->wear_depth[k] : largest;
    double volume = 0.0;
    if (!kernel_ok(joint, "wearjoint_worn_volume failed",
                   wearjoint_worn_volume(&volume, NULL, joint->joint_parameters, joint->wear_depth, joint->n_points)))
        return 0;
    joint->max_wear_depth = largest;
    joint->worn_volume = volume;
    joint->wear_summary_stale = 0;
    return 1;
}

/* The warnings of an accepted step (joint_instance.h), from the kernels' result at its start. */
static int step_warnings(JointInstance *joint, double dt, int32_t changed, const char *function)
{
    int status = JOINT_OK;
    const double *p = joint->joint_parameters;
    if (!joint->started) {
        joint->started = 1;
        double e = hypot(joint->result[R_ECCENTRICITY_X], joint->result[R_ECCENTRICITY_Y]);
        double radius = p[P_BUSHING_RADIUS];
        if (e > radius) {
            joint_log(joint, JOINT_WARNING, "%s: at t=%.17g s the inputs put the pin centre %g m from the bushing "
                      "centre, outside the bushing (radius %g m): the contact force is meaningless.  The inputs are "
                      "the bodies' reference points; are the offsets set (pin_offset_x=%g, pin_offset_y=%g, "
                      "bushing_offset_x=%g, bushing_offset_y=%g m, each in its body's frame)?", function, joint->time,
                      e, radius, p[P_PIN_OFFSET_X], p[P_PIN_OFFSET_Y], p[P_BUSHING_OFFSET_X],
                      p[P_BUSHING_OFFSET_Y]);
            status = JOINT_WARNING;
        }
    }
    if (changed == STEP_OVERSHOT && !joint->warned_wear_step) {
        joint->warned_wear_step = 1;
        joint_log(joint, JOINT_WARNING, "%s: at t=%.17g s a wearing step of %g s is over the wear-step limit (at most "
                  "%g s, and a share k_f k_w v dt of at most %g of a conforming contact's penetration, %g with the "
                  "explicit wear placements): the step no longer resolves the wear; take shorter steps or a smaller "
                  "wear_factor (docs/model.md §7; said once)", function, joint->time, dt, MAX_WEAR_STEP_S,
                  WEAR_STEP_SHARE, WEAR_STEP_SHARE_EXPLICIT);
        /* logged as a warning, returned fmi2OK: some masters (OMSimulator) end the run on a warning status */
    }
    return status;
}

int joint_accept_step(JointInstance *joint, double dt, int held, const char *function)
{
    if (joint->non_finite_inputs) {
        char inputs[512];
        describe_non_finite_inputs(joint, inputs, sizeof inputs);
        joint_log(joint, JOINT_ERROR, "%s: step at t=%.17g s rejected: non-finite inputs (%s)", function, joint->time,
                  inputs);
        return JOINT_DISCARD;
    }
    if (!(dt >= 0.0 && isfinite(dt))) {
        joint_log(joint, JOINT_ERROR, "%s: step rejected: step size %g s is not a finite value >= 0", function, dt);
        return JOINT_DISCARD;
    }
    if (!joint_pack_parameters(joint, function))
        return JOINT_ERROR;
    /* the forces read since the inputs changed are the evaluation the step accepts: no second one */
    int32_t changed = 0;
    int32_t status = joint->forces_stale
                         ? wearjoint_advance(&changed, NULL, joint->inputs, joint->joint_parameters, joint->cos_phi,
                                             joint->sin_phi, joint->wear_depth, joint->block_min, joint->memory,
                                             joint->result, joint->mask, joint->work, joint->n_points,
                                             joint->n_blocks, dt, held)
                         : wearjoint_accept(&changed, NULL, joint->inputs, joint->joint_parameters, joint->cos_phi,
                                            joint->sin_phi, joint->wear_depth, joint->block_min, joint->memory,
                                            joint->result, joint->mask, joint->work, joint->n_points,
                                            joint->n_blocks, dt, held);
    if (!kernel_ok(joint, "wearjoint_advance failed", status))
        return JOINT_ERROR;
    if (changed < 0) {   /* the kernels refused the step's wear (absurd or not finite): nothing changed */
        joint_log(joint, JOINT_ERROR, "%s: step rejected: a step of %g s wears the bushing by more than its radius "
                  "%g m (or by a non-finite depth)", function, dt, joint->parameters[STATE_PARAMETER_BUSHING_RADIUS]);
        return JOINT_DISCARD;
    }
    if (changed)
        joint->wear_summary_stale = 1;
    joint->forces_stale = 1;
    joint->onsets_accepted = 1;
    return step_warnings(joint, dt, changed, function);
}

int joint_completed_integrator_step(JointInstance *joint, const char *function)
{
    int status = joint_accept_step(joint, joint->time - joint->last_accepted_time, 0, function);
    if (status <= JOINT_WARNING)
        joint->last_accepted_time = joint->time;
    return status;
}

int joint_set_time(JointInstance *joint, double time, const char *function)
{
    if (!isfinite(time)) {
        joint_log(joint, JOINT_ERROR, "%s: time=%g is not finite", function, time);
        return 0;
    }
    joint->time = time;
    return 1;
}

int joint_event_indicator(JointInstance *joint, const char *function, double *value)
{
    if (!joint_evaluate(joint, function, "the event indicator"))
        return 0;
    *value = joint->result[R_PENETRATION];
    return 1;
}

int joint_update_contact_memory(JointInstance *joint, const char *function)
{
    if (joint->onsets_accepted)
        return 1;
    if (!joint_evaluate(joint, function, "the event indicator"))
        return 0;
    int32_t changed = 0;
    if (!kernel_ok(joint, "wearjoint_update_contact_memory failed",
                   wearjoint_update_contact_memory(&changed, NULL, joint->result, joint->joint_parameters,
                                                   joint->memory)))
        return 0;
    if (changed)
        joint->forces_stale = 1;
    return 1;
}

/* ------------------------------------------------------------------ FMU state */
/* The head: time, initialised flag, inputs, parameters (core/state_format.py FMU_HEAD_*).  In memory a state
 * is n_points, the head, the contact memory, the wear depths and their block minima. */
enum { HEAD_TIME, HEAD_INITIALISED, HEAD_INPUTS, HEAD_PARAMETERS = HEAD_INPUTS + N_INPUTS };
enum { AT_N_POINTS, AT_HEAD, AT_MEMORY = AT_HEAD + STATE_N_HEAD, AT_WEAR = AT_MEMORY + N_MEMORY };

size_t joint_state_size(const JointInstance *joint)
{
    return (size_t)(AT_WEAR + joint->n_points + joint->n_blocks) * sizeof(double);
}

void joint_get_state(const JointInstance *joint, double *state, int initialised)
{
    double *head = state + AT_HEAD;
    state[AT_N_POINTS] = (double)joint->n_points;
    head[HEAD_TIME] = joint->time;
    head[HEAD_INITIALISED] = initialised ? 1.0 : 0.0;
    memcpy(head + HEAD_INPUTS, joint->inputs, sizeof joint->inputs);
    memcpy(head + HEAD_PARAMETERS, joint->parameters, sizeof joint->parameters);
    memcpy(state + AT_MEMORY, joint->memory, sizeof joint->memory);
    memcpy(state + AT_WEAR, joint->wear_depth, (size_t)joint->n_points * sizeof(double));
    memcpy(state + AT_WEAR + joint->n_points, joint->block_min, (size_t)joint->n_blocks * sizeof(double));
}

int joint_set_state(JointInstance *joint, const double *state, int *initialised, const char *function)
{
    const double *head = state + AT_HEAD;
    joint->time = joint->last_accepted_time = head[HEAD_TIME];
    *initialised = head[HEAD_INITIALISED] == 1.0;
    for (int i = 0; i < N_INPUTS; i++)
        joint_set_input(joint, i, head[HEAD_INPUTS + i]);
    if (memcmp(joint->parameters, head + HEAD_PARAMETERS, sizeof joint->parameters) != 0) {
        memcpy(joint->parameters, head + HEAD_PARAMETERS, sizeof joint->parameters);
        joint->parameters_changed = 1;
    }
    memcpy(joint->memory, state + AT_MEMORY, sizeof joint->memory);
    memcpy(joint->wear_depth, state + AT_WEAR, (size_t)joint->n_points * sizeof(double));
    memcpy(joint->block_min, state + AT_WEAR + joint->n_points, (size_t)joint->n_blocks * sizeof(double));
    joint->forces_stale = joint->wear_summary_stale = 1;
    joint->onsets_accepted = 0;
    return joint_pack_parameters(joint, function);
}

size_t joint_serialized_state_size(const double *state)
{
    int64_t size = 0;
    wearjoint_state_size(&size, NULL, STATE_N_HEAD, (int64_t)state[AT_N_POINTS]);
    return (size_t)size;
}

void joint_serialize_state(const double *state, void *bytes)
{
    int32_t status = 0;
    wearjoint_write_state(&status, NULL, bytes, (int64_t)joint_serialized_state_size(state), STATE_CONTENTS_FMU,
                          state + AT_HEAD, STATE_N_HEAD, state + AT_MEMORY, state + AT_WEAR,
                          (int64_t)state[AT_N_POINTS]);
}

/* Log a problem a state check found (its message from the generated table, with the values compared). */
static void log_state_problem(const JointInstance *joint, const char *function, int32_t problem, const double *values)
{
    char message[512];
    joint_log(joint, JOINT_ERROR, "%s: %s", function, fmu_state_problem(STATE_PROBLEMS[problem],
              STATE_PROBLEM_KINDS[problem], values, message, sizeof message));
}

int joint_deserialize_state(const JointInstance *joint, const void *bytes, size_t size, double *state,
                            const char *function)
{
    double values[4] = {0.0, 0.0, 0.0, 0.0}, *head = state + AT_HEAD, *wear = state + AT_WEAR;
    int32_t problem = 0, status = 0;
    wearjoint_check_header(&problem, NULL, bytes, (int64_t)size, STATE_CONTENTS_FMU, STATE_N_HEAD, joint->n_points,
                           values);
    if (problem == 0) {
        wearjoint_read_state(&status, NULL, bytes, (int64_t)size, head, STATE_N_HEAD, state + AT_MEMORY, wear,
                             joint->n_points);
        if (!parameters_valid(joint, head + HEAD_PARAMETERS, function))
            return 0;
        wearjoint_check_values(&problem, NULL, head, STATE_N_HEAD, state + AT_MEMORY, wear, joint->n_points,
                               head[HEAD_PARAMETERS + STATE_PARAMETER_BUSHING_RADIUS],
                               head[HEAD_PARAMETERS + STATE_PARAMETER_VELOCITY_FLOOR], values);
    }
    if (problem != 0) {
        log_state_problem(joint, function, problem, values);
        return 0;
    }
    state[AT_N_POINTS] = (double)joint->n_points;
    wearjoint_block_minima(&status, NULL, wear, wear + joint->n_points, joint->n_points, joint->n_blocks);
    return 1;
}
