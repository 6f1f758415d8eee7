"""pythonfmu slave ``ClearanceWearJoint``: a thin FMI 2.0 Co-Simulation adapter to one
:class:`wearjoint.ClearanceJoint` (contract: docs/model.md §5).

* Variables come from :mod:`wearjoint.fmu_variables`, registered in its order
  (value reference = position in ``fmu_variables(n_points)``).
* Outputs are direct feed-through: forces are evaluated lazily from the current
  inputs at the first getReal after a change (one evaluation per input set).
* getReal reads each value where it lives (the joint's result array, its wear
  profile, or this slave's own store of inputs, parameters and wear summary)
  through a read plan built once per distinct value-reference list; setReal of
  all 12 inputs in value-reference order is one array write.
* ``doStep(t, h)`` advances wear and contact memory with the inputs held at the
  start of the step (left-endpoint convention), then outputs belong to the new
  state at the same inputs.
* Parameters are read at exitInitializationMode and are fixed afterwards; the
  numba kernels are compiled there too.
* Errors never raise out of pythonfmu unguarded: see :meth:`_abort_call`.  The
  FMU's binary is a status shim (fmu_src/status_shim.c) in front of pythonfmu's:
  errors flagged to it come out as fmi2Error (pythonfmu alone gives fmi2Fatal).
* Non-finite inputs: getReal of a force output fails (fmi2Error) and doStep is
  refused (fmi2Discard, state unchanged); both log the inputs by name.  Finite
  inputs set afterwards make the instance usable again.
* Native path: once initialised, the slave attaches its arrays and the cfuncs of
  :mod:`wearjoint.native` to the status shim, which then answers setReal of
  finite inputs, getReal of everything but the wear summary, and doStep without
  entering Python (same kernels, same arrays).  The staleness flags and the time
  live in ``_flags``, shared with the shim; clearing its native flag (non-finite
  inputs, not initialised) sends every call here.

Built by ``wearjoint build-fmu`` (wearjoint/fmu_build.py), which fixes n_points in
resources/wearjoint_fmu.json.
"""
import contextlib
import ctypes
import functools
import json
import math
import sys
import typing
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
    from wearjoint.fmu import variables as fv
    from wearjoint.core import state_format
    from wearjoint.joint import check_state_values, read_state_bytes, state_bytes
    from wearjoint.fmu import entry_points as native

_RESULT_INDEX = fv.RESULT_SLOTS

# FMU state: the state format of ClearanceJoint (docs/model.md), contents "FMU instance": its head is
# the time [s], 1.0 if initialised, the inputs and the parameters (fv.PARAMETERS order)
_N_INPUTS = len(fv.INPUTS)
_ALL_INPUT_VRS = list(range(_N_INPUTS))   # value references of the inputs, in order

# Where getReal finds a variable's value (see _ReadPlan); the shim's SOURCE_* (-1: ask the slave).
_FROM_SLAVE, _FROM_STORE, _FROM_RESULT, _FROM_WEAR_DEPTH = -1, 0, 1, 2
# _flags, shared with the status shim (its FLAG_*)
_FLAG_NATIVE, _FLAG_FORCES_STALE, _FLAG_WEAR_SUMMARY_STALE, _FLAG_TIME = range(4)
_WEAR_SUMMARY_NAMES = fv.WEAR_SUMMARY_NAMES
_MAX_READ_PLANS = 64   # distinct getReal value-reference lists remembered per instance

# Objects pythonfmu 0.7 releases once too often after a Python exception (see _abort_call).
_OVER_RELEASED = []
# The status shim, relative to the FMU's root folder (the parent of its resources folder).
_SHIM_BINARY = Path("binaries", "linux64", f"{fv.MODEL_NAME}.so")


@functools.lru_cache(maxsize=None)
def _shim(resources: str):
    """The status shim (ctypes), or None if this FMU has none.

    dlopen of the shim's path returns the library the host already loaded.
    """
    try:
        shim = ctypes.CDLL(str(Path(resources).parent / _SHIM_BINARY))
        shim.wearjoint_shim_flag_error  # noqa: B018 - present in every shim
    except (OSError, AttributeError):
        return None
    return shim


_F64P = ctypes.POINTER(ctypes.c_double)


class _NativePath(ctypes.Structure):
    """The shim's NativePath (fmu_src/status_shim.c): arrays by address, cfuncs by address."""

    _fields_ = [("flags", _F64P), ("store", _F64P), ("read_source", ctypes.POINTER(ctypes.c_int32)),
                ("read_index", ctypes.POINTER(ctypes.c_int32)), ("n_variables", ctypes.c_uint32),
                ("n_inputs", ctypes.c_uint32), ("joint_parameters", _F64P), ("cos_phi", _F64P), ("sin_phi", _F64P),
                ("wear_depth", _F64P), ("block_min", _F64P), ("memory", _F64P), ("result", _F64P),
                ("mask", ctypes.c_void_p), ("work", _F64P), ("n_points", ctypes.c_int64),
                ("n_blocks", ctypes.c_int64),
                ("evaluate", ctypes.c_void_p), ("advance", ctypes.c_void_p)]


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
    scratch.advance_array(kinematics[0:3], kinematics[3:6], kinematics[6:9], kinematics[9:12], 0.0)
    scratch.worn_volume_m3  # noqa: B018 - compiles worn_area
    scratch.state_from_bytes(scratch.state_to_bytes())   # getFMUstate, setFMUstate


class _ReadPlan(typing.NamedTuple):
    """How getReal gathers the values of one value-reference list.

    ``gathers``: (source, positions in the answer, indices in the source) per source
    read (_FROM_*); ``force_names``: the force outputs asked for (they need an
    evaluation of the current inputs); ``reads_joint``: a joint array is read;
    ``reads_wear_summary``: max_wear_depth or worn_volume is asked for.
    """

    n_values: int
    gathers: tuple
    force_names: tuple
    reads_joint: bool
    reads_wear_summary: bool


class _SharedFlag:
    """A boolean attribute of the slave kept in ``_flags[index]`` (1.0 / 0.0), where the shim reads it."""

    def __init__(self, index: int):
        self.index = index

    def __get__(self, slave, owner=None) -> bool:
        return slave._flags[self.index] != 0.0

    def __set__(self, slave, value: bool) -> None:
        slave._flags[self.index] = 1.0 if value else 0.0


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


class ClearanceWearJoint(Fmi2Slave):
    """FMI 2.0 Co-Simulation slave holding one ClearanceJoint (see the module docstring)."""

    author = "wearjoint"
    description = ("Planar revolute clearance joint with a wearing bushing (Archard wear, "
                   "Lankarani-Nikravesh contact, Ambrosio friction). Inputs: kinematics of the pin "
                   "and bushing bodies; outputs: forces (direct feed-through) and the wear profile.")
    version = __version__

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        n_points = self.n_points = _built_n_points(self.resources)
        variables = fv.fmu_variables(n_points)
        self._names = [v.name for v in variables]
        vr_of = {name: vr for vr, name in enumerate(self._names)}
        self._reals = np.zeros(len(variables))   # store: inputs, Real parameters, wear summary
        self._integers = {}
        self._parameter_vrs = {vr_of[p.variable.name]: p.variable.name for p in fv.PARAMETERS}
        self._real_parameter_vrs = frozenset(vr_of[p.variable.name] for p in fv.PARAMETERS
                                             if p.variable.type == fv.REAL)
        self._integer_parameter_vrs = frozenset(vr_of[p.variable.name] for p in fv.PARAMETERS
                                                if p.variable.type == fv.INTEGER)
        self._n_points_vr = vr_of[fv.N_POINTS_NAME]
        for vr, v in enumerate(variables):
            self._register(vr, v)
        self._inputs = self._reals[:_N_INPUTS]
        self._pin_position, self._pin_velocity = self._inputs[0:3], self._inputs[3:6]
        self._bushing_position, self._bushing_velocity = self._inputs[6:9], self._inputs[9:12]
        self._max_wear_vr, self._worn_volume_vr = (vr_of[name] for name in _WEAR_SUMMARY_NAMES)
        # (source, index) per value reference for getReal; None for Integer variables
        self._read_source = [None if v.type != fv.REAL else (_FROM_STORE, vr) for vr, v in enumerate(variables)]
        for name, index in _RESULT_INDEX.items():
            self._read_source[vr_of[name]] = (_FROM_RESULT, index)
        for z in range(n_points):
            self._read_source[vr_of[fv.wear_depth_name(z + 1)]] = (_FROM_WEAR_DEPTH, z)
        missing = [v.name for v in variables if v.causality == fv.OUTPUT and v.name not in _WEAR_SUMMARY_NAMES
                   and self._read_source[vr_of[v.name]][0] == _FROM_STORE]
        if missing:
            raise RuntimeError(f"outputs without a source in the joint: {', '.join(missing)}")
        self._read_plans = {}
        # the same map as arrays for the shim's native getReal (wear summary and Integers: ask the slave)
        self._native_read_source = np.array([_FROM_SLAVE if src is None else src[0] for src in self._read_source],
                                            dtype=np.int32)
        self._native_read_index = np.array([0 if src is None else src[1] for src in self._read_source],
                                           dtype=np.int32)
        self._native_read_source[[self._max_wear_vr, self._worn_volume_vr]] = _FROM_SLAVE
        self._flags = np.zeros(4)
        self._native_attached = False
        # the source arrays, indexed by _FROM_*; the joint's arrays once it is built
        self._sources = (self._reals, None, None)
        self._parameter_block = None   # the parameters of the joint as state bytes
        self._non_finite_input_vrs = set()
        self._initialised = False
        self._joint = None
        self._joint_parameters_used = None
        self._parameters_changed = True
        self._forces_stale = True
        self._wear_summary_stale = True

    # staleness flags and time, shared with the shim's native path
    _forces_stale = _SharedFlag(_FLAG_FORCES_STALE)
    _wear_summary_stale = _SharedFlag(_FLAG_WEAR_SUMMARY_STALE)

    @property
    def _time(self) -> float:
        return float(self._flags[_FLAG_TIME])

    @_time.setter
    def _time(self, value: float) -> None:
        self._flags[_FLAG_TIME] = value

    def _register(self, vr: int, v) -> None:
        kind = Real if v.type == fv.REAL else Integer
        if v.causality == fv.INPUT:
            extra = dict(causality=Fmi2Causality.input, variability=Fmi2Variability.continuous)
        elif v.causality == fv.OUTPUT:
            extra = dict(causality=Fmi2Causality.output, variability=Fmi2Variability.continuous,
                         initial=Fmi2Initial.calculated)
        elif v.causality == fv.PARAMETER:
            extra = dict(causality=Fmi2Causality.parameter, variability=Fmi2Variability.fixed,
                         initial=Fmi2Initial.exact)
        else:  # n_points: read-only
            extra = dict(causality=Fmi2Causality.local, variability=Fmi2Variability.constant,
                         initial=Fmi2Initial.exact)
        if kind is Real:
            self._reals[vr] = math.nan if v.start is None else v.start
        else:
            self._integers[vr] = v.start
        # values go through the overridden get_*/set_* below, never through pythonfmu getters
        self.register_variable(kind(v.name, description=v.description, **extra))
        if self.vars[vr].value_reference != vr:
            raise RuntimeError(f"variable {v.name} got value reference {self.vars[vr].value_reference}, expected {vr}")

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
        shim = _shim(self.resources) if self.resources is not None else None
        if shim is not None:
            shim.wearjoint_shim_flag_error()
        raise FmuCallFailed(message)

    def _log_error(self, message: str) -> None:
        # the FMI logger treats the message as a printf format
        self.log(message.replace("%", "%%"), Fmi2Status.error)

    def _name(self, vr: int) -> str:
        return self._names[vr] if 0 <= vr < len(self._names) else f"<no variable with valueReference {vr}>"

    # ------------------------------------------------------------- the joint
    def _parameter_values(self) -> dict:
        return {name: (int(self._integers[vr]) if vr in self._integers else float(self._reals[vr]))
                for vr, name in self._parameter_vrs.items()}

    def _ensure_joint(self) -> None:
        """(Re)build the joint if a parameter was set to a new value since it was built."""
        if not self._parameters_changed:
            return
        values = self._parameter_values()
        if values != self._joint_parameters_used:
            try:
                params = fv.joint_parameters_from_fmi(values, self.n_points)
            except ParameterError as exc:
                self._abort_call(f"invalid FMU parameter: {exc}")
            with _scipy_hidden():
                joint = self._joint = ClearanceJoint(params)
                _compile_kernels(params)
            self._sources = (self._reals, joint.result, joint.wear_depth)
            self._joint_parameters_used = values
            self._parameter_block = np.array(list(values.values()), dtype=float).tobytes()
            self._forces_stale = self._wear_summary_stale = True
            self._attach_native()
        self._parameters_changed = False

    def _attach_native(self) -> None:
        """Hand the joint's arrays and the native kernels to the status shim (if this FMU has one)."""
        shim = _shim(self.resources) if self.resources is not None else None
        if shim is None or not hasattr(shim, "wearjoint_shim_attach_native"):
            return
        joint = self._joint

        def pointer(array, kind=_F64P):
            return array.ctypes.data_as(kind)

        path = _NativePath(
            flags=pointer(self._flags), store=pointer(self._reals),
            read_source=pointer(self._native_read_source, ctypes.POINTER(ctypes.c_int32)),
            read_index=pointer(self._native_read_index, ctypes.POINTER(ctypes.c_int32)),
            n_variables=len(self._names), n_inputs=_N_INPUTS, joint_parameters=pointer(joint.parameter_vector),
            cos_phi=pointer(joint.cos_phi), sin_phi=pointer(joint.sin_phi), wear_depth=pointer(joint.wear_depth),
            block_min=pointer(joint.block_min), memory=pointer(joint.memory), result=pointer(joint.result),
            mask=joint._mask.ctypes.data, work=pointer(joint.work), n_points=joint.wear_depth.size,
            n_blocks=joint.block_min.size,
            evaluate=native.evaluate_native.address, advance=native.advance_native.address)
        self._native_attached = shim.wearjoint_shim_attach_native(ctypes.byref(path)) == 0
        self._sync_native_flag()

    def _sync_native_flag(self) -> None:
        """Let the shim answer the hot calls natively only while that is exactly what this slave would do."""
        allowed = self._native_attached and self._initialised and not self._non_finite_input_vrs
        self._flags[_FLAG_NATIVE] = 1.0 if allowed else 0.0

    def _non_finite_inputs(self) -> str:
        return ", ".join(f"{self._names[vr]}={float(self._reals[vr])!r}" for vr in sorted(self._non_finite_input_vrs))

    def _note_input_finiteness(self, vrs, values) -> None:
        for vr, value in zip(vrs, values):
            if math.isfinite(value):
                self._non_finite_input_vrs.discard(vr)
            else:
                self._non_finite_input_vrs.add(vr)

    def _evaluate_forces(self, plan: _ReadPlan) -> None:
        if self._non_finite_input_vrs:
            self._abort_call(f"getReal of {', '.join(plan.force_names)}: undefined for non-finite inputs "
                             f"({self._non_finite_inputs()})")
        self._joint.evaluate_array(self._pin_position, self._pin_velocity,
                                   self._bushing_position, self._bushing_velocity)
        self._forces_stale = False

    def _refresh_wear_summary(self) -> None:
        joint = self._joint
        self._reals[self._max_wear_vr] = joint.max_wear_depth_m
        self._reals[self._worn_volume_vr] = joint.worn_volume_m3
        self._wear_summary_stale = False

    def _read_plan(self, vrs: tuple) -> _ReadPlan:
        """The plan for ``vrs`` (remembered for the next getReal of the same list)."""
        n_variables = len(self._names)
        bad = [self._name(vr) for vr in vrs if not 0 <= vr < n_variables or self._read_source[vr] is None]
        if bad:
            self._abort_call(f"getReal: not Real variables: {', '.join(bad)}")
        by_source = {}
        for position, vr in enumerate(vrs):
            source, index = self._read_source[vr]
            positions, indices = by_source.setdefault(source, ([], []))
            positions.append(position)
            indices.append(index)
        plan = _ReadPlan(
            n_values=len(vrs),
            gathers=tuple((source, np.array(positions), np.array(indices))
                          for source, (positions, indices) in by_source.items()),
            force_names=tuple(self._names[vr] for vr in vrs if self._read_source[vr][0] == _FROM_RESULT),
            reads_joint=not by_source.keys() <= {_FROM_STORE},
            reads_wear_summary=self._max_wear_vr in vrs or self._worn_volume_vr in vrs)
        if len(self._read_plans) < _MAX_READ_PLANS:
            self._read_plans[vrs] = plan
        return plan

    # ------------------------------------------------------------- FMI hooks
    @_guarded
    def setup_experiment(self, start_time, stop_time=None, tolerance=None):
        self._time = float(start_time)

    @_guarded
    def exit_initialization_mode(self):
        self._ensure_joint()  # builds the joint from the final parameters, compiles the kernels
        self._initialised = True
        self._sync_native_flag()

    @_guarded
    def do_step(self, current_time, step_size):
        if self._non_finite_input_vrs:
            self._log_error(f"doStep at t={current_time!r} s rejected: non-finite inputs "
                            f"({self._non_finite_inputs()})")
            return False
        if not 0.0 <= step_size < math.inf:
            self._log_error(f"doStep rejected: step size {step_size!r} s is not a finite value >= 0")
            return False
        self._ensure_joint()
        if self._joint.advance_array(self._pin_position, self._pin_velocity,
                                     self._bushing_position, self._bushing_velocity, step_size):
            self._wear_summary_stale = True
        self._time = current_time + step_size
        self._forces_stale = True
        return True

    @_guarded
    def get_real(self, vrs):
        key = tuple(vrs)
        plan = self._read_plans.get(key) or self._read_plan(key)
        if plan.reads_joint or plan.reads_wear_summary:
            self._ensure_joint()
            if plan.force_names and self._forces_stale:
                self._evaluate_forces(plan)
            if plan.reads_wear_summary and self._wear_summary_stale:
                self._refresh_wear_summary()
        sources = self._sources
        if len(plan.gathers) == 1:   # one source: its indices are the answer, in order
            source, _, indices = plan.gathers[0]
            return sources[source].take(indices).tolist()
        values = np.empty(plan.n_values)
        for source, positions, indices in plan.gathers:
            values[positions] = sources[source][indices]
        return values.tolist()

    @_guarded
    def set_real(self, vrs, values):
        if vrs == _ALL_INPUT_VRS:   # the master's call every step: one array write
            self._inputs[:] = values
            if not math.isfinite(sum(values)):   # non-finite, or finite values whose sum overflows
                self._note_input_finiteness(vrs, values)
            elif self._non_finite_input_vrs:
                self._non_finite_input_vrs.clear()
        else:
            for vr, value in zip(vrs, values):
                if 0 <= vr < _N_INPUTS:
                    self._reals[vr] = value
                    self._note_input_finiteness((vr,), (value,))
                elif vr in self._real_parameter_vrs:
                    self._check_parameter_settable(vr)
                    self._reals[vr] = value
                    self._parameters_changed = True
                else:
                    self._abort_call(f"setReal: variable {self._name(vr)} cannot be set")
        self._forces_stale = True
        self._sync_native_flag()

    @_guarded
    def get_integer(self, vrs):
        bad = [self._name(vr) for vr in vrs if vr not in self._integers]
        if bad:
            self._abort_call(f"getInteger: not Integer variables: {', '.join(bad)}")
        return [self._integers[vr] for vr in vrs]

    @_guarded
    def set_integer(self, vrs, values):
        for vr, value in zip(vrs, values):
            if vr == self._n_points_vr:
                if value != self.n_points:
                    self._abort_call(f"n_points is fixed at {self.n_points} when the FMU is built; "
                                     f"rebuild it for {value} points (wearjoint build-fmu --n-points {value})")
            elif vr in self._integer_parameter_vrs:
                self._check_parameter_settable(vr)
                self._integers[vr] = int(value)
                self._parameters_changed = True
            else:
                self._abort_call(f"setInteger: variable {self._name(vr)} cannot be set")
        self._forces_stale = True

    def _check_parameter_settable(self, vr: int) -> None:
        if self._initialised:
            self._abort_call(f"parameter {self._names[vr]} is fixed: set it before exitInitializationMode")

    @_guarded
    def get_boolean(self, vrs):
        self._abort_call(f"getBoolean: this FMU has no Boolean variables (asked for {list(vrs)})")

    @_guarded
    def set_boolean(self, vrs, values):
        self._abort_call(f"setBoolean: this FMU has no Boolean variables (asked for {list(vrs)})")

    @_guarded
    def get_string(self, vrs):
        self._abort_call(f"getString: this FMU has no String variables (asked for {list(vrs)})")

    @_guarded
    def set_string(self, vrs, values):
        self._abort_call(f"setString: this FMU has no String variables (asked for {list(vrs)})")

    # ------------------------------------------------------------- FMU state
    # The state object is the serialised bytes themselves (ClearanceJoint's state format): exact,
    # immutable, and getFMUstate / serializeFMUstate share one code path; setFMUstate checks it.
    @_guarded
    def _get_fmu_state(self):
        self._ensure_joint()
        joint = self._joint
        head = np.concatenate(([self._time, 1.0 if self._initialised else 0.0], self._inputs,
                               np.frombuffer(self._parameter_block)))
        return state_bytes(state_format.CONTENTS_FMU, head, joint.memory, joint.wear_depth)

    @_guarded
    def _set_fmu_state(self, state):
        try:
            head, memory, wear_depth = read_state_bytes(state, state_format.CONTENTS_FMU, fv.STATE_HEAD_SIZE,
                                                        self.n_points)
            parameters = head[2 + _N_INPUTS:]
            values = {name: int(v) if vr in self._integers and v.is_integer() else v
                      for (vr, name), v in zip(self._parameter_vrs.items(), parameters.tolist())}
            check_state_values(head, memory, wear_depth, fv.joint_parameters_from_fmi(values, self.n_points))
        except ParameterError as exc:
            self._abort_call(f"setFMUstate: {exc}")
        time, initialised = head[:2]
        if parameters.tobytes() != self._parameter_block or self._parameters_changed:
            for vr, value in zip(self._parameter_vrs, parameters.tolist()):
                if vr in self._integers:
                    self._integers[vr] = int(value)
                else:
                    self._reals[vr] = value
            self._parameters_changed = True
            self._ensure_joint()
        joint = self._joint
        inputs = head[2:2 + _N_INPUTS].tolist()
        self._inputs[:] = inputs
        self._non_finite_input_vrs.clear()
        if not math.isfinite(sum(inputs)):
            self._note_input_finiteness(_ALL_INPUT_VRS, inputs)
        joint.set_state(JointState(wear_depth, memory))
        self._time = time
        self._initialised = initialised == 1.0
        self._forces_stale = self._wear_summary_stale = True
        self._sync_native_flag()

    @staticmethod
    def _fmu_state_to_bytes(state):
        return bytes(state)

    @staticmethod
    def _fmu_state_from_bytes(data):
        return bytes(data)
