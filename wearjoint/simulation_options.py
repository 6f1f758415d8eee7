"""How the monolithic engine integrates (:class:`SimulationOptions`) and the wear's step limit, without the engine
(:mod:`wearjoint.simulate`): the command line's options are read without importing numba."""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from .parameters import MAX_WEAR_STEP_S, JointParameters, ParameterError, SliderCrankParameters, finite, require

INTEGRATORS = ("rk4", "dopri", "gear")
GEAR_SOLVERS = ("cvode", "scipy")
GEAR_JACOBIANS = ("exact", "numerical")


NO_WEAR_MAX_STEP_S = 1e-4   # largest adaptive step without wear [s]
# the default step's share lambda = k_f k_w F v dt with wear: at wear factor 2000 lambda 1.56 wore within 1 % of
# a 1 us run, lambda 4 (the limit an explicit step may take) 43 % deeper (docs/reference/model.md §7)
DEFAULT_WEAR_STEP_SHARE = 1.5
# DOPRI's default step with wear in contact [s]: at 3e-5 s (the wear-step limit) the own-mechanism example's
# impacts per revolution came out 9 % high (84.8 +- 1.3 against 77.8-80.1 at 1e-5 s, 5e-6 s and RK4 at
# 2.5 us, 16 starts x 10 revolutions), the paper's mechanism unchanged (docs/reference/model.md §7)
DOPRI_WEAR_CONTACT_STEP_S = 1e-5


def wear_step_limit_s(joint: JointParameters, mechanism: SliderCrankParameters | None = None,
                      share: float | None = None) -> float:
    """Longest step [s] of a run of ``joint`` in ``mechanism`` (default: the paper's) with wear:
    :meth:`JointParameters.max_wear_step_s` at the mechanism's bound on the sliding speed (``share``: a share
    below the limit's, e.g. DEFAULT_WEAR_STEP_SHARE); inf without wear."""
    return joint.max_wear_step_s((mechanism or SliderCrankParameters()).sliding_speed_bound_m_s(joint), share)


@dataclass(frozen=True)
class SimulationOptions:
    """How to integrate.  ``rk4``: fixed ``step_s``.  ``dopri``: adaptive
    Dormand-Prince 5(4) with ``rtol``/``atol_*`` and ``max_step_s``.  ``gear``: BDF (the
    paper's Gear method, for comparison) with the same tolerances and ``max_step_s`` (None: 1e-4 s, or
    when the joint wears the wear-step limit :func:`wear_step_limit_s`, which an explicit step with wear
    may not exceed, ``step_s`` of RK4 included; DOPRI with wear at most DOPRI_WEAR_CONTACT_STEP_S),
    by ``gear_solver`` (``cvode``: SUNDIALS CVODE through scikit-sundae; ``scipy``: scipy's BDF) with
    ``gear_jacobian`` (``exact``: the mechanism's Jacobian with the contact's,
    :mod:`wearjoint.core.slider_crank_jacobian`; ``numerical``: the solver's finite differences, which
    the ideal mechanism always uses).  ``onset_penetration_m``: how deep past a
    contact onset an adaptive step may end (event location, see
    ``core.integrators.integrate``).  ``free_flight_max_step_s`` (dopri): the largest step that starts with
    no contact active, where nothing wears (None: 1e-4 s with the default ``max_step_s``, else
    ``max_step_s``).  ``sample_dt_s``: spacing of the time series."""

    revolutions: float = 2.0
    integrator: str = "dopri"
    step_s: float = 1e-6
    rtol: float = 1e-6
    atol_position_m: float = 1e-9
    atol_velocity_m_s: float = 1e-5
    max_step_s: float | None = None
    free_flight_max_step_s: float | None = None
    min_step_s: float = 1e-10
    onset_penetration_m: float = 1e-8
    sample_dt_s: float = 1e-5
    ideal: bool = False
    gear_solver: str = "cvode"
    gear_jacobian: str = "exact"

    def __post_init__(self):
        require("revolutions", self.revolutions, finite("revolutions", self.revolutions) > 0.0, "> 0")
        require("integrator", self.integrator, self.integrator in INTEGRATORS, "one of " + ", ".join(INTEGRATORS))
        require("gear_solver", self.gear_solver, self.gear_solver in GEAR_SOLVERS, "one of " + ", ".join(GEAR_SOLVERS))
        require("gear_jacobian", self.gear_jacobian, self.gear_jacobian in GEAR_JACOBIANS,
                 "one of " + ", ".join(GEAR_JACOBIANS))
        positive = ("step_s", "rtol", "atol_position_m", "atol_velocity_m_s", "min_step_s", "sample_dt_s",
                    "onset_penetration_m") + tuple(name for name in ("max_step_s", "free_flight_max_step_s")
                                                    if getattr(self, name) is not None)
        for name in positive:
            require(name, getattr(self, name), finite(name, getattr(self, name)) > 0.0, "> 0")
        largest = self.max_step_s or 1e-7                   # None: the wear-step limit, at least this
        require("min_step_s", self.min_step_s, self.min_step_s <= largest, f"<= max_step_s = {largest!r}")
        if self.free_flight_max_step_s is not None:
            require("free_flight_max_step_s", self.free_flight_max_step_s,
                     self.free_flight_max_step_s >= self.min_step_s, f">= min_step_s = {self.min_step_s!r}")

    def for_joint(self, joint: JointParameters, mechanism: SliderCrankParameters | None = None) -> "SimulationOptions":
        """These options for a run of ``joint`` in ``mechanism``: the default ``max_step_s`` resolved, an
        explicit step above the wear-step limit (:func:`wear_step_limit_s`) refused when the joint wears."""
        limit = wear_step_limit_s(joint, mechanism) if not self.ideal else math.inf
        if self.max_step_s is None:
            default = wear_step_limit_s(joint, mechanism, DEFAULT_WEAR_STEP_SHARE) if not self.ideal else math.inf
            if self.integrator == "dopri" and default < math.inf:
                default = min(default, DOPRI_WEAR_CONTACT_STEP_S)
            return dataclasses.replace(self, max_step_s=min(default, NO_WEAR_MAX_STEP_S),
                                       free_flight_max_step_s=self.free_flight_max_step_s or NO_WEAR_MAX_STEP_S)
        name, step = ("step_s", self.step_s) if self.integrator == "rk4" else ("max_step_s", self.max_step_s)
        if step > limit:
            raise ParameterError(f"{name}={step!r} is invalid with wear (wear_coefficient_m2_N * wear_factor = "
                                 f"{joint.wear_coefficient_m2_N * joint.wear_factor:.4g} m^2/N): allowed at most "
                                 f"{limit:.3g} s, a step's share k_f k_w F v dt of the penetration at most "
                                 f"{joint.wear_step_share:g} and at most {MAX_WEAR_STEP_S:g} s (docs/reference/model.md §7)")
        if self.free_flight_max_step_s is None:
            return dataclasses.replace(self, free_flight_max_step_s=self.max_step_s)
        return self

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)
