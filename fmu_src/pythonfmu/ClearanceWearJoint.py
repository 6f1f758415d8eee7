"""pythonfmu reference slave ``ClearanceWearJoint``: FMI 2.0 Co-Simulation of one
:class:`wearjoint.ClearanceJoint` (contract: docs/reference/fmu.md §5), with the variables and numbers
of the native FMU (fmu_src/fmi/fmi2Functions.c).

* Variables come from :mod:`wearjoint.fmu.variables`, registered in its order (value
  reference = position in ``fmu_variables(n_points)``).  Every Real value lives in one array
  indexed by value reference; a getReal brings what it asks for up to date first: the joint's
  outputs (direct feed-through) from the current inputs, the wear profile and its summary after
  a step or an FMU state changed them.
* ``doStep(t, h)`` advances wear and contact memory with the inputs held at t (the wear with the linearised force's
  mean where the host read the loads' derivatives at t, as the native FMU).
* Parameters are read at exitInitializationMode (the kernels compile there) and fixed afterwards.
* Errors are logged with fmi2Error and flagged to the status shim (fmu_src/pythonfmu/status_shim.c, the
  FMU's binary), which returns fmi2Error where pythonfmu alone gives fmi2Fatal (:meth:`_abort_call`).
  Non-finite inputs: getReal of a joint output fails, doStep is discarded (fmi2Discard).

Built by ``wearjoint build-fmu --backend pythonfmu`` (wearjoint/fmu/build_pythonfmu.py), which
fixes n_points in resources/wearjoint_fmu.json.
"""
import contextlib
import ctypes
import functools
import json
import math
import re
import sys
from pathlib import Path

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real
from pythonfmu.enums import Fmi2Initial, Fmi2Status


@contextlib.contextmanager
def _scipy_hidden():
    """Make ``import scipy`` fail inside the block unless the host already imported it.

    numba imports scipy when it loads (a version check) and on its first compile
    (BLAS probe); scipy's Fortran runtime has crashed non-Python hosts at exit.
    Afterwards the host's own ``import scipy`` works normally.
    """
    hide = "scipy" not in sys.modules
    if hide:
        sys.modules["scipy"] = None
    try:
        yield
    finally:
        if hide and sys.modules.get("scipy", 0) is None:
            del sys.modules["scipy"]


with _scipy_hidden():
    import numpy as np

    from wearjoint import ClearanceJoint, JointParameters, JointState, ParameterError, __version__
    from wearjoint.core import layout as L, state_format
    from wearjoint.checks import worn_through_message
    from wearjoint.core.admissibility import wall_overlap
    from wearjoint.core.wear import STEP_INADMISSIBLE
    from wearjoint.fmu import variables as fv
    from wearjoint.joint import check_state_values, read_state_bytes, state_bytes

# FMU state: the state format of ClearanceJoint (docs/reference/fmu.md), contents "FMU instance": its head is
# the time [s], 1.0 if initialised, the inputs, the parameters (fv.PARAMETERS order), 1.0 if the host read the
# loads' derivatives, and the native FMU's Model Exchange onsets flag (0 here)
_N_INPUTS = len(fv.INPUTS)
_INPUT_NAMES = [v.name for v in fv.INPUTS]
# what a getReal of a value reference needs brought up to date first
_NOT_REAL, _NOTHING, _FORCES, _WEAR, _LINEARISATION = -1, 0, 1, 2, 3

# pythonfmu's causality, variability and initial of each kind of variable (fv.LOCAL: n_points, read-only)
_CAUSALITY = {
    fv.INPUT: dict(causality=Fmi2Causality.input, variability=Fmi2Variability.continuous),
    fv.OUTPUT: dict(causality=Fmi2Causality.output, variability=Fmi2Variability.continuous,
                    initial=Fmi2Initial.calculated),
    fv.PARAMETER: dict(causality=Fmi2Causality.parameter, variability=Fmi2Variability.fixed,
                       initial=Fmi2Initial.exact),
    fv.LOCAL: dict(causality=Fmi2Causality.local, variability=Fmi2Variability.constant, initial=Fmi2Initial.exact),
}

# Objects pythonfmu 0.7 releases once too often after a Python exception (see _abort_call).
_OVER_RELEASED = []
# The status shim, relative to the FMU's root folder (the parent of its resources folder).
_SHIM_BINARY = Path("binaries", "linux64", f"{fv.MODEL_NAME}.so")


def _built_n_points(resources) -> int:
    """N_d fixed by the build (resources/wearjoint_fmu.json); the default outside an FMU."""
    if resources is None:
        return JointParameters.n_points
    return int(json.loads((Path(resources) / fv.BUILD_CONFIG_FILE).read_text())["n_points"])


def _compile_kernels(params) -> None:
    """Run every kernel the slave calls once on a throwaway joint so numba compiles now, not in doStep."""
    scratch = ClearanceJoint(params)
    kinematics = np.zeros(12)
    scratch.evaluate_array(kinematics[0:3], kinematics[3:6], kinematics[6:9], kinematics[9:12])
    scratch.advance_array(kinematics[0:3], kinematics[3:6], kinematics[6:9], kinematics[9:12], 0.0, True)
    scratch.worn_volume_m3  # noqa: B018 - compiles worn_area
    scratch.state_from_bytes(scratch.state_to_bytes())   # getFMUstate, setFMUstate


class FmuCallFailed(Exception):
    """An FMI call of this slave failed; the message was logged with fmi2Error."""


def _guarded(method):
    """Turn any exception escaping an FMI hook into :meth:`_abort_call` (logged, no crash)."""
    @functools.wraps(method)
    def call(self, *args):
        try:
            return method(self, *args)
        except FmuCallFailed:
            raise
        except Exception as exc:  # noqa: BLE001 - every exception must take the guarded path
            self._abort_call(f"{method.__name__} failed: {exc!r}")
    return call


def _refused(call: str, kind: str):
    """The hook of an FMI call on a variable type this FMU does not have: it fails with fmi2Error."""
    def hook(self, vrs, values=None):
        self._abort_call(f"{call}: this FMU has no {kind} variables (asked for {list(vrs)})")
    return hook


class ClearanceWearJoint(Fmi2Slave):
    """FMI 2.0 Co-Simulation slave holding one ClearanceJoint (see the module docstring)."""

    author = "wearjoint"
    description = ("Planar revolute clearance joint with a wearing bushing (Archard wear, elastic-foundation "
                   "contact, Hunt-Crossley damping, Ambrosio friction). Inputs: kinematics of the pin and bushing "
                   "bodies; outputs: forces (direct feed-through) and the wear profile.")
    version = __version__

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        n_points = self.n_points = _built_n_points(self.resources)
        variables = fv.fmu_variables(n_points)
        self._names = [v.name for v in variables]
        vr_of = {name: vr for vr, name in enumerate(self._names)}
        self._values = np.full(len(variables), math.nan)   # every value by value reference (Integers too)
        self._needs = np.full(len(variables), _NOTHING, dtype=np.int8)
        for vr, v in enumerate(variables):
            kind = Real if v.type == fv.REAL else Integer
            self._values[vr] = math.nan if v.start is None else v.start
            if kind is Integer:
                self._needs[vr] = _NOT_REAL
            # values go through the overridden get_*/set_* below, never through pythonfmu getters
            self.register_variable(kind(v.name, description=v.description, **_CAUSALITY[v.causality]))
            if self.vars[vr].value_reference != vr:
                raise RuntimeError(f"variable {v.name} got value reference {self.vars[vr].value_reference}, "
                                   f"expected {vr}")
        self._inputs = self._values[:_N_INPUTS]
        self._pin_position, self._pin_velocity = self._inputs[0:3], self._inputs[3:6]
        self._bushing_position, self._bushing_velocity = self._inputs[6:9], self._inputs[9:12]
        self._parameter_vrs = np.array([vr_of[p.variable.name] for p in fv.PARAMETERS])
        self._settable = {vr: p.variable.type for vr, p in zip(self._parameter_vrs.tolist(), fv.PARAMETERS)}
        self._n_points_vr = vr_of[fv.N_POINTS_NAME]
        self._result_vrs = np.array([vr_of[name] for name in fv.RESULT_SLOTS])
        self._result_slots = np.array(list(fv.RESULT_SLOTS.values()))
        first_depth = vr_of[fv.wear_depth_name(1)]
        self._depth_vrs = slice(first_depth, first_depth + n_points)
        self._summary_vrs = [vr_of[name] for name in fv.WEAR_SUMMARY_NAMES]
        self._jacobian = np.zeros((L.N_RESULT, _N_INPUTS))
        self._derivative_vrs = np.array([vr_of[name] for name in fv.JACOBIAN_SLOTS])
        self._derivative_slots = tuple(np.array(slots) for slots in zip(*fv.JACOBIAN_SLOTS.values()))
        self._evaluated_vrs = np.array([vr_of[name] for name in fv.EVALUATED_INPUTS])
        self._needs[self._result_vrs] = _FORCES
        self._needs[self._derivative_vrs] = _LINEARISATION
        self._needs[self._evaluated_vrs] = _LINEARISATION
        self._needs[self._depth_vrs] = _WEAR
        self._needs[self._summary_vrs] = _WEAR
        self._needs = self._needs.tolist()
        self._parameter_block = None   # the joint's parameter values as bytes (the state's)
        self._joint = None
        self._initialised = False
        self._time = 0.0
        self._stop_time = math.inf      # the master's (setup_experiment): no step passes it
        self._forces_stale = self._wear_stale = self._linearisation_stale = True
        self._derivatives_read = False  # the host read derivatives since the loads were last evaluated (a linearising host)

    # ------------------------------------------------------------- errors
    def _abort_call(self, message: str):
        """Log ``message`` (fmi2Error) and make the current FMI call fail with fmi2Error.

        pythonfmu 0.7 maps a Python exception to fmi2Fatal; flagging the error to
        the status shim first makes the call return fmi2Error.  pythonfmu then
        releases its references to the slave class, the instance and its log
        queue while still holding them (the host segfaults at the next garbage
        collection): one extra reference to each is kept here, forever.
        """
        self._log_error(message)
        _OVER_RELEASED.extend((type(self), self, self.log_queue))
        if self.resources is not None:   # dlopen of the shim's path returns the library the host loaded
            with contextlib.suppress(OSError, AttributeError):   # no shim: outside an FMU
                ctypes.CDLL(str(Path(self.resources).parent / _SHIM_BINARY)).wearjoint_shim_flag_error()
        raise FmuCallFailed(message)

    def _log_error(self, message: str) -> None:
        # the FMI logger treats the message as a printf format
        self.log(message.replace("%", "%%"), Fmi2Status.error)

    def _name(self, vr: int) -> str:
        return self._names[vr] if 0 <= vr < len(self._names) else f"<no variable with valueReference {vr}>"

    def _non_finite_inputs(self) -> str:
        """The non-finite inputs as ``name=value, ...`` ('' if all are finite)."""
        values = self._inputs.tolist()
        if all(map(math.isfinite, values)):
            return ""
        return ", ".join(f"{name}={value!r}" for name, value in zip(_INPUT_NAMES, values) if not math.isfinite(value))

    # ------------------------------------------------------------- the joint
    def _ensure_joint(self) -> None:
        """(Re)build the joint if the parameter values differ from those it was built with."""
        block = self._values[self._parameter_vrs].tobytes()
        if block == self._parameter_block:
            return
        values = {p.variable.name: (int(value) if p.variable.type == fv.INTEGER else value)
                  for p, value in zip(fv.PARAMETERS, self._values[self._parameter_vrs].tolist())}
        try:
            params = fv.joint_parameters_from_fmi(values, self.n_points)
        except ParameterError as exc:       # named as the parameter set names it, and as this FMU does
            field = re.match(r"parameter (\w+)=", str(exc))
            names = [p.variable.name for p in fv.PARAMETERS if field and p.field == field[1]]
            self._abort_call(f"invalid FMU parameter: {exc}" + (f" (the FMU's {', '.join(names)})" if names else ""))
        with _scipy_hidden():
            self._joint = ClearanceJoint(params)
            _compile_kernels(params)
        self._parameter_block = block
        self._forces_stale = self._wear_stale = self._linearisation_stale = True

    def _refresh(self, vrs, needs) -> None:
        """Bring the joint's outputs getReal of ``vrs`` needs (``needs``: _FORCES, _WEAR) up to date."""
        self._ensure_joint()
        joint = self._joint
        linearise = self._linearisation_stale and _LINEARISATION in needs
        if (self._forces_stale and _FORCES in needs) or linearise:
            non_finite = self._non_finite_inputs()
            if non_finite:
                outputs = [self._names[vr] for vr in vrs if self._needs[vr] in (_FORCES, _LINEARISATION)]
                self._abort_call(f"getReal of {', '.join(outputs)}: undefined for non-finite inputs ({non_finite})")
            kinematics = (self._pin_position, self._pin_velocity, self._bushing_position, self._bushing_velocity)
            if linearise:
                joint.linearise_array(*kinematics, self._jacobian)
                self._values[self._derivative_vrs] = self._jacobian[self._derivative_slots]
                self._values[self._evaluated_vrs] = self._inputs
                self._linearisation_stale = False
            else:
                joint.evaluate_array(*kinematics)
            self._values[self._result_vrs] = joint.result[self._result_slots]
            self._forces_stale = self._derivatives_read = False
        if self._wear_stale and _WEAR in needs:
            self._values[self._depth_vrs] = joint.wear_depth
            self._values[self._summary_vrs] = (joint.max_wear_depth_m, joint.worn_volume_m3)
            self._wear_stale = False

    # ------------------------------------------------------------- FMI hooks
    @_guarded
    def setup_experiment(self, start_time, stop_time=None, tolerance=None):
        self._time = float(start_time)
        self._stop_time = math.inf if stop_time is None else float(stop_time)

    @_guarded
    def exit_initialization_mode(self):
        self._ensure_joint()  # builds the joint from the final parameters, compiles the kernels
        self._initialised = True

    @_guarded
    def do_step(self, current_time, step_size):
        if not self._initialised:
            self._abort_call("doStep: not allowed before exitInitializationMode (FMI 2.0 call sequence)")
        slack = 1e-3 * abs(step_size) + 4.0 * sys.float_info.epsilon * max(abs(current_time), abs(self._time))
        if math.isfinite(step_size) and not abs(current_time - self._time) <= slack:   # as fmu_src/fmi/fmi_checks.h
            self._abort_call(f"doStep: currentCommunicationPoint={current_time:.17g} s is invalid: allowed the FMU's "
                             f"time {self._time:.17g} s (the start time, the end of its last step or a state's time "
                             "set): a step was lost or repeated")
        if math.isfinite(step_size) and current_time + step_size > self._stop_time + slack:
            self._abort_call(f"doStep: a step of {step_size:g} s from {current_time:.17g} s ends past the stop time "
                             f"{self._stop_time:.17g} s the master set: allowed up to it")
        non_finite = self._non_finite_inputs()
        if non_finite:
            self._log_error(f"doStep at t={current_time!r} s rejected: non-finite inputs ({non_finite})")
            return False
        if not 0.0 <= step_size < math.inf:
            self._log_error(f"doStep rejected: step size {step_size!r} s is not a finite value >= 0")
            return False
        self._ensure_joint()
        kinematics = (self._pin_position, self._pin_velocity, self._bushing_position, self._bushing_velocity)
        if self._forces_stale and self._derivatives_read:    # read before these inputs were set (a master one step
            self._refresh(self._derivative_vrs[:1], {_LINEARISATION})   # late): the loads and derivatives here
            self._derivatives_read = True                     # still read, as the native FMU's joint_model.c
        if not (self._forces_stale or self._linearisation_stale):   # the host read the loads' derivatives here
            changed = self._joint.accept_linearised_array(*kinematics, step_size, self._jacobian)
        else:
            changed = self._joint.advance_array(*kinematics, step_size, True)
        if changed == STEP_INADMISSIBLE and not self._joint.max_wear_depth_m <= self._joint.params.bushing_radius_m:
            self._log_error(f"doStep at t={current_time!r} s rejected: " + worn_through_message(
                "before it", self._joint.max_wear_depth_m, self._joint.params.bushing_radius_m)
                + ": nothing changed (docs/reference/model.md §3.14)")
            return False
        if changed == STEP_INADMISSIBLE:
            overlap = wall_overlap(self._joint.result, self._joint.parameter_vector, self._joint.wear_depth)
            params = self._joint.params
            self._log_error(f"doStep at t={current_time!r} s rejected: the inputs put the pin {overlap:.6g} m into the "
                            f"bushing wall (admissible {params.admissible_penetration_m:.6g} m) with a normal force "
                            f"of {self._joint.result[6]:.6g} N (admissible {params.admissible_force_N:.6g} N): no "
                            "contact of this joint reaches it; the master's step is too long for the contact "
                            "(docs/reference/model.md §3.14)")
            return False
        if changed < 0:
            self._log_error(f"doStep rejected: a step of {step_size!r} s wears the bushing by more than its radius")
            return False
        if changed:
            self._wear_stale = True
        self._time = current_time + step_size
        self._forces_stale = self._linearisation_stale = True
        return True

    @_guarded
    def get_real(self, vrs):
        n_variables = len(self._needs)
        needs = {self._needs[vr] if vr < n_variables else _NOT_REAL for vr in vrs}
        if _NOT_REAL in needs:
            bad = [self._name(vr) for vr in vrs if vr >= n_variables or self._needs[vr] == _NOT_REAL]
            self._abort_call(f"getReal: not Real variables: {', '.join(bad)}")
        if needs - {_NOTHING}:
            self._refresh(vrs, needs)
        self._derivatives_read = self._derivatives_read or _LINEARISATION in needs
        values = self._values
        return [values[vr] for vr in vrs]

    @_guarded
    def set_real(self, vrs, values):
        for vr, value in zip(vrs, values):
            if vr >= _N_INPUTS:
                self._check_settable("setReal", vr, fv.REAL)
            self._values[vr] = value
        self._forces_stale = self._linearisation_stale = True

    @_guarded
    def get_integer(self, vrs):
        bad = [self._name(vr) for vr in vrs if vr >= len(self._needs) or self._needs[vr] != _NOT_REAL]
        if bad:
            self._abort_call(f"getInteger: not Integer variables: {', '.join(bad)}")
        return [int(self._values[vr]) for vr in vrs]

    @_guarded
    def set_integer(self, vrs, values):
        for vr, value in zip(vrs, values):
            if vr == self._n_points_vr:
                if value != self.n_points:
                    self._abort_call(f"n_points is fixed at {self.n_points} when the FMU is built; "
                                     f"rebuild it for {value} points (wearjoint build-fmu --n-points {value})")
            else:
                self._check_settable("setInteger", vr, fv.INTEGER)
                self._values[vr] = int(value)

    def _check_settable(self, call: str, vr: int, kind: str) -> None:
        """Fail unless ``vr`` is a parameter of type ``kind`` and the instance is not yet initialised."""
        if self._settable.get(vr) != kind:
            self._abort_call(f"{call}: variable {self._name(vr)} cannot be set")
        if self._initialised:
            self._abort_call(f"parameter {self._names[vr]} is fixed: set it before exitInitializationMode")

    get_boolean, set_boolean = _refused("getBoolean", "Boolean"), _refused("setBoolean", "Boolean")
    get_string, set_string = _refused("getString", "String"), _refused("setString", "String")

    # ------------------------------------------------------------- FMU state
    # The state object is the serialised bytes themselves (ClearanceJoint's state format): exact,
    # immutable, and getFMUstate / serializeFMUstate share one code path; setFMUstate checks it.
    @_guarded
    def _get_fmu_state(self):
        self._ensure_joint()
        joint = self._joint
        head = np.concatenate(([self._time, 1.0 if self._initialised else 0.0], self._inputs,
                               np.frombuffer(self._parameter_block),
                               [1.0 if self._derivatives_read else 0.0, 0.0]))   # no Model Exchange: no onsets flag
        return state_bytes(state_format.CONTENTS_FMU, head, joint.memory, joint.wear_depth)

    @_guarded
    def _set_fmu_state(self, state):
        try:
            head, memory, wear_depth = read_state_bytes(state, state_format.CONTENTS_FMU, fv.STATE_HEAD_SIZE,
                                                        self.n_points)
            parameters = head[2 + _N_INPUTS:2 + _N_INPUTS + len(fv.PARAMETERS)]
            values = {p.variable.name: int(v) if p.variable.type == fv.INTEGER and v.is_integer() else v
                      for p, v in zip(fv.PARAMETERS, parameters.tolist())}
            check_state_values(head, memory, wear_depth, fv.joint_parameters_from_fmi(values, self.n_points))
        except ParameterError as exc:
            self._abort_call(f"setFMUstate: {exc}")
        self._values[self._parameter_vrs] = parameters
        self._ensure_joint()
        self._joint.set_state(JointState(wear_depth, memory))
        self._inputs[:] = head[2:2 + _N_INPUTS]
        self._time = float(head[0])
        self._initialised = head[1] == 1.0
        self._forces_stale = self._wear_stale = self._linearisation_stale = True
        self._derivatives_read = head[-2] != 0.0

    @staticmethod
    def _fmu_state_to_bytes(state):
        return bytes(state)

    @staticmethod
    def _fmu_state_from_bytes(data):
        return bytes(data)
