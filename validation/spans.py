"""The spans of ``wearjoint validate``'s runs (:class:`~wearjoint.validation.compare.ValidationPlan`) that make its
comparison mean something, checked before any run: a point-wise window that holds every engine's own points, no-wear
runs that cover it, and a wear run of at least one sample that fits this machine's memory.  Each refusal is one line
naming the plan's field (the command line names its option as written, cli.as_written)."""
from __future__ import annotations

from wearjoint.checks import ParameterError, require

# points of the coarsest engine the window must hold: the co-simulation records a point per communication step, up to
# CoSimulationOptions.max_step_s (0.1 ms) in free flight (a 0.1 ms window held none of its own points: "zero-size array")
WINDOW_POINTS = 5


def min_window_s() -> float:
    """The shortest point-wise window [s]: WINDOW_POINTS of the co-simulation's free-flight steps."""
    from wearjoint.cosim.cosimulation import CoSimulationOptions

    return WINDOW_POINTS * CoSimulationOptions().max_step_s


def default_window_s(window_s: float, period_s: float, paper_period_s: float) -> float:
    """The window a plan's ``window_s`` (for the paper's ``paper_period_s`` revolution) gives a mechanism turning in
    ``period_s``: the same share of a turn, at least :func:`min_window_s`."""
    return max(window_s * period_s / paper_period_s, min_window_s())


def check_spans(plan, mechanism, written=frozenset({"window"})) -> None:
    """ParameterError unless ``plan``'s window holds :func:`min_window_s`, its no-wear runs (``revolutions``) cover
    the window, and its wear run (``wear_revolutions``, where it runs) covers one sample interval and fits this
    machine's memory.  A window longer than the no-wear runs names ``window_s`` where ``written`` (the command line's
    dests) holds it, else ``revolutions``."""
    period, shortest = mechanism.period_s, min_window_s()
    require("window_s", plan.window_s, plan.window_s >= shortest,
            f">= {shortest:g} s ({WINDOW_POINTS} of the co-simulation's free-flight steps: the coarsest engine's own "
            "points the point-wise comparison judges)")
    covered = plan.revolutions * period
    if plan.window_s > covered:
        if "window" not in written:         # the window a default (at least min_window_s): the runs are too short
            require("revolutions", plan.revolutions, False,
                    f">= {plan.window_s / period:.4g} (the no-wear runs cover the point-wise window, window_s = "
                    f"{plan.window_s:g} s, of a {period:.4g} s revolution)")
        require("window_s", plan.window_s, False,
                f"<= the no-wear run ({plan.revolutions:g} rev = {covered:g} s)")
    if not plan.run_wear:
        return
    one_sample = plan.sample_dt_s / period
    require("wear_revolutions", plan.wear_revolutions, plan.wear_revolutions >= one_sample,
            f">= {one_sample:.3g} (one sample interval, sample_dt_s = {plan.sample_dt_s:g} s, of a {period:.4g} s "
            "revolution)")
    from wearjoint.runner import check_time_series_fits

    try:
        check_time_series_fits(plan.wear_revolutions, period, plan.sample_dt_s,
                               remedy="fewer revolutions of wear (a higher --wear-factor wears as deep in fewer)")
    except ParameterError as exc:      # the wear run's revolutions, not the no-wear runs'
        raise ParameterError(str(exc).replace("parameter revolutions=", "parameter wear_revolutions=", 1)) from None


__all__ = ["check_spans", "default_window_s", "min_window_s", "WINDOW_POINTS"]
