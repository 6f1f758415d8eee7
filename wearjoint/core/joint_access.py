"""How the integrators reach the clearance joint: one integrator, any kind of joint.

The integrators call four functions on their ``joint`` argument -- :func:`contact_forces`,
:func:`contact_at`, :func:`accept_joint`, :func:`joint_failed` -- which numba specialises on the
joint's type (``overload``).  This module implements them for :data:`JointArrays`, the joint in
process (the kernels run on its arrays: the monolithic engine); another module can register them for
another joint type (:mod:`wearjoint.cosim.fmu_joint`: the joint FMU's Model Exchange interface).
"""
from collections import namedtuple

from numba import types
from numba.extending import overload

from .contact import evaluate_contact, evaluate_contact_scalars
from .jit import kernel
from .joint_location import bodies_kinematics, bodies_trig, body_state
from .layout import R_NORMAL_FORCE
from .admissibility import wall_overlap
from .wear import STEP_INADMISSIBLE, accept_contact_refreshing

# The integrators' right-hand side calls the compiled contact evaluation: inlining it there
# (numba's inline='always') took 16 of a cold run's 41 s of compiling and ran no faster
# (docs/how-to/choose_step_and_master.md, "First runs and speed").

# The joint in process: the joint parameter vector (layout.P_*), the bushing points' cos/sin, the wear
# profile, the contact search's block minima, the contact memory (layout.M_*), the wear kernels' scratch (a
# bool mask, N_d long, and a float64 array ``work``, 2 N_d long; not state) and the evaluation result
# (layout.R_*), the pin body's and the bushing body's kinematics (layout.N_KINEMATIC_INPUTS; scratch) and
# ``failure`` = [1 once an accepted point was inadmissible (core.admissibility), its time [s], the pin's overlap
# with the bushing wall [m] and the normal force [N] there] (the integrators stop: :func:`joint_failed`).
JointArrays = namedtuple("JointArrays", ("parameters", "cos_phi", "sin_phi", "wear_depth", "block_min",
                                         "memory", "mask", "work", "result", "kinematics", "failure"))
# No joint: the mechanism's own forces come from elsewhere (MODE_EXTERNAL: the co-simulation master, the
# slider-crank FMU).  Its functions do nothing, so code compiled for it holds no contact kernel (compiling
# the contact for a JointArrays that is never evaluated took 15 of a cold co-simulation's 35 s).
NoJoint = namedtuple("NoJoint", ("result",))


def is_joint_type(joint, kind) -> bool:
    """True if the numba type ``joint`` is the namedtuple class ``kind`` (an overload's dispatch)."""
    return isinstance(joint, types.BaseNamedTuple) and joint.instance_class is kind


def contact_forces(joint, t, y, pin, bushing, cos1, sin1, cos2, sin2):
    """Evaluate the joint between the bodies ``pin`` and ``bushing`` (offsets into q, layout.GROUND: the frame;
    core.joint_location) at time t and state y into ``joint.result`` (layout.R_*); cos/sin of their angles are
    given (the mechanism's right-hand side shares them)."""


def contact_at(joint, t, y, pin, bushing):
    """:func:`contact_forces` at (t, y)."""


# accept_joint's answer: the joint did not change (``joint.result`` holds the contact at the accepted point); it
# changed, and ``joint.result`` holds the contact there on its new state (evaluated once, where the step wore); it
# changed otherwise (the contact must be evaluated again there); the step may have worn the bushing, and the contact
# must be evaluated again there (an FMU's Model Exchange joint, which wears at fmi2CompletedIntegratorStep)
JOINT_UNCHANGED, JOINT_EVALUATED, JOINT_CHANGED, JOINT_WORN = 0, 1, 2, 3


def accept_joint(joint, t, y, pin, bushing, h, evaluated):
    """The joint's bookkeeping (between the bodies ``pin`` and ``bushing``, as :func:`contact_forces`) at an accepted point (wear over h, contact onsets); ``evaluated``:
    ``joint.result`` already holds the contact at (t, y).  Returns JOINT_UNCHANGED, JOINT_EVALUATED or
    JOINT_CHANGED (forces at the same state would differ, and ``joint.result`` does not hold them)."""


def joint_failed(joint):
    """True if a call to the joint failed (an FMU call), or an accepted point was inadmissible (in process)."""


@kernel(inline='always')
def _arrays_contact_forces(joint, t, y, pin, bushing, cos1, sin1, cos2, sin2):
    xi, yi, _, vxi, vyi, wi = body_state(y, pin)
    xj, yj, _, vxj, vyj, wj = body_state(y, bushing)
    evaluate_contact_scalars(xi, yi, cos1, sin1, vxi, vyi, wi, xj, yj, cos2, sin2, vxj, vyj, wj,
                             joint.parameters, joint.cos_phi, joint.sin_phi, joint.wear_depth, joint.block_min,
                             joint.memory, joint.result)


@kernel(inline='always')
def _arrays_accept(joint, t, y, pin, bushing, h, evaluated):
    kinematics = joint.kinematics
    bodies_kinematics(y, pin, bushing, kinematics)
    pos_i = kinematics[0:3]
    vel_i = kinematics[3:6]
    pos_j = kinematics[6:9]
    vel_j = kinematics[9:12]
    if not evaluated:                  # as advance_joint, whose accept then refreshes the result
        evaluate_contact(pos_i, vel_i, pos_j, vel_j, joint.parameters, joint.cos_phi, joint.sin_phi, joint.wear_depth,
                         joint.block_min, joint.memory, joint.result)
    code, refreshed = accept_contact_refreshing(joint.result, pos_i, vel_i, pos_j, vel_j, h, joint.parameters,
                                                joint.cos_phi, joint.sin_phi, joint.wear_depth, joint.block_min,
                                                joint.memory, joint.mask, joint.work)
    if code == STEP_INADMISSIBLE and joint.failure[0] == 0.0:
        joint.failure[0] = 1.0
        joint.failure[1] = t
        joint.failure[2] = wall_overlap(joint.result, joint.parameters, joint.wear_depth)
        joint.failure[3] = joint.result[R_NORMAL_FORCE]
    if refreshed:
        return JOINT_EVALUATED
    return JOINT_CHANGED if code > 0 else JOINT_UNCHANGED


@overload(contact_forces)
def _contact_forces(joint, t, y, pin, bushing, cos1, sin1, cos2, sin2):
    if is_joint_type(joint, JointArrays):
        def arrays(joint, t, y, pin, bushing, cos1, sin1, cos2, sin2):
            _arrays_contact_forces(joint, t, y, pin, bushing, cos1, sin1, cos2, sin2)
        return arrays
    if is_joint_type(joint, NoJoint):
        def none(joint, t, y, pin, bushing, cos1, sin1, cos2, sin2):
            pass
        return none
    return None


@overload(contact_at)
def _contact_at(joint, t, y, pin, bushing):
    def at(joint, t, y, pin, bushing):
        cos1, sin1, cos2, sin2 = bodies_trig(y, pin, bushing)
        contact_forces(joint, t, y, pin, bushing, cos1, sin1, cos2, sin2)
    return at


@overload(accept_joint)
def _accept_joint(joint, t, y, pin, bushing, h, evaluated):
    if is_joint_type(joint, JointArrays):
        def arrays(joint, t, y, pin, bushing, h, evaluated):
            return _arrays_accept(joint, t, y, pin, bushing, h, evaluated)
        return arrays
    if is_joint_type(joint, NoJoint):
        def none(joint, t, y, pin, bushing, h, evaluated):
            return JOINT_UNCHANGED
        return none
    return None


@overload(joint_failed)
def _joint_failed(joint):
    if is_joint_type(joint, JointArrays):
        def arrays(joint):
            return joint.failure[0] != 0.0
        return arrays
    if is_joint_type(joint, NoJoint):
        def never(joint):
            return False
        return never
    return None


__all__ = ["JOINT_CHANGED", "JOINT_EVALUATED", "JOINT_UNCHANGED", "JOINT_WORN",
           "JointArrays", "NoJoint", "accept_joint", "contact_at", "contact_forces", "is_joint_type", "joint_failed"]
