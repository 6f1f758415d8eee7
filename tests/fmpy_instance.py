"""fmpy instances of the joint FMU: starting an FMI 2.0 one (FMU2Slave or FMU2Model) with a joint's parameters;
:class:`Joint`, an instance of either FMI version and interface with uniform calls and its log messages (of
conftest.py's ``fmus``); :class:`Slave`, an FMI 2.0 Co-Simulation instance of either backend's FMU (of
conftest.py's ``fmu``) with its log messages, and :func:`contact_inputs`, inputs that press the pin into the
bushing."""
import collections
import itertools
import math
from ctypes import byref

import numpy as np
from fmpy.fmi2 import fmi2True, FMU2Model, FMU2Slave, defaultCallbacks, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE
from fmpy.fmi3 import FMU3Model, FMU3Slave, fmi3Boolean, fmi3Float64, fmi3True
from fmpy.logging import addLoggerProxy

from wearjoint import JointParameters, paper_joint
from wearjoint.fmu import variables as fv

JOINT = paper_joint()


def enter_initialisation(fmu, vr, params=None):
    """setupExperiment(0) and enterInitializationMode on the instantiated ``fmu``, then, if ``params``
    (JointParameters) is given, every FMU parameter reproducing it (Reals and Integers); ``vr``: the
    value references by name.  The caller exits Initialization Mode."""
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    if params is not None:
        reals, integers = fv.fmi_parameter_values_by_type(params)
        fmu.setReal([vr[k] for k in reals], list(reals.values()))
        fmu.setInteger([vr[k] for k in integers], list(integers.values()))


class Joint:
    """One fmpy instance of the joint FMU (FMI ``version``, ``kind`` 'cs' or 'me') with uniform calls and
    its log messages; ``start`` initialises it (Model Exchange: on to Continuous-Time Mode)."""

    def __init__(self, fmu: dict, version: int, kind: str, logging_on: bool = False):
        self.version, self.kind, self.vr, self.log = version, kind, fmu["vr"], []
        cls = {(2, "cs"): FMU2Slave, (2, "me"): FMU2Model, (3, "cs"): FMU3Slave, (3, "me"): FMU3Model}[version, kind]
        self.fmu = cls(guid=fmu["md"].guid, unzipDirectory=fmu["dir"], modelIdentifier=fv.MODEL_NAME,
                       instanceName=f"dd{version}{kind}")
        if version == 2:
            self._logger = fmi2CallbackLoggerTYPE(lambda env, name, status, category, text: self._keep(status, text))
            self._callbacks = fmi2CallbackFunctions(logger=self._logger, allocateMemory=defaultCallbacks.allocateMemory,
                                                    freeMemory=defaultCallbacks.freeMemory)
            self.fmu.instantiate(callbacks=self._callbacks, loggingOn=logging_on)
        else:
            self.fmu.instantiate(loggingOn=logging_on,
                                 logMessage=lambda env, status, category, text: self._keep(status, text))

    def _keep(self, status, text):
        self.log.append((status, text.decode()))

    def start(self, params=JOINT) -> "Joint":
        if self.version == 2:
            enter_initialisation(self.fmu, self.vr, params)
        else:
            self.fmu.enterInitializationMode()
            reals, enumerations = fv.fmi_parameter_values_by_type(params)
            self.fmu.setFloat64([self.vr[k] for k in reals], list(reals.values()))
            self.fmu.setInt64([self.vr[k] for k in enumerations], list(enumerations.values()))
        self.fmu.exitInitializationMode()
        if self.kind == "me":
            self.fmu.enterContinuousTimeMode()
        return self

    def restore(self, data: bytes) -> None:
        f = self.fmu
        state = f.deSerializeFMUstate(data) if self.version == 2 else f.deserializeFMUState(data)
        (f.setFMUstate if self.version == 2 else f.setFMUState)(state)
        (f.freeFMUstate if self.version == 2 else f.freeFMUState)(state)

    def set(self, names, values) -> None:
        (self.fmu.setReal if self.version == 2 else self.fmu.setFloat64)([self.vr[n] for n in names], list(values))

    def get(self, names, n_values=None) -> np.ndarray:
        vrs = [self.vr[n] for n in names]
        return np.array(self.fmu.getReal(vrs) if self.version == 2 else self.fmu.getFloat64(vrs, nValues=n_values))

    def derivative(self, unknowns, knowns, seed, n_values=None) -> np.ndarray:
        args = [self.vr[n] for n in unknowns], [self.vr[n] for n in knowns], list(seed)
        return np.array(self.fmu.getDirectionalDerivative(*args) if self.version == 2
                        else self.fmu.getDirectionalDerivative(*args, nSensitivity=n_values))

    def do_step(self, t: float, h: float) -> int:
        """Co-Simulation doStep from t over h [s]: its status (fmpy raises above a warning)."""
        f = self.fmu
        if self.version == 2:
            return f.fmi2DoStep(f.component, t, h, fmi2True)
        flags, last_time = [fmi3Boolean() for _ in range(3)], fmi3Float64()
        return f.fmi3DoStep(f.component, t, h, fmi3True, *(byref(flag) for flag in flags), byref(last_time))

    def errors(self) -> str:
        return "\n".join(text for status, text in self.log if status >= 3)

    def free(self) -> None:
        self.fmu.freeInstance()


# ------------------------------------------------------------- Slave: one FMI 2.0 Co-Simulation instance
FMI_DISCARD, FMI_ERROR, FMI_FATAL = 2, 3, 4
INPUT_NAMES = [v.name for v in fv.INPUTS]
FORCE_NAMES = ["pin_force_x", "pin_force_y", "pin_torque", "bushing_force_x", "bushing_force_y", "bushing_torque"]
SCALAR_NAMES = [v.name for v in fv.SCALAR_OUTPUTS]
P = JointParameters()


def rotate(angle, x, y):
    c, s = math.cos(angle), math.sin(angle)
    return c * x - s * y, s * x + c * y


def contact_inputs(depth=5e-6, direction=1.0, pin_omega=10.0, bushing_x=0.2, params=P):
    """Inputs with the pin centre at clearance + ``depth`` from the bushing centre along
    the global angle ``direction`` (for the joint ``params``); both bodies rotated, the pin spinning
    about its resting centre."""
    bushing_angle, pin_angle = 0.3, 0.7
    bx, by = rotate(bushing_angle, *params.bushing_offset_m)
    centre = (bushing_x + bx, 0.05 + by)
    e = params.clearance_m + depth
    pin_centre = (centre[0] + e * math.cos(direction), centre[1] + e * math.sin(direction))
    px, py = rotate(pin_angle, *params.pin_offset_m)
    return [pin_centre[0] - px, pin_centre[1] - py, pin_angle, pin_omega * py, -pin_omega * px, pin_omega,
            bushing_x, 0.05, bushing_angle, 0.0, 0.0, 0.0]


# fmpy's native logger proxy (it formats the printf-style message) keeps ONE logger per
# process, so all instances share this one and messages are routed by instance name.
LOGS = collections.defaultdict(list)
_LOGGER = fmi2CallbackLoggerTYPE(
    lambda env, instance, status, category, message: LOGS[instance.decode()].append((status, message.decode())))
CALLBACKS = fmi2CallbackFunctions(logger=_LOGGER, allocateMemory=defaultCallbacks.allocateMemory,
                                  freeMemory=defaultCallbacks.freeMemory)
addLoggerProxy(byref(CALLBACKS))
_INSTANCE_NUMBERS = itertools.count()


class Slave:
    """One fmpy FMU2Slave instance (unique instance name) with its log messages as (status, text)."""

    def __init__(self, fmu, name, parameters=None, integers=None, logging_on=True, stop_time=None):
        self.vr = fmu["vr"]
        name = f"{name}_{next(_INSTANCE_NUMBERS)}"
        self.log = LOGS[name]
        md = fmu["md"]
        self.fmu = FMU2Slave(guid=md.guid, unzipDirectory=fmu["dir"],
                             modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        self.fmu.instantiate(callbacks=CALLBACKS, loggingOn=logging_on)
        self.start(parameters, integers, stop_time)

    def start(self, parameters=None, integers=None, stop_time=None):
        """setupExperiment (from 0, to ``stop_time`` where given), enterInitializationMode and the given parameter
        values."""
        self.fmu.setupExperiment(startTime=0.0, stopTime=stop_time)
        self.fmu.enterInitializationMode()
        if parameters:
            self.fmu.setReal([self.vr[k] for k in parameters], list(parameters.values()))
        if integers:
            self.fmu.setInteger([self.vr[k] for k in integers], list(integers.values()))
        return self

    def initialise(self):
        self.fmu.exitInitializationMode()
        return self

    def set_inputs(self, values):
        self.fmu.setReal([self.vr[n] for n in INPUT_NAMES], list(values))

    def get(self, names):
        return np.array(self.fmu.getReal([self.vr[n] for n in names]))

    def errors(self):
        return [text for status, text in self.log if status >= FMI_ERROR]

    def assert_failed_with_error(self, failure, *words):
        """The call failed with fmi2Error, logged (status error, no fatal) with all ``words``."""
        assert failure.value.status == FMI_ERROR
        assert any(all(w in text for w in words) for status, text in self.log if status == FMI_ERROR), self.log
        assert not any(status == FMI_FATAL for status, _ in self.log), self.log

    def free(self):
        self.fmu.freeInstance()
