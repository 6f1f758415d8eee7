"""The joint in a multibody host's generalized coordinates (wearjoint.exudyn's compiled calls): each side a planar
body's node (x [m], y [m], angle [rad], displacements from a reference) or ground (no coordinates); the joint's
forces on those coordinates, their exact Jacobian, and an accepted step's wear and history row.  Pure numba
functions on arrays, the joint's kernels (core.contact, core.wear) inside.
"""
from . import layout as L
from .contact import contact_jacobian, evaluate_contact
from .geometry import max_depth
from .jit import kernel
from .wear import advance_joint


@kernel
def body_kinematics(q, q_t, index, reference, position, velocity):
    """A body's position (x [m], y [m], angle [rad]) and velocity from the coordinates ``q``, ``q_t``
    (displacements from ``reference``) at its node's three ``index`` entries; an empty ``index``
    (ground) leaves them unchanged."""
    for c in range(index.shape[0]):
        position[c] = reference[c] + q[index[c]]
        velocity[c] = q_t[index[c]]


@kernel
def generalized_contact_forces(q, q_t, pin_index, bushing_index, reference_i, reference_j, pos_i, vel_i, pos_j, vel_j,
                               jp, cos_phi, sin_phi, wear_depth, block_min, memory, result, force):
    """The GenericODE2's force vector at its nodes' coordinates ``q``, ``q_t``, into ``force``: the
    bodies' kinematics, the contact (Eqs. 1-23, the joint's state read, not changed, into ``result``),
    then (Fx [N], Fy [N], T [N m]) on the pin body at ``pin_index`` and on the bushing body at
    ``bushing_index`` (empty: that side is ground)."""
    body_kinematics(q, q_t, pin_index, reference_i, pos_i, vel_i)
    body_kinematics(q, q_t, bushing_index, reference_j, pos_j, vel_j)
    evaluate_contact(pos_i, vel_i, pos_j, vel_j, jp, cos_phi, sin_phi, wear_depth, block_min, memory, result)
    for c in range(pin_index.shape[0]):
        force[pin_index[c]] = result[L.R_PIN_FX + c]
    for c in range(bushing_index.shape[0]):
        force[bushing_index[c]] = result[L.R_BUSHING_FX + c]


@kernel
def _jacobian_block(jacobian, rows, first_row, columns, first_input, derivative, factor_q, factor_q_t):
    """Add -(factor_q d/dq + factor_q_t d/dq_t) of one body's (Fx, Fy, T), the ``derivative`` rows
    from ``first_row``, in one body's coordinates (x, y, angle), whose positions and velocities are
    the kernel's inputs ``first_input`` .. + 2 and + 3 .. + 5, at ``jacobian[rows, columns]``."""
    for r in range(rows.shape[0]):
        for c in range(columns.shape[0]):
            jacobian[rows[r], columns[c]] -= (factor_q * derivative[first_row + r, first_input + c]
                                              + factor_q_t * derivative[first_row + r, first_input + 3 + c])


@kernel
def generalized_force_jacobian(q, q_t, pin_index, bushing_index, reference_i, reference_j, pos_i, vel_i, pos_j, vel_j,
                               jp, cos_phi, sin_phi, wear_depth, block_min, memory, result, derivative, jacobian,
                               factor_q, factor_q_t):
    """The GenericODE2's Jacobian as exudyn's ``jacobianUserFunction`` wants it, into ``jacobian``:
    -(factor_q dF/dq + factor_q_t dF/dq_t) of the force F of :func:`generalized_contact_forces`, from
    the contact's exact derivatives (:func:`contact_jacobian` into ``derivative``, N_RESULT x 12).
    A node's coordinates are its body's position less a constant reference and its velocities, so
    d(position)/dq and d(velocity)/dq_t are identities and the chain rule only picks blocks."""
    body_kinematics(q, q_t, pin_index, reference_i, pos_i, vel_i)
    body_kinematics(q, q_t, bushing_index, reference_j, pos_j, vel_j)
    contact_jacobian(pos_i, vel_i, pos_j, vel_j, jp, cos_phi, sin_phi, wear_depth, block_min, memory, result,
                     derivative)
    for row in range(jacobian.shape[0]):
        for col in range(jacobian.shape[1]):
            jacobian[row, col] = 0.0
    for rows, first_row in ((pin_index, L.R_PIN_FX), (bushing_index, L.R_BUSHING_FX)):
        _jacobian_block(jacobian, rows, first_row, pin_index, 0, derivative, factor_q, factor_q_t)
        _jacobian_block(jacobian, rows, first_row, bushing_index, 6, derivative, factor_q, factor_q_t)


@kernel
def history_row(t, result, wear_depth, slots, history, row):
    """Row ``row`` of the history (HISTORY_COLUMNS): t [s], the ``slots`` of ``result``, max wear depth [m]."""
    history[row, 0] = t
    for k in range(slots.shape[0]):
        history[row, 1 + k] = result[slots[k]]
    history[row, 1 + slots.shape[0]] = max_depth(wear_depth)


@kernel
def accept_step(pin_index, bushing_index, reference_i, reference_j, pos_i, vel_i, pos_j, vel_j, jp, cos_phi, sin_phi,
                wear_depth, block_min, memory, mask, work, result, slots, q, q_t, t, dt, at_end, history, row):
    """The post-step work of one joint in one compiled call: the bodies' kinematics at the system's
    coordinates ``q``, ``q_t``, the wear and contact-onset update over the accepted step ``dt`` [s]
    ending at ``t`` [s] (Eqs. 24-35, :func:`advance_joint`; ``at_end``: the solver evaluated the force only at the
    step's end, so its wear takes that force, else the mean of its start and end), then history row ``row``; returns
    advance_joint's code."""
    body_kinematics(q, q_t, pin_index, reference_i, pos_i, vel_i)
    body_kinematics(q, q_t, bushing_index, reference_j, pos_j, vel_j)
    code = advance_joint(pos_i, vel_i, pos_j, vel_j, dt, at_end, jp, cos_phi, sin_phi, wear_depth, block_min, memory,
                         mask, work, result)
    history_row(t, result, wear_depth, slots, history, row)
    return code
