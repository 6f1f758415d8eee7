"""Results contract (docs/reference/results.md §6): one folder per run.

``summary.json`` (key figures, SI units named in the keys, every parameter
used), ``profile.csv`` (phi_deg,wear_depth_m), ``timeseries.npz`` (all
samples), ``last_revolution.csv`` (samples of the last revolution),
``revolutions.csv`` (per-revolution statistics, with the impact-vibration events and
chattering flags of :func:`wearjoint.analysis.revolution_impact_events`) and PNG figures.
"""
from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import against_ideal, analysis, profile_metrics
from .core import layout as L
from .parameters import JointParameters, SliderCrankParameters, joint_size_note, wear_coefficient_source
from .report import json_values, write_report

REVOLUTION_COLUMNS = analysis.REVOLUTION_COLUMNS + against_ideal.REVOLUTION_COLUMNS
# summary.json's entries that describe the clearance joint's contact: null in a run of the ideal joint
CONTACT_ONLY = ("contact_fraction", "impacts_per_revolution", "max_wear_angle_deg", "regime", "whirl_fraction",
                "chattering_revolution_share", "clearance_m", "admissible_penetration_m", "admissible_force_N",
                "contact_stiffness_N_m1_5")


def new_revolution_stats(n_revolutions: int) -> np.ndarray:
    """Empty per-revolution statistics (layout.S_*), extremes primed for max/min."""
    stats = np.zeros((max(1, n_revolutions), L.N_STATS))
    stats[:, L.S_ACC_MAX] = -np.inf
    stats[:, L.S_ACC_MIN] = np.inf
    return stats


def new_track(sample_dt: float, t0: float = 0.0) -> np.ndarray:
    track = np.zeros(L.N_TRACK)
    track[L.K_NEXT_SAMPLE] = t0
    track[L.K_PREVIOUS_PENETRATION] = -np.inf     # starts in free flight
    track[L.K_SAMPLE_DT] = sample_dt
    return track


@dataclass(frozen=True)
class RunParameters:
    """What a run ran: its engine, the joint and the mechanism as they were given, the engine's options under
    ``options_key`` (``simulation``, ``cosimulation``, ``study``, ...; a dataclass with ``to_dict`` or a dict; None:
    no options entry) and the engine's own entries (``details``: the FMU, its backend and interface, a master).
    summary.json holds :meth:`to_dict`."""

    engine: str
    joint: JointParameters
    mechanism: SliderCrankParameters
    options_key: str | None = None
    options: object = None
    details: dict = field(default_factory=dict)

    @property
    def ideal(self) -> bool:
        """The clearance joint was run as an ideal one (``simulate --ideal``): no contact, no clearance."""
        return bool(getattr(self.options, "ideal", False))

    def to_dict(self) -> dict:
        out = {"joint": self.joint.to_dict(), "mechanism": self.mechanism.to_dict()}
        if self.options_key is not None:
            out[self.options_key] = self.options.to_dict() if hasattr(self.options, "to_dict") else dict(self.options)
        return out | {"engine": self.engine, **self.details}


@dataclass
class RunRecord:
    """Everything a simulating command writes (see module docstring)."""

    samples: np.ndarray                     # (n, layout.N_SAMPLE_COLUMNS)
    revolution_stats: np.ndarray            # (n_rev, layout.N_STATS)
    wear_growth_m: np.ndarray               # max wear depth at the end of each revolution
    phi_deg: np.ndarray
    wear_depth_m: np.ndarray
    worn_volume_m3: float
    simulated_time_s: float
    wall_time_s: float                      # the simulation alone (compilation excluded)
    revolutions: float
    period_s: float                         # duration of one crank revolution
    clearance_m: float
    parameters: RunParameters
    extra: dict = field(default_factory=dict)
    completed: bool = True
    compile_time_s: float = 0.0             # building the engine (FMU load, instantiation) and JIT compilation
    failure: str = ""                       # why the run stopped early when it diverged
    contact_stiffness_N_m1_5: float | None = None   # the K the joint used (given, or from its materials)
    settling_revolutions: int = 1           # the start-up transient, left out of the run's extremes
    revolution_numbers: np.ndarray | None = None   # the revolution each row of revolution_stats is (a wear study's
    #                                                simulated revolutions stand for others); None: 0, 1, 2, ...
    left_out_rows: tuple = ()               # rows of revolution_stats left out of the extremes (a wear study's)
    impact_threshold_m_s2: float = analysis.IMPACT_EVENT_THRESHOLD_M_S2   # an impact-vibration event's size
    impact_merge_deg: float = analysis.IMPACT_EVENT_MERGE_DEG              # and its clusters' merge angle

    def last_revolution(self) -> int:
        """Index of the last revolution that was simulated (complete or partial)."""
        return analysis.last_revolution(self.revolution_stats)

    @property
    def clearance_joint(self) -> str:
        """The joint that wears (its bushing's frame: the profile's angles)."""
        return self.parameters.mechanism.clearance_joint

    def _steady_samples(self) -> np.ndarray:
        """The samples of the revolutions the extremes are taken over (after the start-up; all where none is)."""
        inside = analysis.steady_samples(self.samples, self.revolution_stats, self.period_s,
                                         self.settling_revolutions, self.left_out_rows)
        return self.samples[inside] if inside.any() else self.samples

    def impact_events(self) -> dict:
        """The run's impact-vibration events per revolution (:func:`wearjoint.analysis.revolution_impact_events`)."""
        return analysis.revolution_impact_events(self.samples, self.revolution_stats, self.parameters.mechanism,
                                                 self.impact_threshold_m_s2, self.impact_merge_deg)

    def ideal_comparison(self) -> tuple[np.ndarray, np.ndarray]:
        """|a - a_ideal| and the ideal joint's reaction at every sample
        (:func:`wearjoint.against_ideal.sample_comparison`)."""
        return against_ideal.sample_comparison(self.samples, self.parameters.mechanism)

    def summary(self, impact_events: dict | None = None, ideal_comparison=None) -> dict:
        """summary.json's content (docs/reference/results.md §6); the statistics are :mod:`wearjoint.analysis`'s and
        :mod:`wearjoint.against_ideal`'s (``impact_events``, ``ideal_comparison``: :meth:`impact_events`,
        :meth:`ideal_comparison` where the caller has them already)."""
        out = {
            "revolutions": self.revolutions,
            "simulated_time_s": self.simulated_time_s,
            "wall_time_s": self.wall_time_s,
            "compile_time_s": self.compile_time_s,
            "realtime_factor": self.simulated_time_s / self.wall_time_s if self.wall_time_s > 0 else None,
            **analysis.run_statistics(self.revolution_stats, self.settling_revolutions, self.left_out_rows),
            **profile_metrics.deepest_point(self.phi_deg, self.wear_depth_m),
            **analysis.regime(self._steady_samples()),
            **analysis.impact_event_statistics(impact_events or self.impact_events(), self.parameters.mechanism,
                                               self.settling_revolutions),
            "worn_volume_m3": self.worn_volume_m3,
            **wear_coefficient_source(self.parameters.joint, self.parameters.mechanism),
            **joint_size_note(self.parameters.joint, self.parameters.mechanism),
            **({"wear_coefficient_note": None} if self.parameters.ideal else {}),   # the ideal joint wears nothing
            "clearance_m": self.clearance_m,
            "admissible_penetration_m": self.parameters.joint.admissible_penetration_m,
            "admissible_force_N": self.parameters.joint.admissible_force_N,
            **({} if self.contact_stiffness_N_m1_5 is None else {"contact_stiffness_N_m1_5": self.contact_stiffness_N_m1_5}),
            "completed": self.completed,
            "failure": self.failure or None,
            "parameters": self.parameters.to_dict(),
        }
        if self.revolution_numbers is not None:     # a wear study's simulated revolutions stand for these
            numbers = np.asarray(self.revolution_numbers, dtype=float)
            out["impact_event_revolutions"] = [int(round(numbers[k])) if k < numbers.size and np.isfinite(numbers[k])
                                               else k for k in out["impact_event_revolutions"]]
        out.update(against_ideal.summary_statistics(self.samples, self.revolution_stats, self.parameters.mechanism,
                                                    self.settling_revolutions, out.get("max_contact_force_N"),
                                                    ideal_comparison, self.left_out_rows))
        out.update(self.extra)
        if self.parameters.ideal:      # what only a contact has: none (they read "0.99999 in contact, 1 impact")
            out.update(dict.fromkeys(CONTACT_ONLY))
        return out

    def revolution_table(self, impact_events: dict | None = None, ideal_comparison=None) -> np.ndarray:
        """Per-revolution statistics, columns :data:`REVOLUTION_COLUMNS` (``impact_events``, ``ideal_comparison``:
        as :meth:`summary`'s)."""
        events = impact_events or self.impact_events()
        return np.column_stack([
            analysis.revolution_table(self.revolution_stats, self.wear_growth_m, events["events"],
                                      self.revolution_numbers),
            against_ideal.revolution_columns(self.samples, self.revolution_stats, self.parameters.mechanism,
                                             ideal_comparison)])


def write_json_atomic(path: Path, data: dict) -> None:
    """``data`` as JSON at ``path`` (tmp + rename): numpy values as Python's, a value that is not a finite number (NaN,
    inf: JSON has none) as null."""
    tmp = path.with_suffix(path.suffix + ".tmp")
    tmp.write_text(json.dumps(json_values(data), indent=2, allow_nan=False))
    os.replace(tmp, path)


def write_csv(path, table: np.ndarray, names, fmt: str) -> None:
    """``table`` (rows) as CSV with a header line of ``names``, each value printed with ``fmt``: what
    ``np.savetxt(path, table, delimiter=",", header=",".join(names), comments="", fmt=fmt)`` writes, byte for byte,
    with one formatting of the whole table instead of one per row (a revolution's samples 0.06 -> 0.05 s)."""
    table = np.asarray(table, dtype=float)
    table = table[:, None] if table.ndim == 1 else table
    row = ",".join([fmt] * table.shape[1])
    with open(path, "w") as file:
        file.write(",".join(names) + "\n")
        if table.size:
            file.write(("\n".join([row] * table.shape[0]) + "\n") % tuple(table.ravel().tolist()))


def _earlier_figures(out: Path) -> list[str]:
    """The PNG figures an earlier run wrote into ``out`` (its summary.json's ``figures``), none if it has none."""
    try:
        names = json.loads((out / "summary.json").read_text()).get("figures", [])
    except (OSError, ValueError, AttributeError):
        return []
    return [name for name in names if isinstance(name, str) and name.endswith(".png") and Path(name).name == name]


def write_results(record: RunRecord, out_dir, plots: bool = True, figure_worker=None) -> dict:
    """Write the results folder (report.html last, :mod:`wearjoint.report`); returns the summary dict.  With
    ``figure_worker`` (a started :class:`wearjoint.figure_worker.FigureWorker`) the figures are drawn there while
    this process writes the data files, else (or if it fails) here."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    drawing = plots and figure_worker is not None and figure_worker.send(record, out)
    if np.isfinite(record.wear_depth_m).all():
        write_csv(out / "profile.csv", np.column_stack([record.phi_deg, record.wear_depth_m]),
                  ("phi_deg", "wear_depth_m"), "%.17g")
    else:                       # a master that gives no profile (its note in summary.json): not an earlier run's either
        (out / "profile.csv").unlink(missing_ok=True)
    # uncompressed: deflate saved 28 % of a revolution's 2.3 MB at 30x the time (0.05 s, a tenth of the main job)
    np.savez(out / "timeseries.npz", columns=np.array(L.SAMPLE_NAMES),
             **{name: record.samples[:, k] for k, name in enumerate(L.SAMPLE_NAMES)})
    in_last = record.samples[:, L.T_TIME] > record.last_revolution() * record.period_s
    write_csv(out / "last_revolution.csv", record.samples[in_last], L.SAMPLE_NAMES, "%.10g")
    events = record.impact_events()              # once each, for revolutions.csv and summary.json
    comparison = record.ideal_comparison()
    write_csv(out / "revolutions.csv", record.revolution_table(events, comparison), REVOLUTION_COLUMNS, "%.10g")
    summary = record.summary(events, comparison)
    names = []
    if plots:
        names = figure_worker.names() if drawing else None
        if names is None:
            from .plots import plot_run  # matplotlib only when figures are written
            names = plot_run(record, out)
    summary["figures"] = names                     # none with --no-plots
    for name in set(_earlier_figures(out)) - set(names):   # an earlier run's are not this run's (nor in its report)
        (out / name).unlink(missing_ok=True)
    write_json_atomic(out / "summary.json", summary)
    write_report(out)
    return summary
