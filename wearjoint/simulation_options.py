"""How the monolithic engine integrates (:class:`SimulationOptions`) and the wear's step limit, without the engine
(:mod:`wearjoint.simulate`): the command line's options are read without importing numba."""
from __future__ import annotations

import dataclasses
import math
import os
import zipfile
from dataclasses import dataclass

from .checks import choice, flag, integer, of_type, positive
from .parameters import MAX_WEAR_STEP_S, JointParameters, ParameterError, SliderCrankParameters, require

INTEGRATORS = ("rk4", "dopri", "gear")
GEAR_SOLVERS = ("cvode", "scipy")
GEAR_JACOBIANS = ("exact", "numerical")
_CHOICES = {"integrator": INTEGRATORS, "gear_solver": GEAR_SOLVERS, "gear_jacobian": GEAR_JACOBIANS}


NO_WEAR_MAX_STEP_S = 1e-4   # largest adaptive step without wear [s]
# the default step's share lambda = k_f k_w F v dt with wear: at wear factor 2000 lambda 1.56 wore within 1 % of
# a 1 us run, lambda 4 (the limit an explicit step may take) 43 % deeper (docs/reference/model.md §7)
DEFAULT_WEAR_STEP_SHARE = 1.5
# DOPRI's default step with wear in contact [s]: at 3e-5 s (the wear-step limit) the own-mechanism example's
# impacts per revolution came out 9 % high (84.8 +- 1.3 against 77.8-80.1 at 1e-5 s, 5e-6 s and RK4 at
# 2.5 us, 16 starts x 10 revolutions), the paper's mechanism unchanged (docs/reference/model.md §7)
DOPRI_WEAR_CONTACT_STEP_S = 1e-5
# bounds no meaningful run passes (1e300 was taken: a tolerance that controls nothing; 1e9 chunks ran for minutes)
RTOL_RANGE = (1e-12, 0.1)
MAX_ATOL_POSITION_M = 1e-3
MAX_ATOL_VELOCITY_M_S = 1.0
MAX_CHUNKS_PER_REVOLUTION = 10_000
ONSET_CLEARANCE_SHARE = 0.1     # the deepest an adaptive step may end past a contact onset, in clearances


def wear_step_limit_s(joint: JointParameters, mechanism: SliderCrankParameters | None = None,
                      share: float | None = None) -> float:
    """Longest step [s] of a run of ``joint`` in ``mechanism`` (default: the paper's) with wear:
    :meth:`JointParameters.max_wear_step_s` at the mechanism's bound on the sliding speed (``share``: a share
    below the limit's, e.g. DEFAULT_WEAR_STEP_SHARE); inf without wear."""
    return joint.max_wear_step_s((mechanism or SliderCrankParameters()).sliding_speed_bound_m_s(joint), share)


def check_wear_step(name: str, step_s: float, joint: JointParameters,
                    mechanism: SliderCrankParameters | None = None) -> None:
    """ParameterError naming ``name`` unless ``step_s``, a step [s] that wears ``joint`` in ``mechanism``, is within
    the wear-step limit (:func:`wear_step_limit_s`, docs/reference/model.md §7)."""
    limit = wear_step_limit_s(joint, mechanism)
    if step_s > limit:
        raise ParameterError(f"parameter {name}={step_s!r} is invalid with wear (wear_coefficient_m2_N * wear_factor = "
                             f"{joint.wear_coefficient_m2_N * joint.wear_factor:.4g} m^2/N): allowed at most "
                             f"{limit:.3g} s (" + ("the longest step with wear" if limit >= MAX_WEAR_STEP_S else
                                                   "where a step's share k_f k_w F v dt of the penetration reaches "
                                                   f"{joint.wear_step_share:g}")
                             + "; docs/reference/model.md §7)")


def check_run_arguments(joint, mechanism, options, options_type: type, fmu_path=None,
                        chunks_per_revolution: int = 1) -> None:
    """ParameterError naming the first of a run's arguments of the wrong type (the parameter sets, the options: e.g.
    given in the wrong order), ``fmu_path`` neither None nor an FMU file (a zip archive), or ``chunks_per_revolution``
    no integer >= 1."""
    of_type("joint", joint, JointParameters, "the paper's joint in the mechanism, paper_joint(mechanism)")
    of_type("mechanism", mechanism, SliderCrankParameters, "the paper's")
    of_type("options", options, options_type, "the defaults")
    if fmu_path is not None:   # (is_zipfile would take an int for a file descriptor)
        path_like = isinstance(fmu_path, (str, os.PathLike))
        require("fmu_path", str(fmu_path) if path_like else fmu_path, path_like and _is_fmu(fmu_path),
                "an existing FMU file (.fmu: a zip archive with a modelDescription.xml)")
    integer("chunks_per_revolution", chunks_per_revolution, 1, MAX_CHUNKS_PER_REVOLUTION)


def _is_fmu(path) -> bool:
    """True if ``path`` is a zip archive with a modelDescription.xml at its root (any other zip ran into fmpy's
    FileNotFoundError)."""
    try:
        with zipfile.ZipFile(path) as archive:
            return "modelDescription.xml" in archive.namelist()
    except (OSError, zipfile.BadZipFile):
        return False


def check_run_span(options, joint: JointParameters, mechanism: SliderCrankParameters | None = None) -> None:
    """ParameterError unless a run of ``options`` (its ``revolutions``, ``sample_dt_s``, ``onset_penetration_m``)
    covers one sample interval of ``mechanism``'s revolution and locates contact onsets within ONSET_CLEARANCE_SHARE
    of ``joint``'s clearance (1e-300 revolutions ran and reported zeros; an onset 1e300 m deep located none)."""
    period = (mechanism or SliderCrankParameters()).period_s
    shortest = options.sample_dt_s / period
    require("revolutions", options.revolutions, options.revolutions >= shortest,
            f">= {shortest:.3g} (one sample interval, sample_dt_s = {options.sample_dt_s:g} s, of a {period:.4g} s "
            "revolution)")
    deepest = ONSET_CLEARANCE_SHARE * joint.clearance_m
    require("onset_penetration_m", options.onset_penetration_m, options.onset_penetration_m <= deepest,
            f"<= {deepest:.3g} m ({ONSET_CLEARANCE_SHARE:g} of the clearance {joint.clearance_m:.4g} m)")


@dataclass(frozen=True)
class SimulationOptions:
    """How to integrate.  ``rk4``: fixed ``step_s``.  ``dopri``: adaptive
    Dormand-Prince 5(4) with ``rtol``/``atol_*`` and ``max_step_s``.  ``gear``: BDF (the
    paper's Gear method, for comparison) with the same tolerances and ``max_step_s`` (None: 1e-4 s, or
    when the joint wears the wear-step limit :func:`wear_step_limit_s`, which an explicit step with wear
    may not exceed, ``step_s`` of RK4 included; DOPRI with wear at most DOPRI_WEAR_CONTACT_STEP_S),
    by ``gear_solver`` (``cvode``: SUNDIALS CVODE through scikit-sundae; ``scipy``: scipy's BDF) with
    ``gear_jacobian`` (``exact``: the mechanism's Jacobian with the contact's,
    :mod:`wearjoint.core.slider_crank_jacobian`, the crank-rod joint's only; ``numerical``: the solver's finite
    differences, which the ideal mechanism always uses; None: exact where there is one).  ``onset_penetration_m``: how deep past a
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
    gear_jacobian: str | None = None

    def __post_init__(self):
        """Every value checked (a real one an int, a float or a numpy real scalar, kept as a float; ``ideal`` a
        bool)."""
        for name in ("integrator", "gear_solver", "gear_jacobian"):
            if getattr(self, name) is not None or name != "gear_jacobian":    # None: exact where there is one
                choice(name, getattr(self, name), _CHOICES[name])
        object.__setattr__(self, "ideal", flag("ideal", self.ideal))
        for name in ("revolutions", "step_s", "rtol", "atol_position_m", "atol_velocity_m_s", "min_step_s",
                     "sample_dt_s", "onset_penetration_m", "max_step_s", "free_flight_max_step_s"):
            if getattr(self, name) is not None or name not in ("max_step_s", "free_flight_max_step_s"):   # None: default
                object.__setattr__(self, name, positive(name, getattr(self, name)))
        require("rtol", self.rtol, RTOL_RANGE[0] <= self.rtol <= RTOL_RANGE[1], "in [{:g}, {:g}]".format(*RTOL_RANGE))
        require("atol_position_m", self.atol_position_m, self.atol_position_m <= MAX_ATOL_POSITION_M,
                f"<= {MAX_ATOL_POSITION_M:g} m")
        require("atol_velocity_m_s", self.atol_velocity_m_s, self.atol_velocity_m_s <= MAX_ATOL_VELOCITY_M_S,
                f"<= {MAX_ATOL_VELOCITY_M_S:g} m/s")
        if self.integrator == "rk4":
            require("step_s", self.step_s, self.step_s >= self.min_step_s, f">= min_step_s = {self.min_step_s!r}")
        largest = self.max_step_s or 1e-7                   # None: the wear-step limit, at least this
        require("min_step_s", self.min_step_s, self.min_step_s <= largest, f"<= max_step_s = {largest!r}")
        if self.free_flight_max_step_s is not None:
            require("free_flight_max_step_s", self.free_flight_max_step_s,
                     self.free_flight_max_step_s >= self.min_step_s, f">= min_step_s = {self.min_step_s!r}")

    def for_joint(self, joint: JointParameters, mechanism: SliderCrankParameters | None = None) -> "SimulationOptions":
        """These options for a run of ``joint`` in ``mechanism``: the default ``max_step_s`` resolved; with wear, an
        RK4 ``step_s`` (whatever ``max_step_s``) or another integrator's given ``max_step_s`` above the wear-step
        limit (:func:`wear_step_limit_s`) refused (:func:`check_wear_step`), and a span :func:`check_run_span` refuses;
        the default ``gear_jacobian`` exact with the clearance at the crank-rod joint, else numerical."""
        if self.gear_jacobian is None:
            crank_rod = mechanism is None or mechanism.clearance_joint == "crank-rod"
            return dataclasses.replace(self, gear_jacobian="exact" if crank_rod else "numerical").for_joint(joint,
                                                                                                             mechanism)
        check_run_span(self, joint, mechanism)
        if not self.ideal and self.integrator == "rk4":
            check_wear_step("step_s", self.step_s, joint, mechanism)
        if self.max_step_s is None:
            default = wear_step_limit_s(joint, mechanism, DEFAULT_WEAR_STEP_SHARE) if not self.ideal else math.inf
            if default < self.min_step_s:       # the limit is inversely proportional to k_w * wear_factor below 3e-5 s
                name = "wear_factor" if joint.wear_factor != 1.0 else "wear_coefficient_m2_N"   # the one set
                value = getattr(joint, name)
                raise ParameterError(
                    f"parameter {name}={value!r} is invalid: with wear_coefficient_m2_N * "
                    f"wear_factor = {joint.wear_coefficient_m2_N * joint.wear_factor:.4g} m^2/N a step may wear for "
                    f"at most {default:.3g} s, below min_step_s = {self.min_step_s:g} s: allowed at most "
                    f"{value * default / self.min_step_s:.4g} with this "
                    f"{'wear coefficient' if name == 'wear_factor' else 'wear factor'} and mechanism "
                    "(docs/reference/model.md §7)")
            if self.integrator == "dopri" and default < math.inf:
                default = min(default, DOPRI_WEAR_CONTACT_STEP_S)
            return dataclasses.replace(self, max_step_s=min(default, NO_WEAR_MAX_STEP_S),
                                       free_flight_max_step_s=self.free_flight_max_step_s or NO_WEAR_MAX_STEP_S)
        if not self.ideal and self.integrator != "rk4":
            check_wear_step("max_step_s", self.max_step_s, joint, mechanism)
        if self.free_flight_max_step_s is None:
            return dataclasses.replace(self, free_flight_max_step_s=self.max_step_s)
        return self

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)
