/* One clearance/wear joint as an FMU instance holds it, independent of the FMI version.
 *
 * The generic FMI layers (fmi2Functions.c, fmi3Functions.c) own the call sequence and
 * joint_model.c the value references (the model interface of fmu_model.h); this part owns the
 * joint's memory and data (inputs, parameters, the kernels' arrays), checks parameters against the
 * generated table, calls the compiled kernels (joint_kernels.h) and reads and writes the FMU state.  Statuses are numbered as fmi2Status and fmi3Status (0 ok .. 4 fatal).
 */
#ifndef WEARJOINT_JOINT_INSTANCE_H
#define WEARJOINT_JOINT_INSTANCE_H

#include <stddef.h>
#include <stdint.h>

#include "fmu_model.h"
#include "model_variables.h"

enum { JOINT_OK = FMU_OK, JOINT_WARNING = FMU_WARNING, JOINT_DISCARD = FMU_DISCARD, JOINT_ERROR = FMU_ERROR,
       JOINT_FATAL = FMU_FATAL };

typedef struct {
    FmuHost host;                      /* first: logger, memory, instance name (fmu_new_instance) */
    double time;
    double last_accepted_time;         /* Model Exchange: end of the last completed integrator step */
    double inputs[N_INPUTS];
    uint32_t non_finite_inputs;        /* bit i: input i is not finite */
    double parameters[N_PARAMETERS];   /* FMU parameter values (choices as their index) */
    int parameters_changed;            /* since the joint parameter vector was packed */
    int forces_stale;                  /* result does not belong to the current inputs */
    int jacobian_stale;                /* jacobian does not belong to result */
    int onsets_accepted;               /* an accepted step did the onset bookkeeping at these inputs */
    int wear_summary_stale;
    int warned_wear_step;              /* the wear-step warning was logged (once per instance) */
    int started;                       /* a step was accepted: the first one's pin position was checked */
    double max_wear_depth, worn_volume;
    int64_t n_points, n_blocks;
    double joint_parameters[N_JOINT_PARAMETERS];
    double memory[N_MEMORY];
    double result[N_RESULT];
    double jacobian[N_RESULT * N_INPUTS];   /* d result[r] / d inputs[m] at [N_INPUTS r + m] */
    double *phi, *cos_phi, *sin_phi, *wear_depth, *work, *block_min; /* one allocation */
    unsigned char *mask;               /* scratch of the wear update, like work */
} JointInstance;

/* A joint with n_points bushing points and default parameters; NULL (logged) without memory. */
JointInstance *joint_new(const char *name, int64_t n_points, int logging_on, FmuLogFunction *log,
                         FmuAllocateFunction *allocate, FmuReleaseFunction *release, void *environment);
void joint_free(JointInstance *joint);
/* Re-size the bushing to n_points (>= 8) and restore the defaults; 0 (logged) on failure. */
int joint_resize(JointInstance *joint, int64_t n_points);
/* Default inputs and parameters, an unworn bushing, no contact memory. */
void joint_reset(JointInstance *joint);

#define joint_log(joint, ...) fmu_log(&(joint)->host, __VA_ARGS__)

void joint_set_input(JointInstance *joint, int index, double value);
void joint_set_parameter(JointInstance *joint, int index, double value);
/* Check the parameters (the first bad one is logged, naming it) and pack the kernels' vector. */
int joint_pack_parameters(JointInstance *joint, const char *when);
/* The joint's outputs (result) for the current inputs; ``output`` names what was asked for. */
int joint_evaluate(JointInstance *joint, const char *function, const char *output);
/* joint_evaluate and the exact derivatives of result with respect to the inputs (jacobian). */
int joint_jacobian(JointInstance *joint, const char *function, const char *output);
int joint_wear_summary(JointInstance *joint, const char *function);
/* Accept a step of dt [s] at the current inputs: wear and contact-onset bookkeeping; held != 0: the inputs
 * were held over the step (Co-Simulation: the wear takes their force), else they end it (Model Exchange:
 * the step's mean force, docs/model.md §3.11).
 * JOINT_DISCARD (logged, state unchanged) for non-finite inputs or dt.  JOINT_WARNING (logged, the
 * step accepted), once per instance: the first step's pin centre lies outside the bushing (the inputs
 * likely lack the offsets).  A wearing step over the wear-step limit (docs/model.md §7) is logged as a
 * warning once per instance and returns JOINT_OK: the run goes on in every master. */
int joint_accept_step(JointInstance *joint, double dt, int held, const char *function);
/* Model Exchange: accept the step since the last completed one (wear, onsets); a JOINT_* status. */
int joint_completed_integrator_step(JointInstance *joint, const char *function);
/* Model Exchange: set the time (finite; 0, logged, otherwise). */
int joint_set_time(JointInstance *joint, double time, const char *function);
/* Model Exchange: the event indicator at the current inputs, the signed penetration of the
 * deepest bushing point (a contact onset is its zero crossing); 0 (logged) on failure. */
int joint_event_indicator(JointInstance *joint, const char *function, double *value);
/* The contact-onset bookkeeping alone at the current inputs (an event); nothing if an accepted
 * step at these inputs did it (from the contact before that step's wear, as in process). */
int joint_update_contact_memory(JointInstance *joint, const char *function);

/* FMU state (fmu_model.h): in memory the joint's values copied as they are (n_points, time, initialised flag,
 * inputs, parameters, contact memory, wear depths, block minima); serialised the state format of
 * wearjoint/core/state_format.py (header, CRC-32C), contents "FMU instance", written and checked by kernels. */
size_t joint_state_size(const JointInstance *joint);
void joint_get_state(const JointInstance *joint, double *state, int initialised);
/* Restore a state of joint_get_state; *initialised is its flag.  0 (logged) on failure. */
int joint_set_state(JointInstance *joint, const double *state, int *initialised, const char *function);
size_t joint_serialized_state_size(const double *state);
void joint_serialize_state(const double *state, void *bytes);
/* 1 if ``bytes`` is a valid serialised state of this joint (header, checksum, parameters, value ranges; the
 * first problem logged otherwise), written into ``state``; the joint is unchanged either way. */
int joint_deserialize_state(const JointInstance *joint, const void *bytes, size_t size, double *state,
                            const char *function);

#endif
