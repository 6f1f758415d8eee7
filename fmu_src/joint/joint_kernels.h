/* The joint's kernels, compiled ahead of time from wearjoint's numba code (wearjoint/fmu/aot.py).
 *
 * Each is the function behind a numba cfunc of wearjoint/fmu/joint_entry_points.py, with numba's
 * calling convention: int32 status (0 = success), a pointer for the return value, a pointer
 * for exception information (never written: the kernels have no path that raises), then the
 * arguments.  The physics lives only there (wearjoint/core/); joint_model.c and joint_variables.c
 * map FMI variables onto the kernels' arrays (layout: wearjoint/core/layout.py, mirrored in
 * the generated model_variables.h).
 */
#ifndef WEARJOINT_JOINT_KERNELS_H
#define WEARJOINT_JOINT_KERNELS_H

#include <stdint.h>

#include "state_format.h"

/* Forces for the kinematics (12 values: pin x, y, angle, vx, vy, omega, then the bushing's)
 * into result (Eqs. 1-23); the joint's state is unchanged. */
int32_t wearjoint_evaluate(int32_t *status, void *excinfo, const double *kinematics, const double *joint_parameters,
                           const double *cos_phi, const double *sin_phi, const double *wear_depth,
                           const double *block_min, const double *memory, double *result, void *mask,
                           int64_t n_points, int64_t n_blocks);

/* wearjoint_evaluate, and the exact derivatives of the result with respect to the 12 kinematic
 * inputs: jacobian[12 r + m] = d result[r] / d kinematics[m] (0 for the discrete contact flag and
 * deepest point); the joint's state is unchanged. */
int32_t wearjoint_jacobian(int32_t *status, void *excinfo, const double *kinematics, const double *joint_parameters,
                           const double *cos_phi, const double *sin_phi, const double *wear_depth,
                           const double *block_min, const double *memory, double *result, double *jacobian,
                           int64_t n_points, int64_t n_blocks);

/* Accept a step of dt [s] ending at the kinematics (held != 0: held over the step, a Co-Simulation step):
 * Archard wear with the step's mean normal force and contact-onset bookkeeping; *changed = 1 if the
 * joint's state changed.  mask (n_points bytes) and work (2 n_points doubles) are scratch. */
int32_t wearjoint_advance(int32_t *changed, void *excinfo, const double *kinematics, const double *joint_parameters,
                          const double *cos_phi, const double *sin_phi, double *wear_depth, double *block_min,
                          double *memory, double *result, void *mask, double *work, int64_t n_points,
                          int64_t n_blocks, double dt, int64_t held);

/* wearjoint_advance when result already holds the evaluation at these kinematics and this state:
 * the wear and onset update only; held == 2 (HELD_LINEARISED): held, and jacobian holds the derivatives at these
 * kinematics a linearising host read (the wear takes the linearised force's mean over the step). */
int32_t wearjoint_accept(int32_t *changed, void *excinfo, const double *kinematics, const double *joint_parameters,
                         const double *cos_phi, const double *sin_phi, double *wear_depth, double *block_min,
                         double *memory, double *result, const double *jacobian, void *mask, double *work,
                         int64_t n_points, int64_t n_blocks, double dt, int64_t held);

/* Contact-onset bookkeeping for the evaluation in result (a Model Exchange event): a new contact
 * stores its approach velocity, leaving contact clears it; *changed = 1 if the memory changed. */
int32_t wearjoint_update_contact_memory(int32_t *changed, void *excinfo, const double *result,
                                        const double *joint_parameters, double *memory);

/* Bushing point angles phi_z = z 2 pi / N_d (Eq. 3), their cosines and sines. */
int32_t wearjoint_bushing_points(int32_t *status, void *excinfo, double *phi, double *cos_phi, double *sin_phi,
                                 int64_t n_points);

/* The contact search's per-block minima of the wear depth (after the profile was replaced). */
int32_t wearjoint_block_minima(int32_t *status, void *excinfo, const double *wear_depth, double *block_min,
                               int64_t n_points, int64_t n_blocks);

/* Volume removed from the bushing: contact length times the worn area [m^3]. */
int32_t wearjoint_worn_volume(double *volume, void *excinfo, const double *joint_parameters, const double *wear_depth,
                              int64_t n_points);

/* out = [how far the pin of the evaluation ``result`` is in the bushing wall [m] along its eccentricity, the
 * admissible penetration [m], the admissible normal force [N]] (wearjoint/core/admissibility.py). */
int32_t wearjoint_wall_overlap(int32_t *status, void *excinfo, const double *result, const double *joint_parameters,
                               const double *wear_depth, int64_t n_points, double *out);

/* The derived slots of the joint parameter vector: E* (Eq. 32) and k_w times the wear factor. */
int32_t wearjoint_complete_parameters(int32_t *status, void *excinfo, double *joint_parameters);

#endif
