/* The data of ClearanceWearJoint's instances (struct FmuModel of fmu_model.h), private to the model's three
 * files: joint_model.c (memory, lifetime, Configuration Mode, parameters, the kernels: evaluation, steps,
 * Model Exchange), joint_variables.c (the variables by value reference) and joint_state.c (the FMU state).
 * Statuses are fmu_model.h's FMU_* (numbered as fmi2Status and fmi3Status, 0 ok .. 4 fatal).
 */
#ifndef WEARJOINT_JOINT_MODEL_H
#define WEARJOINT_JOINT_MODEL_H

#include <stdint.h>

#include "fmu_model.h"
#include "model_variables.h"

struct FmuModel {
    FmuHost host;                      /* first: logger, memory, instance name (fmu_new_instance) */
    double time;
    double last_accepted_time;         /* Model Exchange: end of the last completed integrator step */
    double inputs[N_INPUTS];
    uint32_t non_finite_inputs;        /* bit i: input i is not finite */
    double parameters[N_PARAMETERS];   /* FMU parameter values (choices as their index) */
    int parameters_changed;            /* since the joint parameter vector was packed */
    int forces_stale;                  /* result does not belong to the current inputs */
    int jacobian_stale;                /* jacobian does not belong to result */
    int jacobian_unchecked;            /* jacobian was not checked for non-finite values (joint_jacobian does) */
    int jacobian_read;                 /* the host read derivatives of this evaluation: the next evaluation takes the
                                          forces and their derivatives in one pass of the kernels */
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
    uint64_t configured_n_points;      /* FMI 3.0 Configuration Mode: the value set for n_points */
};

/* joint_model.c's, for the other two files.  Re-size the bushing to n_points (>= 8) and restore the defaults;
 * 0 (logged) on failure. */
int joint_resize(FmuModel *model, int64_t n_points);
void joint_set_input(FmuModel *model, int index, double value);
void joint_set_parameter(FmuModel *model, int index, double value);
/* Check the parameters (the first bad one is logged, naming it) and pack the kernels' vector. */
int joint_pack_parameters(FmuModel *model, const char *when);
/* The joint's outputs (result) for the current inputs; ``output`` names what was asked for. */
int joint_evaluate(FmuModel *model, const char *function, const char *output);
/* joint_evaluate and the exact derivatives of result with respect to the inputs (jacobian). */
int joint_jacobian(FmuModel *model, const char *function, const char *output);
/* max_wear_depth and worn_volume for the current wear depths. */
int joint_wear_summary(FmuModel *model, const char *function);

/* joint_variables.c's, for the other two files: the inputs that are not finite, as name=value, into out. */
void describe_non_finite_inputs(const FmuModel *model, char *out, size_t size);

#endif
