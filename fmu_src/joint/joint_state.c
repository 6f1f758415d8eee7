/* ClearanceWearJoint's FMU state (fmu_model.h, "FMU state"; the joint's data: joint_model.h) and its size, the
 * bushing's points (FMI 3.0 Configuration Mode).  In memory the joint's values copied as they are (n_points, time,
 * initialised flag, inputs, parameters, contact memory, wear depths, block minima); serialised the state format of
 * wearjoint/core/state_format.py (header, CRC-32C), contents "FMU instance", written and checked by kernels
 * (state_format.h).
 */
#include <string.h>

#include "joint_model.h"
#include "joint_kernels.h"

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "the kernels write the state's float64 values in the machine's byte order: little-endian only"
#endif

/* The head: time, initialised flag, inputs, parameters (core/state_format.py FMU_HEAD_*), then what the host's
 * calls left that the next step depends on: it read the loads' derivatives (a linearising host), an accepted
 * step did the onset bookkeeping at these inputs.  In memory a state is n_points, the head, the contact memory,
 * the wear depths and their block minima. */
enum { HEAD_TIME, HEAD_INITIALISED, HEAD_INPUTS, HEAD_PARAMETERS = HEAD_INPUTS + N_INPUTS,
       HEAD_DERIVATIVES_READ = HEAD_PARAMETERS + N_PARAMETERS, HEAD_ONSETS_ACCEPTED, HEAD_END };
_Static_assert(HEAD_END == STATE_N_HEAD, "the state head's layout and STATE_N_HEAD (fmu/variables.py) disagree");
enum { AT_N_POINTS, AT_HEAD, AT_MEMORY = AT_HEAD + STATE_N_HEAD, AT_WEAR = AT_MEMORY + N_MEMORY };

size_t model_state_size(const FmuModel *model)
{
    return (size_t)(AT_WEAR + model->n_points + model->n_blocks) * sizeof(double);
}

void model_get_state(const FmuModel *model, double *state, int initialised)
{
    double *head = state + AT_HEAD;
    state[AT_N_POINTS] = (double)model->n_points;
    head[HEAD_TIME] = model->time;
    head[HEAD_INITIALISED] = initialised ? 1.0 : 0.0;
    memcpy(head + HEAD_INPUTS, model->inputs, sizeof model->inputs);
    memcpy(head + HEAD_PARAMETERS, model->parameters, sizeof model->parameters);
    head[HEAD_DERIVATIVES_READ] = model->jacobian_read ? 1.0 : 0.0;
    head[HEAD_ONSETS_ACCEPTED] = model->onsets_accepted ? 1.0 : 0.0;
    memcpy(state + AT_MEMORY, model->memory, sizeof model->memory);
    memcpy(state + AT_WEAR, model->wear_depth, (size_t)model->n_points * sizeof(double));
    memcpy(state + AT_WEAR + model->n_points, model->block_min, (size_t)model->n_blocks * sizeof(double));
}

/* Restore a state of model_get_state; *initialised is its flag.  0 (logged) on failure. */
int model_set_state(FmuModel *model, const double *state, int *initialised, const char *function)
{
    const double *head = state + AT_HEAD;
    model->time = model->last_accepted_time = head[HEAD_TIME];
    *initialised = head[HEAD_INITIALISED] == 1.0;
    for (int i = 0; i < N_INPUTS; i++)
        joint_set_input(model, i, head[HEAD_INPUTS + i]);
    if (memcmp(model->parameters, head + HEAD_PARAMETERS, sizeof model->parameters) != 0) {
        memcpy(model->parameters, head + HEAD_PARAMETERS, sizeof model->parameters);
        model->parameters_changed = 1;
    }
    memcpy(model->memory, state + AT_MEMORY, sizeof model->memory);
    memcpy(model->wear_depth, state + AT_WEAR, (size_t)model->n_points * sizeof(double));
    memcpy(model->block_min, state + AT_WEAR + model->n_points, (size_t)model->n_blocks * sizeof(double));
    model->forces_stale = model->wear_summary_stale = 1;
    model->jacobian_read = head[HEAD_DERIVATIVES_READ] != 0.0;
    model->onsets_accepted = head[HEAD_ONSETS_ACCEPTED] != 0.0;   /* after the inputs: setting them clears it */
    return joint_pack_parameters(model, function);
}

size_t model_serialized_state_size(const FmuModel *model, const double *state)
{
    (void)model;
    int64_t size = 0;
    wearjoint_state_size(&size, NULL, STATE_N_HEAD, (int64_t)state[AT_N_POINTS]);
    return (size_t)size;
}

void model_serialize_state(const FmuModel *model, const double *state, unsigned char *bytes)
{
    int32_t status = 0;
    wearjoint_write_state(&status, NULL, bytes, (int64_t)model_serialized_state_size(model, state),
                          STATE_CONTENTS_FMU, state + AT_HEAD, STATE_N_HEAD, state + AT_MEMORY, state + AT_WEAR,
                          (int64_t)state[AT_N_POINTS]);
}

/* Log a problem a state check found (its message from the generated table, with the values compared). */
static void log_state_problem(const FmuModel *model, const char *function, int32_t problem, const double *values)
{
    char message[512];
    fmu_log(&model->host, FMU_ERROR, "%s: %s", function, fmu_state_problem(STATE_PROBLEMS[problem],
            STATE_PROBLEM_KINDS[problem], values, message, sizeof message));
}

/* 1 if ``bytes`` is a valid serialised state of this joint (header, checksum, parameters, value ranges; the
 * first problem logged otherwise), written into ``state``; the joint is unchanged either way. */
int model_deserialize_state(FmuModel *model, const unsigned char *bytes, size_t size, double *state,
                            const char *function)
{
    double values[4] = {0.0, 0.0, 0.0, 0.0}, *head = state + AT_HEAD, *wear = state + AT_WEAR;
    int32_t problem = 0, status = 0;
    wearjoint_check_header(&problem, NULL, bytes, (int64_t)size, STATE_CONTENTS_FMU, STATE_N_HEAD, model->n_points,
                           values);
    if (problem == 0) {
        wearjoint_read_state(&status, NULL, bytes, (int64_t)size, head, STATE_N_HEAD, state + AT_MEMORY, wear,
                             model->n_points);
        if (!fmu_parameters_valid(&model->host, PARAMETERS, N_PARAMETERS, head + HEAD_PARAMETERS, function))
            return 0;
        wearjoint_check_values(&problem, NULL, head, STATE_N_HEAD, state + AT_MEMORY, wear, model->n_points,
                               head[HEAD_PARAMETERS + STATE_PARAMETER_BUSHING_RADIUS],
                               head[HEAD_PARAMETERS + STATE_PARAMETER_VELOCITY_FLOOR], values);
    }
    if (problem != 0) {
        log_state_problem(model, function, problem, values);
        return 0;
    }
    state[AT_N_POINTS] = (double)model->n_points;
    wearjoint_block_minima(&status, NULL, wear, wear + model->n_points, model->n_points, model->n_blocks);
    return 1;
}

/* ------------------------------------------------------------------ FMI 3.0 Configuration Mode */
void model_enter_configuration(FmuModel *model) { model->configured_n_points = (uint64_t)model->n_points; }

/* Re-size the bushing to the n_points set; inputs, parameters and the time set before are kept. */
int model_exit_configuration(FmuModel *model)
{
    if ((int64_t)model->configured_n_points == model->n_points)
        return 1;
    double inputs[N_INPUTS], parameters[N_PARAMETERS];
    double time = model->time;
    memcpy(inputs, model->inputs, sizeof inputs);
    memcpy(parameters, model->parameters, sizeof parameters);
    if (!joint_resize(model, (int64_t)model->configured_n_points))
        return 0;   /* out of memory (logged): the old size stays */
    for (int i = 0; i < N_INPUTS; i++)
        joint_set_input(model, i, inputs[i]);
    for (int i = 0; i < N_PARAMETERS; i++)
        joint_set_parameter(model, i, parameters[i]);
    model->time = model->last_accepted_time = time;
    return 1;
}
