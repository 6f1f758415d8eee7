"""How the integrators reach the clearance joint: one integrator, any kind of joint.

The integrators call four functions on their ``joint`` argument -- :func:`contact_forces`,
:func:`contact_at`, :func:`accept_joint`, :func:`joint_failed` -- which numba specialises on the
joint's type (``overload``).  This module implements them for :data:`JointArrays`, the joint in
process (the kernels run on its arrays: the monolithic engine); another module can register them for
another joint type (:mod:`wearjoint.cosim.fmu_joint`: the joint FMU's Model Exchange interface).
"""
from collections import namedtuple

import math

from numba import types
from numba.extending import overload

from .contact import evaluate_contact, evaluate_contact_scalars
from .jit import kernel
from .layout import CRANK, N_COORDINATES, ROD
from .wear import accept_contact_refreshing

# The integrators' right-hand side calls the compiled contact evaluation: inlining it there
# (numba's inline='always') took 16 of a cold run's 41 s of compiling and ran no faster
# (docs/performance.md, "Compile time").

# The joint in process: the joint parameter vector (layout.P_*), the bushing points' cos/sin, the wear
# profile, the contact search's block minima, the contact memory (layout.M_*), the wear kernels' scratch (a
# bool mask, N_d long, and a float64 array ``work``, 2 N_d long; not state) and the evaluation result
# (layout.R_*).
JointArrays = namedtuple("JointArrays", ("parameters", "cos_phi", "sin_phi", "wear_depth", "block_min",
                                         "memory", "mask", "work", "result"))
# No joint: the mechanism's own forces come from elsewhere (MODE_EXTERNAL: the co-simulation master, the
# slider-crank FMU).  Its functions do nothing, so code compiled for it holds no contact kernel (compiling
# the contact for a JointArrays that is never evaluated took 15 of a cold co-simulation's 35 s).
NoJoint = namedtuple("NoJoint", ("result",))


def is_joint_type(joint, kind) -> bool:
    """True if the numba type ``joint`` is the namedtuple class ``kind`` (an overload's dispatch)."""
    return isinstance(joint, types.BaseNamedTuple) and joint.instance_class is kind


def contact_forces(joint, t, y, cos1, sin1, cos2, sin2):
    """Evaluate the joint at time t and state y into ``joint.result`` (layout.R_*); cos/sin of the
    crank's and the rod's angles are given (the mechanism's right-hand side shares them)."""


def contact_at(joint, t, y):
    """:func:`contact_forces` at (t, y)."""


# accept_joint's answer: the joint did not change (``joint.result`` holds the contact at the accepted point); it
# changed, and ``joint.result`` holds the contact there on its new state (evaluated once, where the step wore); it
# changed otherwise (the contact must be evaluated again there)
JOINT_UNCHANGED, JOINT_EVALUATED, JOINT_CHANGED = 0, 1, 2


def accept_joint(joint, t, y, h, evaluated):
    """The joint's bookkeeping at an accepted point (wear over h, contact onsets); ``evaluated``:
    ``joint.result`` already holds the contact at (t, y).  Returns JOINT_UNCHANGED, JOINT_EVALUATED or
    JOINT_CHANGED (forces at the same state would differ, and ``joint.result`` does not hold them)."""


def joint_failed(joint):
    """True if a call to the joint failed (an FMU call; never in process)."""


@kernel(inline='always')
def _arrays_contact_forces(joint, t, y, cos1, sin1, cos2, sin2):
    n = N_COORDINATES
    evaluate_contact_scalars(y[CRANK], y[CRANK + 1], cos1, sin1, y[n + CRANK], y[n + CRANK + 1], y[n + CRANK + 2],
                             y[ROD], y[ROD + 1], cos2, sin2, y[n + ROD], y[n + ROD + 1], y[n + ROD + 2],
                             joint.parameters, joint.cos_phi, joint.sin_phi, joint.wear_depth, joint.block_min,
                             joint.memory, joint.result)


@kernel(inline='always')
def _arrays_accept(joint, t, y, h, evaluated):
    n = N_COORDINATES
    vel_i = y[n + CRANK:n + CRANK + 3]
    vel_j = y[n + ROD:n + ROD + 3]
    pos_i = y[CRANK:CRANK + 3]
    pos_j = y[ROD:ROD + 3]
    if not evaluated:                  # as advance_joint, whose accept then refreshes the result
        evaluate_contact(pos_i, vel_i, pos_j, vel_j, joint.parameters, joint.cos_phi, joint.sin_phi, joint.wear_depth,
                         joint.block_min, joint.memory, joint.result)
    code, refreshed = accept_contact_refreshing(joint.result, pos_i, vel_i, pos_j, vel_j, h, joint.parameters,
                                                joint.cos_phi, joint.sin_phi, joint.wear_depth, joint.block_min,
                                                joint.memory, joint.mask, joint.work)
    if refreshed:
        return JOINT_EVALUATED
    return JOINT_CHANGED if code > 0 else JOINT_UNCHANGED


@overload(contact_forces)
def _contact_forces(joint, t, y, cos1, sin1, cos2, sin2):
    if is_joint_type(joint, JointArrays):
        def arrays(joint, t, y, cos1, sin1, cos2, sin2):
            _arrays_contact_forces(joint, t, y, cos1, sin1, cos2, sin2)
        return arrays
    if is_joint_type(joint, NoJoint):
        def none(joint, t, y, cos1, sin1, cos2, sin2):
            pass
        return none
    return None


@overload(contact_at)
def _contact_at(joint, t, y):
    def at(joint, t, y):
        contact_forces(joint, t, y, math.cos(y[CRANK + 2]), math.sin(y[CRANK + 2]), math.cos(y[ROD + 2]),
                       math.sin(y[ROD + 2]))
    return at


@overload(accept_joint)
def _accept_joint(joint, t, y, h, evaluated):
    if is_joint_type(joint, JointArrays):
        def arrays(joint, t, y, h, evaluated):
            return _arrays_accept(joint, t, y, h, evaluated)
        return arrays
    if is_joint_type(joint, NoJoint):
        def none(joint, t, y, h, evaluated):
            return JOINT_UNCHANGED
        return none
    return None


@overload(joint_failed)
def _joint_failed(joint):
    if is_joint_type(joint, JointArrays) or is_joint_type(joint, NoJoint):
        def never(joint):
            return False
        return never
    return None


__all__ = ["JOINT_CHANGED", "JOINT_EVALUATED", "JOINT_UNCHANGED", "JointArrays", "NoJoint", "accept_joint",
           "contact_at", "contact_forces", "is_joint_type", "joint_failed"]
