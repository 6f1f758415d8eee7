"""One instance of the ``ClearanceWearJoint`` FMU as a co-simulation master uses it.

:class:`FmuInstance` loads the FMU with fmpy (any backend: native or pythonfmu),
sets the joint's parameters, initialises it and hands out its raw FMI functions
as C function pointers (Model Exchange) or addresses (co-simulation), so that a compiled master loop calls ``fmi2DoStep`` /
``fmi2SetReal`` / ``fmi2GetReal`` and the FMU-state functions without Python in
between.  FMU errors raise :class:`FmuError` carrying the FMU's log.
fmpy is imported only when an instance is made (``import wearjoint`` stays light).
"""
from __future__ import annotations

import ctypes
import shutil
from pathlib import Path

import numpy as np

from ..parameters import JointParameters, ParameterError
from . import variables as fv
from .extracted import extracted_fmu
from .fmi import (
    COMPLETED_STEP_CALL, COMPONENT_CALL, EVENT_INDICATORS_CALL,
    FMI_DISCARD, FMI_WARNING, REAL_VALUES_CALL, SET_TIME_CALL, STATUS_CALL, FmuError, c_function, function_address,
    raise_failed_call,
)

INPUT_NAMES = tuple(v.name for v in fv.INPUTS)   # pin x, y, angle, vx, vy, omega, then bushing
N_INPUTS = len(INPUT_NAMES)
# the FMI functions a co-simulation master's compiled loop calls, by address (FmuInstance.loop_functions)
LOOP_FUNCTIONS = ("fmi2DoStep", "fmi2SetReal", "fmi2GetReal", "fmi2GetFMUstate", "fmi2SetFMUstate", "fmi2FreeFMUstate")


class OwnsFmuInstance:
    """An engine that owns one :class:`FmuInstance` (``_instance``, None once freed): :meth:`close`
    frees it; ``with`` closes it."""

    _instance: FmuInstance | None = None

    def close(self) -> None:
        """Free the FMU instance (idempotent)."""
        if self._instance is not None:
            self._instance.close()
            self._instance = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


class FmuInstance:
    """One initialised instance of the joint FMU: fmpy's FMU2Slave (co-simulation) or FMU2Model
    (model exchange, left in continuous-time mode), its raw FMI functions (for compiled
    loops), its log.

    ``inputs`` / ``outputs``: float64 arrays (e.g. views of a master's buffer) that
    :meth:`exchange` and the compiled loops' setReal / getReal read and write directly;
    ``output_names`` says which FMU output goes where (the inputs are :data:`INPUT_NAMES`).
    """

    def __init__(self, fmu_path: Path, joint: JointParameters, inputs: np.ndarray, outputs: np.ndarray,
                 output_names: tuple[str, ...], interface: str = "co-simulation"):
        from fmpy.fmi2 import (FMU2Model, FMU2Slave, defaultCallbacks, fmi2CallbackFunctions,
                               fmi2CallbackLoggerTYPE, fmi2FMUstate, fmi2Integer, fmi2Real, fmi2ValueReference)

        self.unzip_dir, md, self._owns_unzip_dir = extracted_fmu(fmu_path)
        try:   # the shared extraction stays; a folder this instance owns goes with a refused FMU
            self.interface = interface
            kind = md.coSimulation if interface == "co-simulation" else md.modelExchange
            if md.fmiVersion != "2.0":
                raise ParameterError(f"parameter fmu_path={str(fmu_path)!r} is invalid: allowed an FMI 2.0 FMU (it "
                                     f"is FMI {md.fmiVersion}; this master takes FMI 2.0: build-fmu --fmi-version 2)")
            if md.modelName != fv.MODEL_NAME or kind is None:
                raise ParameterError(f"parameter fmu_path={str(fmu_path)!r} is invalid: "
                                     f"allowed a {fv.MODEL_NAME} FMU with the {interface} interface")
            self.vr = fv.value_references(md)
            built = next((int(v.start) for v in md.modelVariables if v.name == fv.N_POINTS_NAME), None)
            if built != joint.n_points:
                raise ParameterError(f"parameter n_points={joint.n_points!r} is invalid: allowed {built}, the bushing "
                                     f"points the FMU {fmu_path} was built for (run it with --n-points {built}, or "
                                     f"build one for {joint.n_points}: wearjoint build-fmu --n-points {joint.n_points})")
            if fv.wear_depth_name(joint.n_points) not in self.vr:
                raise ParameterError(f"parameter fmu_path={str(fmu_path)!r} is invalid: allowed an FMU with every "
                                     "profile point as an output (this master reads the whole profile; build-fmu "
                                     "--profile-stride 1)")
        except ParameterError:
            self._remove_unzip_dir()
            raise
        self.log: list[tuple[int, str]] = []
        # A plain ctypes logger (no fmpy logger proxy: that proxy is one per process).
        # pythonfmu passes the message as the format string with '%' doubled.
        self._logger = fmi2CallbackLoggerTYPE(
            lambda env, instance, status, category, message: self.log.append(
                (status, message.decode(errors="replace").replace("%%", "%"))))
        self._callbacks = fmi2CallbackFunctions(logger=self._logger, allocateMemory=defaultCallbacks.allocateMemory,
                                                freeMemory=defaultCallbacks.freeMemory)
        self.instantiated = False
        try:
            fmu_class = FMU2Slave if interface == "co-simulation" else FMU2Model
            self.fmu = fmu_class(guid=md.guid, unzipDirectory=self.unzip_dir, modelIdentifier=kind.modelIdentifier,
                                 instanceName="joint")
        except Exception as exc:  # fmpy raises a bare Exception (e.g. no binary for this platform)
            self._remove_unzip_dir()
            raise FmuError(f"FMU {fmu_path} cannot be loaded: {exc}") from None
        self.state_slot = np.zeros(1, dtype=np.uintp)   # the rollback snapshot (getFMUstate), 0 when none
        self._fmi2FMUstate = fmi2FMUstate
        dll = self.fmu.dll                     # fmpy has set argtypes/restype on these
        self.set_real = dll.fmi2SetReal
        self.get_real = dll.fmi2GetReal
        self.input_vrs = np.array([self.vr[n] for n in INPUT_NAMES], dtype=np.uint32)
        self.output_vrs = np.array([self.vr[n] for n in output_names], dtype=np.uint32)
        # ctypes arrays aliasing the master's buffer: the FMI calls read and write it directly
        self.inputs = (fmi2Real * N_INPUTS).from_buffer(inputs)
        self.outputs = (fmi2Real * len(output_names)).from_buffer(outputs)
        self._fmi2Real, self._fmi2Integer, self._fmi2ValueReference = fmi2Real, fmi2Integer, fmi2ValueReference
        n = self.n_points = joint.n_points
        wear_names = [fv.wear_depth_name(z) for z in range(1, n + 1)] + ["max_wear_depth", "worn_volume"]
        self.wear_vrs = (fmi2ValueReference * (n + 2))(*(self.vr[name] for name in wear_names))
        self.wear_values = (fmi2Real * (n + 2))()
        try:
            try:
                self.fmu.instantiate(callbacks=self._callbacks, loggingOn=True)
            except Exception as exc:  # fmpy raises a bare Exception here
                raise FmuError(f"FMU {fmu_path}: fmi2Instantiate failed ({exc}){self._log_tail()}") from None
            self.instantiated = True
            self.component = self.fmu.component
            self.check(dll.fmi2SetupExperiment(self.component, 0, 0.0, 0.0, 0, 0.0), "fmi2SetupExperiment", 0.0)
            self._set_parameters(joint)
            self.check(dll.fmi2EnterInitializationMode(self.component), "fmi2EnterInitializationMode", 0.0)
            self.check(dll.fmi2ExitInitializationMode(self.component), "fmi2ExitInitializationMode", 0.0)
            if interface == "model-exchange":   # the initial event iteration, then continuous time
                self.event_info = np.zeros(4)     # fmi2EventInfo (5 ints, a double)
                while True:
                    self.check(c_function(dll.fmi2NewDiscreteStates, STATUS_CALL)(self.component,
                                                                                  self.event_info.ctypes.data),
                               "fmi2NewDiscreteStates", 0.0)
                    if self.event_info.view(np.int32)[0] == 0:   # newDiscreteStatesNeeded
                        break
                self.check(dll.fmi2EnterContinuousTimeMode(self.component), "fmi2EnterContinuousTimeMode", 0.0)
        except BaseException:
            self.close()
            raise
        if interface == "model-exchange":
            self.loop_functions = None
            self.model_exchange_functions = (
                c_function(dll.fmi2SetTime, SET_TIME_CALL), c_function(dll.fmi2SetReal, REAL_VALUES_CALL),
                c_function(dll.fmi2GetReal, REAL_VALUES_CALL),
                c_function(dll.fmi2CompletedIntegratorStep, COMPLETED_STEP_CALL),
                c_function(dll.fmi2EnterEventMode, COMPONENT_CALL),
                c_function(dll.fmi2NewDiscreteStates, STATUS_CALL),
                c_function(dll.fmi2EnterContinuousTimeMode, COMPONENT_CALL),
                c_function(dll.fmi2GetEventIndicators, EVENT_INDICATORS_CALL))
            return
        self.loop_functions = (
            self.component, self.input_vrs, self.output_vrs, self.state_slot,
            *(function_address(getattr(dll, name)) for name in LOOP_FUNCTIONS))

    def _set_parameters(self, joint: JointParameters) -> None:
        real_values, integer_values = fv.fmi_parameter_values_by_type(joint)
        reals = [(self.vr[k], v) for k, v in real_values.items()]
        ints = [(self.vr[k], v) for k, v in integer_values.items()]
        for rows, value_type, function in ((reals, self._fmi2Real, self.set_real),
                                           (ints, self._fmi2Integer, self.fmu.dll.fmi2SetInteger)):
            vrs = (self._fmi2ValueReference * len(rows))(*(vr for vr, _ in rows))
            vals = (value_type * len(rows))(*(v for _, v in rows))
            self.check(function(self.component, vrs, len(rows), vals), function.__name__, 0.0)

    def _log_tail(self) -> str:
        errors = [text for status, text in self.log if status > FMI_WARNING] or [text for _, text in self.log[-3:]]
        return (": " + " | ".join(errors[-3:])) if errors else ""

    def check(self, status: int, call: str, t: float) -> None:
        """Raise FmuError (with the FMU's log) for a status worse than fmi2Warning, RunDiverged where the call
        refused the run's state (co-simulation: a doStep's fmi2Discard; Model Exchange: an accepted step's error)."""
        if status > FMI_WARNING:
            refused = (call == "fmi2DoStep" and status == FMI_DISCARD if self.interface == "co-simulation"
                       else call == "fmi2CompletedIntegratorStep")
            raise_failed_call(status, call, t, self._log_tail(), refused)

    def check_recorded(self, record, calls: tuple[str, ...]) -> None:
        """:meth:`check` of the failure a compiled loop recorded (:func:`wearjoint.fmu.loop_calls.failed_call`:
        the call's index in ``calls``, its status, its time), if any."""
        if record[0] != 0.0:
            self.check(int(record[1]), calls[int(record[0])], float(record[2]))

    def exchange(self, t: float) -> None:
        """setReal of the inputs, getReal of the outputs (both in the master's buffer)."""
        vr_pointer = ctypes.POINTER(self._fmi2ValueReference)
        self.check(self.set_real(self.component, self.input_vrs.ctypes.data_as(vr_pointer), N_INPUTS, self.inputs),
                   "fmi2SetReal", t)
        self.check(self.get_real(self.component, self.output_vrs.ctypes.data_as(vr_pointer), len(self.outputs),
                                 self.outputs), "fmi2GetReal", t)

    def wear(self, t: float) -> np.ndarray:
        """[wear_depth[1..N] ..., max_wear_depth, worn_volume] [m, m, m^3] (a copy)."""
        self.check(self.get_real(self.component, self.wear_vrs, len(self.wear_values), self.wear_values),
                   "fmi2GetReal", t)
        return np.array(self.wear_values)

    def max_wear_depth(self, t: float) -> float:
        value = self._fmi2Real()
        vr = self._fmi2ValueReference(self.vr["max_wear_depth"])
        self.check(self.get_real(self.component, ctypes.byref(vr), 1, ctypes.byref(value)), "fmi2GetReal", t)
        return value.value

    # -- FMU state
    def serialize(self, t: float) -> bytes:
        state = self._fmi2FMUstate()
        self.check(self.fmu.dll.fmi2GetFMUstate(self.component, ctypes.byref(state)), "fmi2GetFMUstate", t)
        try:
            return self.fmu.serializeFMUstate(state)
        except Exception as exc:  # fmpy's FMICallException
            raise FmuError(f"fmi2SerializeFMUstate failed at t={t:.9g} s ({exc}){self._log_tail()}") from None
        finally:
            self.fmu.fmi2FreeFMUstate(self.component, ctypes.byref(state))

    def deserialize(self, data: bytes, t: float) -> None:
        state = self._fmi2FMUstate()
        buffer = ctypes.create_string_buffer(data, len(data))
        self.check(self.fmu.dll.fmi2DeSerializeFMUstate(self.component, buffer, len(data), ctypes.byref(state)),
                   "fmi2DeSerializeFMUstate", t)
        try:
            self.check(self.fmu.dll.fmi2SetFMUstate(self.component, state), "fmi2SetFMUstate", t)
        finally:
            self.fmu.fmi2FreeFMUstate(self.component, ctypes.byref(state))

    def set_wear_profile(self, wear_depth_m, t: float) -> None:
        """Start from a worn bushing: the instance's state with its wear depths [m] replaced by ``wear_depth_m``
        (one per bushing point), through the FMU's own state format (get, serialise, rewrite, deserialise,
        set); the FMU checks the depths (finite, in [0, bushing radius]) and refuses others with an error."""
        from ..core.state_format import CONTENTS_FMU, state_size
        from ..joint import read_state_bytes, state_bytes

        depth = np.ascontiguousarray(wear_depth_m, dtype=float)
        n_points = self.n_points
        if depth.shape != (n_points,):
            raise ParameterError(f"parameter wear profile of {depth.size} points is invalid: allowed the FMU's "
                                 f"{n_points} bushing points")
        data = self.serialize(t)
        n_head = (len(data) - state_size(0, n_points)) // 8
        head, memory, _ = read_state_bytes(data, CONTENTS_FMU, n_head, n_points)
        self.deserialize(state_bytes(CONTENTS_FMU, head, memory, depth), t)

    def close(self) -> None:
        """Free the snapshot and the instance (terminate first), remove the extracted files.
        Safe to call twice; errors here are not raised (the instance is gone either way)."""
        if self.instantiated:
            self.instantiated = False
            if self.state_slot[0]:
                self.fmu.dll.fmi2FreeFMUstate(
                    self.component, ctypes.cast(self.state_slot.ctypes.data, ctypes.POINTER(self._fmi2FMUstate)))
                self.state_slot[0] = 0
            self.fmu.dll.fmi2Terminate(self.component)
            self.fmu.dll.fmi2FreeInstance(self.component)
        self._remove_unzip_dir()

    def _remove_unzip_dir(self) -> None:
        """Remove the extracted files if this instance owns them (not the shared extraction, :mod:`.extracted`)."""
        if self._owns_unzip_dir:
            shutil.rmtree(self.unzip_dir, ignore_errors=True)
