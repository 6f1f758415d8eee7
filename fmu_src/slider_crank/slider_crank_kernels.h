/* The slider-crank's kernels, compiled ahead of time from wearjoint's numba code (wearjoint/fmu/aot.py,
 * model slider-crank): the cfuncs of wearjoint/fmu/slider_crank_entry_points.py, with numba's calling
 * convention (int32 status, 0 = success; a pointer for the return value; one for exception
 * information, never written), then the arguments.  The physics lives only in wearjoint/core/
 * (mechanism.py: Eqs. 38-44; integrators.py: RK4).  y = [q, q_dot] (18 values: crank, rod, slider,
 * each x, y, angle); forces = the joint's (Fx, Fy, T) on the crank, then on the rod; the workspace
 * is jac, schur (81 values each), phi, phi_dot, gamma, minv, force (9 each), all scratch but minv.
 */
#ifndef WEARJOINT_SLIDER_CRANK_KERNELS_H
#define WEARJOINT_SLIDER_CRANK_KERNELS_H

#include <stdint.h>

#include "state_format.h"

/* The kernels' parameter vector mp from the 13 SliderCrankParameters fields (rpm, degrees), and
 * minv = M^-1 (Eq. 42). */
int32_t slider_crank_parameters(int32_t *status, void *excinfo, const double *fields, double *mp, double *minv);

/* The ideal mechanism's consistent state at time t into y (crank at theta0 - omega t, Eq. 39). */
int32_t slider_crank_initial_state(int32_t *status, void *excinfo, double t, const double *mp, double *jac,
                                   double *schur, double *phi, double *phi_dot, double *gamma, double *minv,
                                   double *force, double *y);

/* dy = dy/dt at (t, y) under the joint's loads (Eq. 44, crank-rod joint open). */
int32_t slider_crank_derivative(int32_t *status, void *excinfo, double t, const double *y, const double *mp,
                                const double *forces, double *jac, double *schur, double *phi, double *phi_dot,
                                double *gamma, double *minv, double *force, double *dy);

/* y advanced over [t, t + h] in n_steps RK4 steps with the loads held; dy = f at the end; stages:
 * 4 x 18 scratch. */
int32_t slider_crank_step(int32_t *status, void *excinfo, double t, double h, int64_t n_steps, double *y,
                          const double *mp, const double *forces, double *jac, double *schur, double *phi,
                          double *phi_dot, double *gamma, double *minv, double *force, double *dy, double *stages);

#endif
