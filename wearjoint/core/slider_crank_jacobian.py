"""Exact Jacobian d(y_dot)/dy of the slider-crank with the clearance joint (Eqs. 38-44 with Baumgarte),
for implicit integrators (scipy's BDF, ``--integrator gear``).

y = [q (9), q_dot (9)] (Eq. 38), y_dot = [q_dot, q_dd(t, y, F(y))] with q_dd the open-joint accelerations
of :func:`~wearjoint.core.slider_crank.open_joint_accelerations_rotated` and F the joint's loads on the
crank and the rod (Eqs. 20-23).  The chain rule is evaluated as forward mode through the **same**
kernels, never a second copy of an equation:

* dF/dy: :func:`~wearjoint.core.contact.contact_jacobian` (forward mode through the contact chain);
* d q_dd / dy at fixed F plus d q_dd / dF dF/dy: the closed-form accelerations are rational in y, cos,
  sin and F (products, sums, one 2x2 solve), so numba compiles the same kernel for complex numbers
  and each of the 18 directions is one complex-step evaluation (Squire & Trapp 1998): y + i h e_m,
  F + i h dF/dy_m, cos/sin of the complex angles; d q_dd / dy_m = Im(q_dd) / h.  There is no
  subtraction, so the result is exact to round-off for any small h; h = 1e-40 keeps the neglected
  O(h^2) terms ~80 orders below the values.
"""
import cmath

import numpy as np

from .contact import contact_jacobian
from .jit import kernel
from .layout import (
    CRANK, N_COORDINATES, N_KINEMATIC_INPUTS, N_RESULT, R_BUSHING_FX, R_BUSHING_FY, R_BUSHING_TORQUE, R_PIN_FX,
    R_PIN_FY, R_PIN_TORQUE, ROD,
)
from .slider_crank import open_joint_accelerations_rotated

COMPLEX_STEP = 1e-40
# the loads on the crank then on the rod as :func:`~wearjoint.core.slider_crank.derivative` passes them
BODY_FORCE_ROWS = np.array([R_PIN_FX, R_PIN_FY, R_PIN_TORQUE, R_BUSHING_FX, R_BUSHING_FY, R_BUSHING_TORQUE])
# the contact kernel's input (layout.N_KINEMATIC_INPUTS: x, y, theta, vx, vy, omega of the crank, then
# of the rod) that each entry of y is, -1 for the slider's
_N = N_COORDINATES
CONTACT_INPUT = np.full(2 * _N, -1, dtype=np.int64)
for _k in range(3):
    CONTACT_INPUT[CRANK + _k] = _k
    CONTACT_INPUT[_N + CRANK + _k] = 3 + _k
    CONTACT_INPUT[ROD + _k] = 6 + _k
    CONTACT_INPUT[_N + ROD + _k] = 9 + _k


def make_jacobian_workspace():
    """Scratch of :func:`state_jacobian`: the contact's Jacobian (N_RESULT x 12), complex y, y_dot
    (18 each) and loads (6)."""
    n2 = 2 * N_COORDINATES
    return (np.zeros((N_RESULT, N_KINEMATIC_INPUTS)), np.zeros(n2, dtype=np.complex128),
            np.zeros(n2, dtype=np.complex128), np.zeros(6, dtype=np.complex128))


@kernel
def state_jacobian(t, y, mp, joint, ws, jac):
    """jac[r, m] = d y_dot[r] / d y[m] (18 x 18) of the clearance mechanism (MODE_CLEARANCE of
    :func:`~wearjoint.core.slider_crank.derivative`) at time t [s] and state y; ``joint`` a
    :data:`~wearjoint.core.joint_access.JointArrays` (its ``result`` is overwritten with the contact at
    (t, y), its state is not changed), ``ws`` from :func:`make_jacobian_workspace`.  Where the force
    is not differentiable (contact onset, friction ramp ends, deepest point changes) it is one of the
    one-sided derivatives (:func:`~wearjoint.core.contact.contact_jacobian`)."""
    n = N_COORDINATES
    dforce, y_c, dy_c, forces_c = ws
    result = joint.result
    contact_jacobian(y[CRANK:CRANK + 3], y[n + CRANK:n + CRANK + 3], y[ROD:ROD + 3], y[n + ROD:n + ROD + 3],
                     joint.parameters, joint.cos_phi, joint.sin_phi, joint.wear_depth, joint.block_min,
                     joint.memory, result, dforce)
    h = COMPLEX_STEP
    for r in range(2 * n):
        for m in range(2 * n):
            jac[r, m] = 0.0
    for k in range(n):
        jac[k, n + k] = 1.0                        # d q / dt = q_dot
    for m in range(2 * n):
        for k in range(2 * n):
            y_c[k] = y[k]
        y_c[m] = complex(y[m], h)
        column = CONTACT_INPUT[m]
        for k in range(6):
            slope = dforce[BODY_FORCE_ROWS[k], column] if column >= 0 else 0.0
            forces_c[k] = complex(result[BODY_FORCE_ROWS[k]], h * slope)
        th1 = y_c[CRANK + 2]
        th2 = y_c[ROD + 2]
        open_joint_accelerations_rotated(t, y_c, mp, forces_c, cmath.cos(th1), cmath.sin(th1), cmath.cos(th2),
                                         cmath.sin(th2), dy_c)
        for r in range(n, 2 * n):
            jac[r, m] = dy_c[r].imag / h
