"""The joint FMU's Model Exchange interface as the integrators' joint (:mod:`wearjoint.core.joint_access`).

:data:`FmuJoint` holds the FMU's C functions (ctypes function pointers) and the buffers they read and
write.  Every evaluation is ``fmi2SetTime`` + ``fmi2SetReal`` of the inputs + ``fmi2GetReal`` of the
outputs, every accepted point ``fmi2CompletedIntegratorStep`` (and, where the contact begins or ends, an
event: ``fmi2EnterEventMode``, ``fmi2NewDiscreteStates``, ``fmi2EnterContinuousTimeMode``).  Importing
this module registers those implementations (numba ``overload``) beside the in-process joint's.
"""
from collections import namedtuple

from numba.extending import overload

from ..core.jit import kernel
from ..core.joint_access import (
    JOINT_CHANGED, JOINT_UNCHANGED, JOINT_WORN, accept_joint, contact_forces, is_joint_type, joint_failed,
)
from ..core.joint_location import bodies_kinematics
from ..core.layout import M_ACTIVE, R_NORMAL_FORCE
from ..core.wear import wears
from ..fmu.loop_calls import failed_call
from ..fmu.variables import INPUTS

# ``io`` = the inputs (the pin body's kinematics, then the bushing body's) then the outputs, whose layout.R_* slots are
# ``output_slots``; ``result`` the outputs in the result layout; ``parameters`` the joint parameter vector;
# ``memory`` (layout.M_*) the master's own: M_ACTIVE whether the FMU's event indicator (the signed penetration,
# >= 0 in contact) was in contact at the last accepted point, which the integrators' onset location reads (the
# FMU keeps its contact memory itself); ``indicators`` the event indicator's value; ``event_info`` the
# fmi2EventInfo struct, ``flags`` the two fmi2Boolean outputs of fmi2CompletedIntegratorStep; ``events`` counts
# the event iterations [at contact onsets, at separations]; ``failure`` = [index of the failed call (FMU_CALLS),
# status, time].
FmuJoint = namedtuple("FmuJoint", ("component", "set_time", "set_real", "get_real", "completed_integrator_step",
                                   "enter_event_mode", "new_discrete_states", "enter_continuous_time_mode",
                                   "get_event_indicators", "input_vrs", "output_vrs", "output_slots", "io", "result",
                                   "parameters", "memory", "indicators", "event_info", "flags", "events",
                                   "failure"))
FMU_CALLS = ("", "fmi2SetTime", "fmi2SetReal", "fmi2GetReal", "fmi2CompletedIntegratorStep", "fmi2EnterEventMode",
             "fmi2NewDiscreteStates", "fmi2EnterContinuousTimeMode", "fmi2GetEventIndicators")
N_INPUTS = len(INPUTS)


@kernel
def _contact_forces(joint, t, y, pin, bushing):
    if joint.failure[0] != 0.0:
        return
    io = joint.io
    bodies_kinematics(y, pin, bushing, io)
    if failed_call(joint.failure, 0, 1, joint.set_time(joint.component, t), t):
        return
    if failed_call(joint.failure, 0, 2, joint.set_real(joint.component, joint.input_vrs.ctypes.data, N_INPUTS,
                                             io.ctypes.data), t):
        return
    n_out = joint.output_vrs.shape[0]
    if failed_call(joint.failure, 0, 3, joint.get_real(joint.component, joint.output_vrs.ctypes.data, n_out,
                                             io.ctypes.data + 8 * N_INPUTS), t):
        return
    for k in range(n_out):
        joint.result[joint.output_slots[k]] = io[N_INPUTS + k]


@kernel
def _accept(joint, t, y, pin, bushing, h, evaluated):
    """fmi2CompletedIntegratorStep (and an event iteration where a contact begins or ends); the joint_access answer:
    JOINT_CHANGED where a call failed or the onset memory changed, JOINT_WORN where the step may have worn the
    bushing (as in process, the points are then recorded with the contact before the wear and after it), else
    JOINT_UNCHANGED (DOPRI reuses its last stage, FSAL, instead of evaluating the FMU again)."""
    if not evaluated:
        _contact_forces(joint, t, y, pin, bushing)
    if joint.failure[0] != 0.0:
        return JOINT_CHANGED
    c = joint.component
    # the event indicator at the accepted point (before the step's wear): a sign change is a state event
    if failed_call(joint.failure, 0, 8, joint.get_event_indicators(c, joint.indicators.ctypes.data, 1), t):
        return JOINT_CHANGED
    if failed_call(joint.failure, 0, 4, joint.completed_integrator_step(c, 1, joint.flags.ctypes.data,
                                                              joint.flags.ctypes.data + 4), t):
        return JOINT_CHANGED
    onset = joint.indicators[0] >= 0.0
    if onset != (joint.memory[M_ACTIVE] > 0.5):   # a contact began or ended: a state event
        joint.events[0 if onset else 1] += 1
        if failed_call(joint.failure, 0, 5, joint.enter_event_mode(c), t):
            return JOINT_CHANGED
        if failed_call(joint.failure, 0, 6, joint.new_discrete_states(c, joint.event_info.ctypes.data), t):
            return JOINT_CHANGED
        if failed_call(joint.failure, 0, 7, joint.enter_continuous_time_mode(c), t):
            return JOINT_CHANGED
        joint.memory[M_ACTIVE] = 1.0 if onset else 0.0
        return JOINT_CHANGED
    return JOINT_WORN if wears(joint.result, joint.result[R_NORMAL_FORCE], joint.parameters, h) else JOINT_UNCHANGED


@overload(contact_forces)
def _overload_contact_forces(joint, t, y, pin, bushing, cos1, sin1, cos2, sin2):
    if is_joint_type(joint, FmuJoint):
        def fmu(joint, t, y, pin, bushing, cos1, sin1, cos2, sin2):
            _contact_forces(joint, t, y, pin, bushing)
        return fmu
    return None


@overload(accept_joint)
def _overload_accept_joint(joint, t, y, pin, bushing, h, evaluated):
    if is_joint_type(joint, FmuJoint):
        def fmu(joint, t, y, pin, bushing, h, evaluated):
            return _accept(joint, t, y, pin, bushing, h, evaluated)
        return fmu
    return None


@overload(joint_failed)
def _overload_joint_failed(joint):
    if is_joint_type(joint, FmuJoint):
        def fmu(joint):
            return joint.failure[0] != 0.0
        return fmu
    return None


__all__ = ["FMU_CALLS", "FmuJoint"]
