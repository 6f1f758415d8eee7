/* The slider-crank's kernels, compiled ahead of time from wearjoint's numba code (wearjoint/fmu/aot.py,
 * model slider-crank): the cfuncs of wearjoint/fmu/slider_crank_entry_points.py, with numba's calling
 * convention (int32 status, 0 = success; a pointer for the return value; one for exception
 * information, never written), then the arguments.  The physics lives only in wearjoint/core/
 * (core/slider_crank.py: Eqs. 38-44; integrators.py: RK4).  y = [q, q_dot] (18 values: crank, rod, slider,
 * each x, y, angle); inputs = the joint's (Fx, Fy, T) on its pin body, then on its bushing body, the load on
 * the slider (positive towards the crank's pivot), then the linearisation a joint FMU publishes (wearjoint/core/
 * layout.py, MECHANISM_INPUT_*); the workspace
 * is jac, schur (81 values each), phi, phi_dot, gamma, minv, force (9 each), all scratch but minv.
 */
#ifndef WEARJOINT_SLIDER_CRANK_KERNELS_H
#define WEARJOINT_SLIDER_CRANK_KERNELS_H

#include <stdint.h>

#include "state_format.h"

/* The kernels' parameter vector mp from the mechanism's parameters (rpm, degrees; the FMU's in their
 * order), and minv = M^-1 (Eq. 42).  Returns (through *problem) 0, or what is wrong with the slider-load
 * table: kind * LOAD_TABLE_ROW_BASE + row (nothing packed). */
int32_t slider_crank_parameters(int32_t *problem, void *excinfo, const double *fields, double *mp, double *minv);

/* The ideal mechanism's consistent state at time t into y (crank at theta0 - omega t, Eq. 39). */
int32_t slider_crank_initial_state(int32_t *status, void *excinfo, double t, const double *mp, double *jac,
                                   double *schur, double *phi, double *phi_dot, double *gamma, double *minv,
                                   double *force, double *y);

/* dy = dy/dt at (t, y) under the inputs (Eq. 44, crank-rod joint open); writes the slider's input load into mp. */
int32_t slider_crank_derivative(int32_t *status, void *excinfo, double t, const double *y, double *mp,
                                const double *inputs, double *jac, double *schur, double *phi, double *phi_dot,
                                double *gamma, double *minv, double *force, double *dy);

/* y advanced over [t, t + h] in n_steps RK4 steps, the joint's loads held at the inputs or, if linearised, F0 +
 * J (u - u0) of the linearisation the inputs carry (wearjoint/core/linearisation.py); dy = f at the end; stages:
 * 4 x 18, linearisation: N_LINEARISATION, loads: 6, scratch. */
int32_t slider_crank_step(int32_t *status, void *excinfo, double t, double h, int64_t n_steps, int64_t linearised,
                          double *y, double *mp, const double *inputs, double *jac, double *schur, double *phi,
                          double *phi_dot, double *gamma, double *minv, double *force, double *dy, double *stages,
                          double *linearisation, double *loads);

/* out = the clearance joint's kinematic inputs (x, y, angle, vx, vy, omega of its pin body, then of its
 * bushing body; the ground's zero) from y, for the joint named by mp (wearjoint/core/joint_location.py). */
int32_t slider_crank_joint_kinematics(int32_t *status, void *excinfo, const double *y, const double *mp, double *out);

#endif
