"""How the integrators reach the clearance joint: one integrator, two kinds of joint.

* :data:`~wearjoint.core.mechanism.JointArrays` -- the joint in process: the kernels run on
  its arrays (the monolithic engine).
* :data:`FmuJoint` -- the joint as an FMU's Model Exchange interface: every evaluation is
  ``fmi2SetTime`` + ``fmi2SetReal`` of the 12 inputs + ``fmi2GetReal`` of the outputs, every
  accepted point ``fmi2CompletedIntegratorStep`` (and, where the contact begins or ends, an event:
  ``fmi2EnterEventMode``, ``fmi2NewDiscreteStates``, ``fmi2EnterContinuousTimeMode``).

The functions below are specialised by numba on the joint's type (``overload``), so the
integrators' code is the same for both and the in-process path compiles to what it was.
"""
from collections import namedtuple

import math

from numba import types
from numba.extending import overload

from .contact import evaluate_contact_scalars, update_contact_memory
from .jit import kernel
from .layout import CRANK, M_ACTIVE, N_COORDINATES, R_CONTACT, R_NORMAL_FORCE, ROD
from .wear import accept_contact, advance_joint, wears

# The integrators' right-hand side calls the compiled contact evaluation: inlining it there
# (numba's inline='always') took 16 of a cold run's 41 s of compiling and ran no faster
# (docs/performance.md, "Compile time").

# The FMU's C functions (ctypes function pointers) and the buffers they read and write:
# ``io`` = the 12 inputs (pin body = crank, bushing body = rod) then the outputs, whose
# layout.R_* slots are ``output_slots``; ``result`` the outputs in the result layout;
# ``parameters`` / ``memory`` the joint parameter vector and a mirror of the FMU's contact
# memory (the same onset rule, :func:`update_contact_memory`, applied to the FMU's outputs);
# ``event_info`` the fmi2EventInfo struct, ``flags`` the two fmi2Boolean outputs of
# fmi2CompletedIntegratorStep; ``events`` counts the event iterations [at contact onsets, at
# separations]; ``failure`` = [index of the failed call (FMU_CALLS), status, time].
FmuJoint = namedtuple("FmuJoint", ("component", "set_time", "set_real", "get_real", "completed_integrator_step",
                                   "enter_event_mode", "new_discrete_states", "enter_continuous_time_mode",
                                   "input_vrs", "output_vrs", "output_slots", "io", "result", "parameters",
                                   "memory", "event_info", "flags", "events", "failure"))
FMU_CALLS = ("", "fmi2SetTime", "fmi2SetReal", "fmi2GetReal", "fmi2CompletedIntegratorStep", "fmi2EnterEventMode",
             "fmi2NewDiscreteStates", "fmi2EnterContinuousTimeMode")
N_INPUTS = 12
FMI_WARNING = 1


def _is_fmu_joint(joint) -> bool:
    return isinstance(joint, types.NamedTuple) and joint.instance_class is FmuJoint


def contact_forces(joint, t, y, cos1, sin1, cos2, sin2):
    """Evaluate the joint at time t and state y into ``joint.result`` (layout.R_*); cos/sin of the
    crank's and the rod's angles are given (the mechanism's right-hand side shares them)."""


def contact_at(joint, t, y):
    """:func:`contact_forces` at (t, y)."""


def accept_joint(joint, t, y, h, evaluated):
    """The joint's bookkeeping at an accepted point (wear over h, contact onsets); ``evaluated``:
    ``joint.result`` already holds the contact at (t, y).  Returns True if the joint may have
    changed (forces at the same state would differ)."""


def joint_failed(joint):
    """True if a call to the joint failed (an FMU call; never in process)."""


# ------------------------------------------------------------------ in process
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
    if evaluated:
        return accept_contact(joint.result, pos_i, vel_i, pos_j, vel_j, h, False, joint.parameters, joint.cos_phi,
                              joint.sin_phi, joint.wear_depth, joint.block_min, joint.memory, joint.mask,
                              joint.work) > 0
    return advance_joint(pos_i, vel_i, pos_j, vel_j, h, False, joint.parameters, joint.cos_phi, joint.sin_phi,
                         joint.wear_depth, joint.block_min, joint.memory, joint.mask, joint.work, joint.result) > 0


# ------------------------------------------------------------------ through the FMU
@kernel(inline='always')
def _fmu_call_failed(joint, call, status, t):
    """Record the first failing call; True if ``status`` is worse than fmi2Warning."""
    if status > FMI_WARNING:
        if joint.failure[0] == 0.0:
            joint.failure[0] = call
            joint.failure[1] = status
            joint.failure[2] = t
        return True
    return False


@kernel
def _fmu_contact_forces(joint, t, y):
    if joint.failure[0] != 0.0:
        return
    n = N_COORDINATES
    io = joint.io
    for k in range(3):
        io[k] = y[CRANK + k]
        io[3 + k] = y[n + CRANK + k]
        io[6 + k] = y[ROD + k]
        io[9 + k] = y[n + ROD + k]
    if _fmu_call_failed(joint, 1, joint.set_time(joint.component, t), t):
        return
    if _fmu_call_failed(joint, 2, joint.set_real(joint.component, joint.input_vrs.ctypes.data, N_INPUTS,
                                                 io.ctypes.data), t):
        return
    n_out = joint.output_vrs.shape[0]
    if _fmu_call_failed(joint, 3, joint.get_real(joint.component, joint.output_vrs.ctypes.data, n_out,
                                                 io.ctypes.data + 8 * N_INPUTS), t):
        return
    for k in range(n_out):
        joint.result[joint.output_slots[k]] = io[N_INPUTS + k]


@kernel
def _fmu_accept(joint, t, y, h, evaluated):
    """fmi2CompletedIntegratorStep (and an event iteration where a contact begins or ends).
    "Changed" as in process: the onset memory changed, or the step may have worn the bushing;
    otherwise DOPRI reuses its last stage (FSAL) instead of evaluating the FMU again."""
    if not evaluated:
        _fmu_contact_forces(joint, t, y)
    if joint.failure[0] != 0.0:
        return True
    c = joint.component
    if _fmu_call_failed(joint, 4, joint.completed_integrator_step(c, 1, joint.flags.ctypes.data,
                                                                  joint.flags.ctypes.data + 4), t):
        return True
    onset = joint.result[R_CONTACT] > 0.5
    if onset != (joint.memory[M_ACTIVE] > 0.5):   # a contact began or ended: a state event
        joint.events[0 if onset else 1] += 1
        if _fmu_call_failed(joint, 5, joint.enter_event_mode(c), t):
            return True
        if _fmu_call_failed(joint, 6, joint.new_discrete_states(c, joint.event_info.ctypes.data), t):
            return True
        if _fmu_call_failed(joint, 7, joint.enter_continuous_time_mode(c), t):
            return True
    onset_changed = update_contact_memory(joint.result, joint.parameters, joint.memory)
    return onset_changed or wears(joint.result, joint.result[R_NORMAL_FORCE], joint.parameters, h)


@overload(contact_forces)
def _contact_forces(joint, t, y, cos1, sin1, cos2, sin2):
    if _is_fmu_joint(joint):
        def fmu(joint, t, y, cos1, sin1, cos2, sin2):
            _fmu_contact_forces(joint, t, y)
        return fmu

    def arrays(joint, t, y, cos1, sin1, cos2, sin2):
        _arrays_contact_forces(joint, t, y, cos1, sin1, cos2, sin2)
    return arrays


@overload(contact_at)
def _contact_at(joint, t, y):
    def at(joint, t, y):
        contact_forces(joint, t, y, math.cos(y[CRANK + 2]), math.sin(y[CRANK + 2]), math.cos(y[ROD + 2]),
                       math.sin(y[ROD + 2]))
    return at


@overload(accept_joint)
def _accept_joint(joint, t, y, h, evaluated):
    if _is_fmu_joint(joint):
        def fmu(joint, t, y, h, evaluated):
            return _fmu_accept(joint, t, y, h, evaluated)
        return fmu

    def arrays(joint, t, y, h, evaluated):
        return _arrays_accept(joint, t, y, h, evaluated)
    return arrays


@overload(joint_failed)
def _joint_failed(joint):
    if _is_fmu_joint(joint):
        def fmu(joint):
            return joint.failure[0] != 0.0
        return fmu

    def arrays(joint):
        return False
    return arrays


__all__ = ["FmuJoint", "FMU_CALLS", "contact_forces", "contact_at", "accept_joint", "joint_failed"]
