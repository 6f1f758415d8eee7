"""fmpy instances of the joint FMU: starting an FMI 2.0 one (FMU2Slave or FMU2Model) with a joint's parameters;
:class:`Joint`, an instance of either FMI version and interface with uniform calls and its log messages (of
conftest.py's ``fmus``)."""
from ctypes import byref

import numpy as np
from fmpy.fmi2 import fmi2True, FMU2Model, FMU2Slave, defaultCallbacks, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE
from fmpy.fmi3 import FMU3Model, FMU3Slave, fmi3Boolean, fmi3Float64, fmi3True

from wearjoint import paper_joint
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
