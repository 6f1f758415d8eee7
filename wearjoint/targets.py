"""The targets of the sweeps and the sensitivity studies: one entry per command they run (``simulate``, ``cosim``,
``wear-study``), each called as the library (never through the command line): options -> config -> run -> record.

An entry (:class:`Target`) knows

* ``add_arguments(parser)``: its options, the command's own (:mod:`wearjoint.run_options`: names, types,
  defaults, choices), so that a sweep's ``--vary``, design file and ``--param`` take what the command takes;
* ``config(options)``: option values (dest -> value, as :func:`parser` gives them) turned into the library's
  configuration (parameter sets, run options); a bad value raises :class:`~wearjoint.checks.ParameterError` with
  the command's one-line message;
* ``run(config, out, plots, progress)``: the run into the results folder ``out``, returning its summary; a run that
  fails raises one of ``failures`` (ParameterError, RunStopped, FmuError, ...: the message says why) once what
  the run keeps of itself is written;
* ``model(options)``: the parameter sets the run resolves; ``engine(options)``: whose kernels it runs (a worker warms
  them once); ``snapshots(options)``: the revolutions whose figures its summary holds per snapshot.

:func:`run` chains them and writes the folder's report.html; :func:`read_record` reads a folder's summary.json.
The engines are imported when a target runs, not with this module.
"""
from __future__ import annotations

import argparse
import functools
import json
import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Callable

import numpy as np

from .checks import ParameterError, RunStopped, finite, require
from .fmu.fmi import FmuError
from .interrupts import results_kept, stopped_by_ctrl_c
from .parameters import JointParameters, SliderCrankParameters
from .run_options import (
    add_cosim_arguments, add_simulate_arguments, add_wear_study_arguments, calibration_facts, check_settling,
    model_from_options, read_initial_profile,
)

if TYPE_CHECKING:
    from .cosim import CoSimulationOptions
    from .simulation_options import SimulationOptions
    from .studies.wear_study import WearStudyConfig

RECORD_NAME = "summary.json"


@dataclass(frozen=True)
class Target:
    """One sweepable command as the library runs it (see the module docstring)."""

    name: str
    add_arguments: Callable
    config: Callable
    run: Callable
    model: Callable
    engine: Callable
    snapshots: Callable
    failures: tuple


def finished(record) -> None:
    """A written run's outcome (its :class:`~wearjoint.results.RunRecord`) as an exception: KeyboardInterrupt if
    Ctrl-C stopped it, RunStopped saying why it stopped (diverged, or an FMU's call failed); nothing if it
    completed."""
    if stopped_by_ctrl_c(record):
        raise KeyboardInterrupt
    if record.failure:
        raise RunStopped(record.failure)


def _write(record, out, plots: bool) -> dict:
    """The record's results folder (:func:`wearjoint.results.write_results`), then :func:`finished`."""
    from .results import write_results

    summary = write_results(record, out, plots=plots)
    finished(record)
    return summary


def _monolithic(options) -> tuple:
    return ("monolithic",)


def _no_snapshots(options) -> tuple:
    return ()


# ------------------------------------------------------------------ simulate
@dataclass(frozen=True)
class SimulateConfig:
    """A monolithic run: the parameter sets, its integration options, the start-up revolutions left out of the
    summary's extremes and the worn profile to start from (None: unworn)."""

    joint: JointParameters
    mechanism: SliderCrankParameters
    options: SimulationOptions
    settling_revolutions: int = 1
    initial_profile_m: np.ndarray | None = None
    load_coupling: str = "linearised"
    initial_profile_file: str | None = None


def refuse_unused(options, unused, allowed: str) -> None:
    """ParameterError naming the first of ``unused`` ((option, its key in ``options``, its default)) whose value is
    not its default: an option the run would silently ignore (``allowed``: where it does something)."""
    for option, key, default in unused:
        value = options.get(key, default)
        require(option, str(value) if isinstance(value, Path) else value, value == default, allowed)


def refuse_unread_wear(options) -> None:
    """The wear options that a run wearing nothing (``--no-wear``; ``--ideal``: no bushing) would ignore, refused
    (model_from_options refuses ``--wear-factor`` with ``--no-wear`` for the other commands: build-fmu keeps k_w,
    which the FMU's wear_factor parameter may switch on)."""
    why = "--no-wear" if options.get("no_wear") else "--ideal" if options.get("ideal") else None
    if why is not None:
        factor = 0.0 if options.get("wear_factor") == 0.0 else None          # --no-wear's own value, written
        refuse_unused(options, (("--wear-coefficient-m2-N", "wear_coefficient_m2_N", None),
                                ("--calibration", "calibration", None), ("--wear-factor", "wear_factor", factor)),
                      f"only without {why} (the run wears nothing)")


def _tolerance_options(defaults: SimulationOptions) -> tuple:
    """The adaptive integrators' tolerance options as :func:`refuse_unused` takes them."""
    return (("--rtol", "rtol", defaults.rtol), ("--atol-position", "atol_position", defaults.atol_position_m),
            ("--atol-velocity", "atol_velocity", defaults.atol_velocity_m_s))


def simulation_options(options) -> SimulationOptions:
    """simulate's integration options from option values; an integrator's option given to another refused."""
    from .simulation_options import SimulationOptions

    o, defaults = options, SimulationOptions()
    tolerances = _tolerance_options(defaults)
    if o["integrator"] != "rk4":
        refuse_unused(o, (("--step", "step", defaults.step_s),), "only with --integrator rk4 (its fixed step)")
    else:
        refuse_unused(o, (*tolerances, ("--max-step", "max_step", None)),
                      "only with --integrator dopri or gear (rk4 steps by --step)")
    if o["integrator"] != "gear":
        refuse_unused(o, (("--gear-solver", "gear_solver", defaults.gear_solver),
                          ("--gear-jacobian", "gear_jacobian", defaults.gear_jacobian)), "only with --integrator gear")
    if o["integrator"] != "dopri":
        refuse_unused(o, (("--free-flight-max-step", "free_flight_max_step", None),), "only with --integrator dopri")
    return SimulationOptions(revolutions=o["revolutions"], integrator=o["integrator"], step_s=o["step"],
                             rtol=o["rtol"], atol_position_m=o["atol_position"], atol_velocity_m_s=o["atol_velocity"],
                             max_step_s=o["max_step"], free_flight_max_step_s=o["free_flight_max_step"],
                             sample_dt_s=o["sample_dt"], ideal=o["ideal"], gear_solver=o["gear_solver"],
                             gear_jacobian=o["gear_jacobian"])


def simulate_config(options) -> SimulateConfig:
    refuse_unread_wear(options)
    joint, mechanism = model_from_options(options)
    run_options = simulation_options(options)
    settling = check_settling(options)
    given = options["initial_profile"]
    require("--initial-profile", None if given is None else str(given), given is None or not run_options.ideal,
            "only without --ideal (the ideal joint has no bushing)")
    profile = None if given is None else read_initial_profile(given, joint)
    return SimulateConfig(joint, mechanism, run_options, settling, profile,
                          initial_profile_file=None if given is None else str(given))


def _note_initial_profile(record, file: str | None, profile_m) -> None:
    """summary.json's ``initial_profile`` of a run that started from a worn bushing: the file and its largest depth
    [m] (the summary's max_wear_depth_m and worn_volume_m3 include what it held)."""
    if profile_m is not None:
        record.extra["initial_profile"] = {"file": file, "max_wear_depth_m": float(np.max(profile_m))}


def simulate_record(config: SimulateConfig, progress: bool = False):
    """The monolithic run's record (:class:`~wearjoint.results.RunRecord`), not yet written."""
    from .simulate import run_simulation

    record = run_simulation(config.joint, config.mechanism, config.options, progress=progress,
                            initial_profile_m=config.initial_profile_m)
    record.settling_revolutions = config.settling_revolutions
    _note_initial_profile(record, config.initial_profile_file, config.initial_profile_m)
    return record


def simulate_run(config: SimulateConfig, out, plots: bool = True, progress: bool = False) -> dict:
    with results_kept():        # Ctrl-C after the run waits for its results
        return _write(simulate_record(config, progress), out, plots)


# ------------------------------------------------------------------ cosim
@dataclass(frozen=True)
class CosimConfig:
    """A co-simulation: who runs it (``master``; with this package's, through the FMU's ``interface``), the
    parameter sets, the run's options (CoSimulationOptions; SimulationOptions through Model Exchange; None with a
    third-party master, which runs ``revolutions`` at the fixed ``step_s`` sampled every ``sample_dt_s``), the FMU,
    the start-up revolutions left out of the summary's extremes, the worn profile to start from."""

    joint: JointParameters
    mechanism: SliderCrankParameters
    master: str
    interface: str
    options: CoSimulationOptions | SimulationOptions | None
    revolutions: float
    step_s: float | None
    sample_dt_s: float
    fmusim: str | None
    fmu: Path | None
    fmu_backend: str
    settling_revolutions: int = 1
    initial_profile_m: np.ndarray | None = None
    load_coupling: str = "linearised"
    initial_profile_file: str | None = None


def cosim_config(options) -> CosimConfig:
    from .cosim import CoSimulationOptions
    from .cosim.masters import MASTERS, master_available
    from .cosim.step_rule import paper_step_scale
    from .fmu.fmi import DEFAULT_BACKEND
    from .simulation_options import check_wear_step, wear_step_limit_s
    from .fmu.ssp import LOAD_COUPLINGS, package_step_s
    from .simulation_options import SimulationOptions

    o, defaults = options, CoSimulationOptions()
    refuse_unread_wear(o)
    require("--master", o["master"], o["master"] in MASTERS, "one of " + ", ".join(MASTERS))
    require("--fmusim", o["fmusim"], o["fmusim"] is None or o["master"] == "container", "only with --master container")
    fmusim = None if o["fmusim"] is None else shutil.which(str(o["fmusim"]))
    require("--fmusim", o["fmusim"], o["fmusim"] is None or fmusim is not None,
            "an executable fmusim, its path or a name on PATH (the Modelica Reference-FMUs' importer: "
            "github.com/modelica/Reference-FMUs)")
    coupling = o.get("load_coupling", "linearised")
    require("--load-coupling", coupling, coupling in LOAD_COUPLINGS, "one of " + ", ".join(LOAD_COUPLINGS))
    require("--load-coupling", coupling, coupling == "linearised" or o["master"] != "wearjoint",
            "only with a third-party --master (this package's master couples by --scheme)")
    require("--initial-profile", None if o["initial_profile"] is None else str(o["initial_profile"]),
            o["initial_profile"] is None or o["master"] == "wearjoint",
            "only with --master wearjoint (it sets the FMU's state; the SSP's masters start unworn)")
    joint, mechanism = model_from_options(o)
    settling = check_settling(o)
    profile = None if o["initial_profile"] is None else read_initial_profile(o["initial_profile"], joint)
    run_options, step = None, o["step"]
    tolerances = _tolerance_options(SimulationOptions())
    coupling_options = (("--scheme", "scheme", defaults.scheme), ("--coupling-tolerance", "coupling_tolerance", None),
                        ("--min-step", "min_step", defaults.min_step_s))
    if o["master"] != "wearjoint":
        refuse_unused(o, (("--fmu-interface", "fmu_interface", "co-simulation"), *coupling_options,
                          ("--max-step", "max_step", defaults.max_step_s),
                          ("--onset-penetration", "onset_penetration", defaults.onset_penetration_m), *tolerances,
                          ("--fmu", "fmu", None), ("--fmu-backend", "fmu_backend", DEFAULT_BACKEND)),
                      "only with --master wearjoint (a third-party master steps the SSP's Co-Simulation FMUs, "
                      "export-ssp's native builds, at the fixed --step)")
    elif o["fmu_interface"] == "model-exchange":
        refuse_unused(o, (*coupling_options, ("--step", "step", None)), "only with --fmu-interface co-simulation "
                      "(Model Exchange integrates by Dormand-Prince: --rtol, --atol-*, --max-step)")
    else:
        refuse_unused(o, tolerances, "only with --fmu-interface model-exchange (Co-Simulation steps by --scheme)")
    if o["master"] != "wearjoint":
        missing = master_available(o["master"])
        if missing is not None:
            installed = [m for m in MASTERS if m == "wearjoint" or master_available(m) is None]
            require("--master", o["master"], False,
                    f"one of the masters installed here, {', '.join(installed)} ({missing})")
        if step is None:     # the package's step (the step rule's), within the wear-step limit
            step = package_step_s(coupling, paper_step_scale(joint, mechanism), wear_step_limit_s(joint, mechanism),
                                  mechanism.period_s)
        require("--revolutions", o["revolutions"], finite("--revolutions", o["revolutions"]) > 0.0,
                "> 0 crank revolutions")
        run_s = o["revolutions"] * mechanism.period_s
        if o["step"] is None:       # the package's own step: a run shorter than it is the run's fault
            require("--revolutions", o["revolutions"], run_s >= step, f">= {step / mechanism.period_s:.3g} (one "
                    f"communication step of the package, {step:g} s, of a {mechanism.period_s:.4g} s revolution)")
        require("--step", step, 0.0 < finite("--step", step) <= run_s,
                f"a communication step > 0 [s] and at most the run's {run_s:g} s")
        check_wear_step("step_s", step, joint, mechanism)       # as this package's master refuses it
    elif o["fmu_interface"] == "model-exchange":
        # --max-step left at the master's default: SimulationOptions' own (DOPRI with wear 1e-5 s, else 1e-4 s)
        max_step = None if o["max_step"] == defaults.max_step_s else o["max_step"]
        run_options = SimulationOptions(revolutions=o["revolutions"], integrator="dopri", rtol=o["rtol"],
                                        atol_position_m=o["atol_position"], atol_velocity_m_s=o["atol_velocity"],
                                        max_step_s=max_step, onset_penetration_m=o["onset_penetration"],
                                        sample_dt_s=o["sample_dt"])
    else:
        run_options = CoSimulationOptions(revolutions=o["revolutions"], scheme=o["scheme"],
                                          step_s=step,
                                          max_step_s=o["max_step"], min_step_s=o["min_step"],
                                          onset_penetration_m=o["onset_penetration"], sample_dt_s=o["sample_dt"],
                                          coupling_tolerance=o["coupling_tolerance"])
    return CosimConfig(joint, mechanism, o["master"], o["fmu_interface"], run_options, o["revolutions"], step,
                       o["sample_dt"], fmusim, o["fmu"], o["fmu_backend"], settling, profile, coupling,
                       None if o["initial_profile"] is None else str(o["initial_profile"]))


def cosim_record(config: CosimConfig, progress: bool = False):
    """The co-simulation's record (:class:`~wearjoint.results.RunRecord`), not yet written."""
    c = config
    if c.master != "wearjoint":
        from .cosim.masters import run_master

        from .cosim.step_rule import unchecked_step_note

        record = run_master(c.master, c.joint, c.mechanism, c.revolutions, c.step_s, c.sample_dt_s, fmusim=c.fmusim,
                            load_coupling=c.load_coupling)
        note = unchecked_step_note(c.step_s, c.load_coupling, c.joint, c.mechanism)
        if note:
            record.extra["communication_step_note"] = note
    elif c.interface == "model-exchange":
        from .cosim.model_exchange import run_model_exchange

        record = run_model_exchange(c.joint, c.mechanism, c.options, fmu_path=c.fmu, progress=progress,
                                    fmu_backend=c.fmu_backend, initial_profile_m=c.initial_profile_m)
    else:
        from .cosim import run_cosimulation

        record = run_cosimulation(c.joint, c.mechanism, c.options, fmu_path=c.fmu, progress=progress,
                                  fmu_backend=c.fmu_backend, initial_profile_m=c.initial_profile_m)
    record.settling_revolutions = c.settling_revolutions
    _note_initial_profile(record, c.initial_profile_file, c.initial_profile_m)
    return record


def cosim_run(config: CosimConfig, out, plots: bool = True, progress: bool = False) -> dict:
    with results_kept():        # Ctrl-C after the run waits for its results
        return _write(cosim_record(config, progress), out, plots)


def _cosim_engine(options) -> tuple:
    return ("cosim", options.get("fmu_backend"), str(options.get("fmu")))


# ------------------------------------------------------------------ wear-study
def parse_int_list(name: str, text: str, example: str = "1000,2000") -> tuple:
    """'1000,2000' -> (1000, 2000); a clear ParameterError for anything else (``example``: a valid value)."""
    values = []
    for item in str(text).split(","):
        item = item.strip()
        try:
            values.append(int(item))
        except ValueError:
            raise ParameterError(f"{name}={item!r} is invalid: allowed an integer (digits only: not 1.5 or 1e3; "
                                 f"e.g. {example})") from None
    return tuple(values)


def parse_float_list(name: str, text: str) -> tuple:
    values = []
    for item in str(text).split(","):
        try:
            values.append(float(item))
        except ValueError:
            raise ParameterError(f"{name}: {item.strip()!r} is not a number (expected e.g. 1,10,50)") from None
    return tuple(values)


def wear_study_config(options) -> WearStudyConfig:
    """The wear study's configuration (its other tasks, --convergence and --calibrate-max-depth-m, are the
    command's)."""
    from .studies.cycle_jump import DEFAULT_JUMP_TOLERANCE
    from .studies.wear_study import DEFAULT_WEAR_FACTOR, WearStudyConfig
    from .studies.wear_study_recovery import quartile_snapshots

    o = options
    if o["engine"] != "monolithic" or o["integrator"] != "dopri":
        refuse_unused(o, (("--rtol", "rtol", WearStudyConfig.rtol),), "only with --integrator dopri and the "
                      "monolithic --engine (rk4 steps by --max-step)")
    if o["engine"] != "cosim":
        refuse_unused(o, (("--fmu-backend", "fmu_backend", WearStudyConfig.fmu_backend),), "only with --engine cosim")
    elif "integrator" in (o.get("written") or ()):    # the default's value written too: it was recorded as used
        require("--integrator", o["integrator"], False, "only with the monolithic --engine (the co-simulation steps "
                "by its adaptive master, --max-step its longest step in contact)")
    refuse_unread_wear(o)
    joint, mechanism = model_from_options(o)
    revolutions = parse_int_list("--revolutions", o["revolutions"], "4000")
    if len(revolutions) != 1:
        raise ParameterError("--revolutions takes one integer")
    revolutions = revolutions[0]
    if o["snapshots"] is not None:
        snapshots = parse_int_list("--snapshots", o["snapshots"])
    else:
        snapshots = quartile_snapshots(revolutions)
    jump_tolerance = o["cycle_jump_tolerance"]
    if jump_tolerance is None and o["wear_factor"] is None and not o["no_cycle_jump"]:
        jump_tolerance = DEFAULT_JUMP_TOLERANCE
    if o["wear_factor"] is None and not o["no_wear"]:
        joint = joint.replace(wear_factor=DEFAULT_WEAR_FACTOR)
    return WearStudyConfig(joint=joint, mechanism=mechanism, revolutions=revolutions, snapshots=snapshots,
                           jump_tolerance=jump_tolerance, jump_block_revolutions=o["cycle_jump_block"],
                           engine=o["engine"], integrator=o["integrator"], max_step_s=o["max_step"],
                           **({"rtol": o["rtol"]} if o.get("rtol") is not None else {}),
                           checkpoint_every_revolutions=o["checkpoint_every"],
                           impact_threshold_m_s2=o["impact_threshold_m_s2"], fmu_backend=o["fmu_backend"],
                           life_depth_m=o.get("life_depth_m"))


def wear_study_run(config: WearStudyConfig, out, plots: bool = True, progress: bool = False) -> dict:
    """The study into ``out``, resuming the one ``out`` holds (a sweep case stopped part-way: its checkpoint, which
    refuses other settings) (StudyDiverged, a RunDiverged, once a diverged study's outputs are written)."""
    from .studies.wear_study import CHECKPOINT_NAME, run_wear_study

    return run_wear_study(config, out, resume=(Path(out) / CHECKPOINT_NAME).is_file(), progress=progress, plots=plots)


def _wear_study_model(options) -> tuple:
    study = wear_study_config(options)               # its own wear factor where none is given
    return study.joint, study.mechanism


def _wear_study_engine(options) -> tuple:
    return _cosim_engine(options) if options.get("engine") == "cosim" else ("monolithic",)


# ------------------------------------------------------------------ the registry
TARGETS = {t.name: t for t in (
    Target("simulate", add_simulate_arguments, simulate_config, simulate_run, model_from_options, _monolithic,
           _no_snapshots, failures=(ParameterError, RunStopped)),
    # an FMU that failed (FmuError), a diverged run, a third-party master that failed: RuntimeErrors all, as
    # `wearjoint cosim` reports them
    Target("cosim", add_cosim_arguments, cosim_config, cosim_run, model_from_options, _cosim_engine, _no_snapshots,
           failures=(ParameterError, RuntimeError)),
    Target("wear-study", add_wear_study_arguments, wear_study_config, wear_study_run, _wear_study_model,
           _wear_study_engine, lambda options: wear_study_config(options).snapshots,
           failures=(ParameterError, RunStopped, FmuError)),
)}


def target(name: str) -> Target:
    """Target ``name``; ParameterError naming the allowed ones."""
    if name not in TARGETS:
        raise ParameterError(f"sweep command {name!r} is invalid: allowed one of {', '.join(TARGETS)}")
    return TARGETS[name]


@functools.lru_cache(maxsize=None)
def parser(name: str) -> argparse.ArgumentParser:
    """A parser holding target ``name``'s options (the command's own); shared, read only."""
    p = argparse.ArgumentParser(prog=f"wearjoint {name}", allow_abbrev=False)
    target(name).add_arguments(p)
    return p


def report_facts(options) -> dict:
    """What the report states beside the summary that only the options know: where k_w came from, with a
    calibration's interval and note (:func:`~wearjoint.run_options.calibration_facts`)."""
    calibration = options.get("calibration")
    if calibration is None:
        return {}
    return calibration_facts(calibration, *model_from_options(options))


def read_record(out) -> dict:
    """A results folder's record: its summary.json."""
    return json.loads((Path(out) / RECORD_NAME).read_text())


def run(name: str, options, out, plots: bool = True, progress: bool = False, command_line: str | None = None) -> dict:
    """Run target ``name`` with option values ``options`` (dest -> value) into the results folder ``out``: config,
    run, then report.html (``command_line``: the command the run equals, recorded in summary.json too) wherever the
    run wrote a summary, a failed one's included.  Returns the record (:func:`read_record`); raises the target's
    ``failures`` as they come."""
    from .report import summary_path, write_report

    spec = target(name)
    out = Path(out)
    try:
        spec.run(spec.config(options), out, plots=plots, progress=progress)
    finally:
        if summary_path(out) is not None:
            write_report(out, command_line, report_facts(options))
    return read_record(out)


__all__ = ["TARGETS", "RECORD_NAME", "Target", "SimulateConfig", "CosimConfig", "target", "parser", "run",
           "read_record", "report_facts", "finished", "simulation_options", "simulate_config", "cosim_config",
           "wear_study_config", "parse_int_list", "parse_float_list", "simulate_record", "cosim_record"]
