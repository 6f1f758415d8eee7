"""The slider-crank with the joint FMU's Model Exchange interface inside the monolithic integrator.

The mechanism and the joint are integrated together by the same integrator as ``wearjoint
simulate`` (:func:`wearjoint.core.integrators.integrate`), with the joint reached through the
FMU (:data:`wearjoint.cosim.fmu_joint.FmuJoint`): every stage evaluation is
``fmi2SetTime`` + ``fmi2SetReal`` of the 12 inputs + ``fmi2GetReal`` of the outputs, contact
onsets are located on the event indicator (the signed penetration) exactly as the monolithic
run locates them, and every accepted step ends with ``fmi2CompletedIntegratorStep`` (plus an
event iteration where a contact begins or ends).  There is no coupling error: with the same
options this reproduces the monolithic run step for step.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from ..core import layout as L
from ..core.integrators import integrate
from ..fmu.ensure import ensure_fmu
from ..fmu.fmi import DEFAULT_BACKEND, FmuError
from ..fmu.instance import N_INPUTS, FmuInstance, OwnsFmuInstance
from ..checks import RunStopped
from ..parameters import JointParameters, ParameterError, SliderCrankParameters, paper_joint
from ..results import RunParameters
from ..runner import run_engine
from ..simulate import Simulation, SimulationOptions
from ..simulation_options import check_run_arguments
from .fmu_joint import FMU_CALLS, FmuJoint
from .master_layout import OUTPUT_NAMES, OUTPUT_RESULT_INDEX


class ModelExchangeSimulation(OwnsFmuInstance):
    """The monolithic engine (:class:`wearjoint.simulate.Simulation`, composed) integrating the slider-crank with
    the joint in the FMU (Model Exchange): a :class:`wearjoint.runner.Engine`.  Call
    :meth:`~wearjoint.fmu.instance.OwnsFmuInstance.close` (or use ``with``) to free the FMU instance."""

    def __init__(self, joint: JointParameters | None = None, mechanism: SliderCrankParameters | None = None,
                 options: SimulationOptions | None = None, fmu_path=None, fmu_backend: str = DEFAULT_BACKEND,
                 initial_profile_m=None):
        check_run_arguments(joint, mechanism, options, SimulationOptions, fmu_path)
        options = options or SimulationOptions()
        if options.integrator == "gear" or options.ideal:
            raise ParameterError(f"parameter integrator={options.integrator!r} is invalid with the FMU's Model "
                                 "Exchange interface: allowed rk4 or dopri (no ideal joint)")
        if fmu_backend != "native":
            raise ParameterError(f"parameter fmu_backend={fmu_backend!r} is invalid with the Model Exchange "
                                 "interface: allowed native (the pythonfmu FMU is co-simulation only)")
        mechanism = mechanism or SliderCrankParameters()
        joint = joint or paper_joint(mechanism)
        self.fmu_path = ensure_fmu(joint.n_points, fmu_path, backend=fmu_backend)
        self.fmu_backend = fmu_backend
        self._io = np.zeros(N_INPUTS + len(OUTPUT_NAMES))
        self._instance = FmuInstance(self.fmu_path, joint, self._io[:N_INPUTS], self._io[N_INPUTS:], OUTPUT_NAMES,
                                       interface="model-exchange")
        try:
            # the in-process joint lends the FMU joint its parameter vector and result array (the integrators'
            # bookkeeping); the contact state at accepted points is the FMU's event indicator's
            self._engine = Simulation(joint, mechanism, options, initial_profile_m)
            in_process = self._engine.joint
            f = self._instance
            if initial_profile_m is not None:
                f.set_wear_profile(initial_profile_m, 0.0)
            self._fmu_joint = FmuJoint(f.component, *f.model_exchange_functions, f.input_vrs, f.output_vrs,
                                       OUTPUT_RESULT_INDEX.astype(np.int64), self._io, in_process.result,
                                       in_process.parameter_vector, np.zeros(L.N_MEMORY), np.zeros(1), f.event_info,
                                       np.zeros(2, dtype=np.int32), np.zeros(2, dtype=np.int64), np.zeros(3))
            self._engine.integrate_with(self._fmu_joint)
            self._check()
        except BaseException:
            self.close()
            raise

    # the engine's state, read through
    t = property(lambda self: self._engine.t)
    y = property(lambda self: self._engine.y)
    accepted = property(lambda self: self._engine.accepted)
    rejected = property(lambda self: self._engine.rejected)
    revolution_stats = property(lambda self: self._engine.revolution_stats)
    joint_parameters = property(lambda self: self._engine.joint_parameters)

    @property
    def events(self) -> tuple[int, int]:
        """Event iterations so far: (at contact onsets, at separations)."""
        return int(self._fmu_joint.events[0]), int(self._fmu_joint.events[1])

    def _check(self) -> None:
        self._instance.check_recorded(self._fmu_joint.failure, FMU_CALLS)   # an accepted step refused: the run diverged

    def warm_up(self) -> None:
        """Compile the integrator for the FMU joint without advancing (an empty interval)."""
        e = self._engine
        integrate(e.method_code, e.t, e.t, e.y.copy(), e.control.copy(), e.mode, e.mechanism.parameter_vector,
                  self._fmu_joint, e.body_forces.copy(), e.mechanism.workspace, e.dy.copy(), e.revolution_stats.copy(),
                  np.zeros((0, L.N_SAMPLE_COLUMNS)), e.track.copy())

    def advance_to(self, t_end: float, samples: np.ndarray) -> int:
        n = self._engine.advance_to(t_end, samples)
        try:
            self._check()
        except RunStopped as exc:    # a refused step: the samples before it kept
            raise type(exc)(str(exc), n) from None
        except FmuError as exc:      # a call failed (not a refused step): the run stops there, what came before kept
            raise RunStopped(str(exc), n) from None
        return n

    def wear_profile(self) -> tuple[np.ndarray, np.ndarray, float]:
        """(phi_deg, wear_depth_m, worn_volume_m3) read from the FMU (the bushing frame)."""
        values = self._instance.wear(self.t)
        n = self.joint_parameters.n_points
        return self._engine.joint.phi_deg, values[:n], float(values[n + 1])

    def max_wear_depth_m(self) -> float:
        return self._instance.max_wear_depth(self.t)

    def describe(self) -> tuple[RunParameters, dict]:
        """The monolithic engine's record naming the FMU and its interface (:class:`wearjoint.runner.Engine`)."""
        parameters, extra = self._engine.describe()
        details = {"fmu_interface": "model-exchange", "fmu": str(self.fmu_path), "fmu_backend": self.fmu_backend}
        return dataclasses.replace(parameters, engine="cosim", details=details), extra


def run_model_exchange(joint: JointParameters | None = None, mechanism: SliderCrankParameters | None = None,
                       options: SimulationOptions | None = None, fmu_path=None, progress: bool = True,
                       fmu_backend: str = DEFAULT_BACKEND, chunks_per_revolution: int = 8, initial_profile_m=None):
    """Simulate ``options.revolutions`` crank revolutions with the FMU's Model Exchange interface from the
    bushing's ``initial_profile_m`` (default: unworn); the run's record (as
    :func:`wearjoint.simulate.run_simulation`'s)."""
    check_run_arguments(joint, mechanism, options, SimulationOptions, fmu_path, chunks_per_revolution)
    o = options or SimulationOptions()
    return run_engine(lambda: ModelExchangeSimulation(joint, mechanism, o, fmu_path, fmu_backend, initial_profile_m),
                      o.revolutions, (mechanism or SliderCrankParameters()).period_s, o.sample_dt_s,
                      "cosim (model exchange)", progress, chunks_per_revolution)


__all__ = ["ModelExchangeSimulation", "run_model_exchange", "FmuError"]
