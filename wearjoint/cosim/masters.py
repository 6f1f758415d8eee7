"""Third-party co-simulation masters running ``SliderCrankWithClearance.ssp`` (``wearjoint cosim --master``).

Each adapter runs the package (or its fmpy container FMU) at a fixed communication step for the
requested time and returns a :class:`wearjoint.cosim.master_trace.MasterTrace`: the traced outputs at every
communication point and, where the master lets one read it, the final worn profile, which
:func:`wearjoint.cosim.master_trace.record_from_trace` turns into the :class:`wearjoint.results.RunRecord` every
engine writes.

* ``libcosim`` -- OSP libcosim (``libcosimpy``): ``CosimExecution.from_ssp_file``, stepped one
  communication step at a time, a last-value observer read after each.
* ``ecos`` -- ecos (``ecospy``; its library needs ``libtbb.so.12`` from the pip package ``tbb``,
  preloaded here): ``EcosSimulation(ssp_path=...)``, the package's parameter set applied by name.
* ``fmpy-ssp`` -- fmpy's SSP simulator ``fmpy.ssp.simulation.simulate_ssp``; fmpy 0.3.32 does not
  apply the SSD's parameter bindings itself, so the package's parameter sets (as fmpy reads them)
  are passed as its ``parameter_set``.  It returns connector values only (no worn profile) and keeps
  every connector of every step in memory, about 3 kB a step.
* ``omsimulator`` -- OpenModelica's OMSimulator (its Python package ``OMSimulator``: ``pip install
  omsimulator``, or an OMSimulator build's ``lib/<platform>`` on ``PYTHONPATH``): the package imported
  through its C API (``oms_importFile``, the SSD's OMSimulator annotations and parameter sets), the
  fixed step set, no result file, stepped one communication step at a time and read with ``oms_getReal``.
  Its fixed-step master moves the connections after each step in dependency order, the joint's
  loads evaluated at the new kinematics, like the container.
* ``container`` -- the system as one fmpy container FMU (:func:`wearjoint.fmu.ssp.container_fmu`,
  fixed internal step = the communication step), run by fmpy's ``FMU2Slave`` or, given its path,
  by fmusim (the Reference-FMUs' importer; no worn profile from its CSV).

Every master holds each FMU's inputs over a step (zero-order hold).  libcosim, ecos and fmpy's simulator read
the joint's loads before they set its new inputs, so the mechanism gets them one step late; the
container sets the kinematics first and reads the loads evaluated at them (docs/explanation/cosim_study.md).
ecos is traced after it moved the connections (the joint's rows at their point, the slider's acceleration with the
new loads); libcosim and fmpy's simulator before (their joint rows realigned, :func:`align_joint`; the slider's
acceleration its step's end's): the same motion, accelerations one coupling jump apart.
"""
from __future__ import annotations

import ctypes
import io
import os
import subprocess
import tempfile
import time
import zipfile
from pathlib import Path

import numpy as np

from .._compile.user_cache import user_cache_dir
from ..checks import RunDiverged
from ..fmu import ssp
from ..fmu import variables as fv
from ..results import RunParameters, RunRecord
from ..runner import check_time_series_fits
from .master_trace import JOINT_TRACED, MECHANISM_TRACED, TRACED, MasterTrace, align_joint, record_from_trace

MASTERS = ("wearjoint", "libcosim", "ecos", "fmpy-ssp", "omsimulator", "container")
THIRD_PARTY = MASTERS[1:]
# a third-party master's default communication step by the package's load coupling: the one the package asks its
# masters for (inside the monolithic scatter on time or one step late, docs/explanation/cosim_study.md; held loads
# at 1 us, this default until now, put the container's 8-start impacts z -5.1 off)
DEFAULT_STEP_S = ssp.DEFAULT_STEP_S
_PACKAGES = {"libcosim": "libcosimpy", "ecos": "ecospy and tbb", "fmpy-ssp": "fmpy", "container": "fmpy",
             "omsimulator": "the OMSimulator Python package (pip install omsimulator, or an OMSimulator build's "
                            "lib/x86_64-linux-gnu on PYTHONPATH)"}


class MasterUnavailable(ImportError):
    """The master's package is not installed."""


def _steps(stop_time_s: float, step_s: float) -> int:
    return max(1, int(round(stop_time_s / step_s)))


def _stepwise(master, step_s, n, do_step, read, load_time_s) -> MasterTrace:
    """``n`` calls of ``do_step()``, ``read()`` (the traced values, in TRACED order) before the first and after each;
    a step that fails (``do_step()`` returns False or raises: the joint FMU refused it) ends the trace there, its
    ``failure`` saying so."""
    values = np.empty((n + 1, len(TRACED)))
    values[0] = read()
    failure = ""
    start = time.perf_counter()
    for i in range(1, n + 1):
        try:
            ok, why = do_step(), ""
        except Exception as exc:      # fmpy's FMICallException, an OMSimulator status: the master's own errors
            ok, why = False, f" ({exc})"
        if ok is False:
            failure = (f"{master}'s step to t = {i * step_s:.6g} s failed{why}: the joint FMU refuses inputs deeper "
                       "in the bushing wall or pressed harder than any contact admits (fmi2Discard, its log line "
                       "names them)")
            values = values[:i]
            break
        values[i] = read()
    wall = time.perf_counter() - start
    return MasterTrace(master, step_s, np.arange(values.shape[0]) * step_s, values, None, wall, load_time_s, failure)


def _profile_names(n_points: int) -> list[str]:
    return [fv.wear_depth_name(z) for z in range(1, n_points + 1)]


def _unzipped(ssp_path, folder: Path) -> Path:
    with zipfile.ZipFile(ssp_path) as package:
        package.extractall(folder)
    return folder / "SystemStructure.ssd"


def run_libcosim(ssp_path, step_s: float, stop_time_s: float, n_points: int) -> MasterTrace:
    """The package in OSP libcosim at ``step_s`` [s] up to ``stop_time_s`` [s]."""
    try:
        from libcosimpy.CosimExecution import CosimExecution
        from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
        from libcosimpy.CosimObserver import CosimObserver
    except ImportError as exc:
        raise MasterUnavailable(str(exc)) from exc
    log_output_level(CosimLogLevel.ERROR)
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="wearjoint_libcosim_") as tmp:
        execution = CosimExecution.from_ssp_file(str(_unzipped(ssp_path, Path(tmp))), step_size=round(step_s * 1e9))
        observer = CosimObserver.create_last_value()
        execution.add_observer(observer)
        slaves = {s.name.decode(): s.index for s in execution.slave_infos()}
        refs = {name: {v.name.decode(): v.reference for v in execution.slave_variables(index)}
                for name, index in slaves.items()}
        groups = [(slaves[c], [refs[c][n] for n in names]) for c, names in
                  ((ssp.MECHANISM, MECHANISM_TRACED), (ssp.JOINT, JOINT_TRACED))]
        execution.step(1)      # libcosim initialises the FMUs in its first step: t = 0 is not observable
        trace = _stepwise("libcosim", step_s, _steps(stop_time_s, step_s), lambda: execution.step(1),
                          lambda: [x for index, r in groups for x in observer.last_real_values(index, r)],
                          time.perf_counter() - start)
        trace = align_joint(trace)
        trace.time_s += step_s
        profile = [refs[ssp.JOINT][n] for n in _profile_names(n_points)]
        trace.wear_depth_m = np.array(observer.last_real_values(slaves[ssp.JOINT], profile))
    return trace


def _load_ecos():
    """ecospy, its library's libtbb.so.12 (pip package ``tbb``, in the environment's lib, or the base
    interpreter's for a venv that sees its packages) loaded first."""
    import sys

    libs = [lib for prefix in dict.fromkeys((sys.prefix, sys.base_prefix))
            for lib in sorted(Path(prefix, "lib").glob("libtbb.so.12*"))]
    if libs:
        ctypes.CDLL(str(libs[0]), mode=ctypes.RTLD_GLOBAL)
    try:
        import ecospy
    except (ImportError, OSError) as exc:
        raise MasterUnavailable(str(exc)) from exc
    return ecospy


def run_ecos(ssp_path, step_s: float, stop_time_s: float, n_points: int) -> MasterTrace:
    """The package in ecos at ``step_s`` [s] up to ``stop_time_s`` [s], its parameter set applied."""
    from unittest import mock

    ecospy = _load_ecos()
    ecospy.EcosLib.set_log_level("warn")
    start = time.perf_counter()
    # ecos unpacks the package into $TMPDIR/ecos_ssp_<uuid> and leaves it there (1.2 MB a run): into a folder of
    # this run's, removed after it
    with tempfile.TemporaryDirectory(prefix="wearjoint_ecos_") as tmp:
        with mock.patch.dict(os.environ, TMPDIR=tmp):     # the C library's getenv sees it
            simulation = ecospy.EcosSimulation(ssp_path=str(ssp_path), step_size=step_s)
        try:
            if not simulation.init(parameter_set=ssp.PARAMETER_SET):
                raise RuntimeError(f"ecos could not initialise {ssp_path}: {ecospy.EcosLib.get_last_error()}")
            names = [f"{component}::{name}" for component, name in TRACED]
            trace = _stepwise("ecos", step_s, _steps(stop_time_s, step_s), simulation.step,
                              lambda: [simulation.get_real(name) for name in names], time.perf_counter() - start)
            trace.wear_depth_m = np.array([simulation.get_real(f"{ssp.JOINT}::{n}")
                                           for n in _profile_names(n_points)])
            simulation.terminate()
        finally:
            simulation.free()
    return trace


def run_fmpy_ssp(ssp_path, step_s: float, stop_time_s: float, n_points: int) -> MasterTrace:
    """The package in fmpy's SSP simulator at ``step_s`` [s] up to ``stop_time_s`` [s]."""
    from types import SimpleNamespace

    from fmpy.ssp.simulation import simulate_ssp
    from fmpy.ssp.ssd import read_ssd

    start = time.perf_counter()
    parameters = [SimpleNamespace(name=f"{component}.{name}", value=value)
                  for (component, name), value in ssp.bound_parameters(read_ssd(str(ssp_path))).items()]
    n = _steps(stop_time_s, step_s)
    load = time.perf_counter() - start
    start = time.perf_counter()
    # its loop runs while time < stop_time, time += step: (n + 1/2) steps make n + 1; row i is the end of step i
    try:
        rows = simulate_ssp(str(ssp_path), stop_time=(n + 0.5) * step_s, step_size=step_s,
                            parameter_set=SimpleNamespace(parameters=parameters))
    except Exception as exc:      # fmpy's FMICallException: its simulator keeps no rows of a run it aborts
        raise RunDiverged(f"the run diverged: fmpy's SSP simulator stopped ({exc}): the joint FMU refuses inputs deeper "
                          "in the bushing wall than any contact (fmi2Discard: the FMU's log line on stderr names the "
                          "inputs); the "
                          f"communication step {step_s:g} s is too long for this contact; fmpy keeps no rows of the "
                          "run (docs/explanation/cosim_study.md)") from None
    wall = time.perf_counter() - start
    values = np.column_stack([rows[f"{component}.{name}"] for component, name in TRACED])
    return align_joint(MasterTrace("fmpy-ssp", step_s, (np.arange(len(rows)) + 1) * step_s, values, None, wall, load))


def _load_omsimulator():
    """OMSimulator's C API (``OMSimulator.capi.Capi``; importing it loads ``libOMSimulator.so``)."""
    try:
        from OMSimulator.capi import Capi
    except (ImportError, OSError) as exc:
        raise MasterUnavailable(str(exc)) from exc
    return Capi


def run_omsimulator(ssp_path, step_s: float, stop_time_s: float, n_points: int) -> MasterTrace:
    """The package in OMSimulator at ``step_s`` [s] up to ``stop_time_s`` [s]: its log to a file that stays
    (the last run's, in the user's cache; quoted in the error if a call fails), its warnings and errors in the trace."""
    capi = _load_omsimulator()
    lib = capi.obj
    lib.oms_importFile.argtypes = [ctypes.c_char_p, ctypes.POINTER(ctypes.c_char_p)]
    n = _steps(stop_time_s, step_s)
    log = user_cache_dir() / "omsimulator" / "last_run.log"     # OMSimulator prints its path: it stays
    log.parent.mkdir(parents=True, exist_ok=True)
    log.unlink(missing_ok=True)                                   # the last run's only
    with tempfile.TemporaryDirectory(prefix="wearjoint_omsimulator_") as tmp:

        def check(status, what: str) -> None:
            if getattr(status, "value", status) != 0:   # oms_status_ok; warnings too end the run (OMSimulator's)
                text = log.read_text(errors="replace").strip().splitlines() if log.exists() else []
                raise RuntimeError(f"OMSimulator: {what} failed ({status}): {' | '.join(text[-3:])}")

        start = time.perf_counter()
        capi.setLogFile(str(log))
        model = None
        try:
            capi.setTempDirectory(tmp)
            cref = ctypes.c_char_p()
            check(lib.oms_importFile(str(Path(ssp_path).resolve()).encode(), ctypes.byref(cref)), "importFile")
            model = cref.value.decode()
            system = f"{model}.{ssp.SSP_NAME}"
            check(capi.setResultFile(model, "", 1), "setResultFile")
            check(capi.setFixedStepSize(system, step_s), "setFixedStepSize")
            check(capi.setStopTime(model, (n + 1) * step_s), "setStopTime")
            check(capi.instantiate(model), "instantiate")
            check(capi.initialize(model), "initialize")
            value = ctypes.c_double()
            names = [f"{system}.{component}.{name}".encode() for component, name in TRACED]

            def read(crefs=names):
                out = []
                for name in crefs:
                    check(lib.oms_getReal(name, ctypes.byref(value)), f"getReal({name.decode()})")
                    out.append(value.value)
                return out

            clock = iter(range(1, n + 1))
            # stepUntil runs while its time < the target: half a step short of the next point makes one step
            trace = _stepwise("omsimulator", step_s, n,
                              lambda: check(lib.oms_stepUntil(model.encode(), (next(clock) - 0.5) * step_s),
                                            "stepUntil"), read, time.perf_counter() - start)
            profile = [f"{system}.{ssp.JOINT}.{name}".encode() for name in _profile_names(n_points)]
            trace.wear_depth_m = np.array(read(profile))
            check(capi.terminate(model), "terminate")
        finally:
            if model is not None:
                capi.delete(model)
            capi.setLogFile("")   # back to the console (it prints where the log is)
    trace.log = tuple(line for line in (log.read_text(errors="replace") if log.is_file() else "").splitlines()
                      if "warning" in line.lower() or "error" in line.lower())     # no file: it logged nothing
    return trace


def run_container(ssp_path, step_s: float, stop_time_s: float, n_points: int, fmusim: str | None = None) -> MasterTrace:
    """The package as an fmpy container FMU (fixed step ``step_s`` [s]) up to ``stop_time_s`` [s],
    run by fmpy's ``FMU2Slave``, or by the fmusim binary ``fmusim`` when given."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    n = _steps(stop_time_s, step_s)
    names = [ssp.container_variable(component, name) for component, name in TRACED]
    with tempfile.TemporaryDirectory(prefix="wearjoint_container_") as tmp:
        start = time.perf_counter()
        fmu = ssp.container_fmu(ssp_path, Path(tmp) / ssp.CONTAINER_FILE_NAME, step_s)
        if fmusim is not None:
            return _fmusim(fmusim, fmu, names, step_s, n, time.perf_counter() - start)
        md = read_model_description(str(fmu))
        vrs = {v.name: v.valueReference for v in md.modelVariables}
        slave = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(fmu), unzipdir=Path(tmp) / "unzipped"),
                          modelIdentifier=md.coSimulation.modelIdentifier, instanceName="container")
        slave.instantiate()
        try:
            slave.setupExperiment(startTime=0.0)
            slave.enterInitializationMode()
            slave.exitInitializationMode()
            traced = [vrs[name] for name in names]
            clock = iter(range(n))
            trace = _stepwise("container", step_s, n, lambda: slave.doStep(next(clock) * step_s, step_s),
                              lambda: slave.getReal(traced), time.perf_counter() - start)
            profile = [vrs[ssp.container_variable(ssp.JOINT, name)] for name in _profile_names(n_points)]
            trace.wear_depth_m = np.array(slave.getReal(profile))
            slave.terminate()
        finally:
            slave.freeInstance()
    return trace


def _fmusim(fmusim: str, fmu: Path, names, step_s: float, n: int, load_time_s: float) -> MasterTrace:
    """The container in fmusim, every communication point written to its CSV; a run fmusim ends with an error (the
    joint refused a step) is the trace of the rows it wrote, its ``failure`` fmusim's message (none written: an
    error)."""
    out = fmu.with_suffix(".csv")
    # fmusim stops a few steps short of --stop-time (its time accumulates): ask for more, keep n steps
    command = [fmusim, "--interface-type", "cs", "--stop-time", repr((n + 20) * step_s), "--output-interval",
               repr(step_s), *(a for name in names for a in ("--output-variable", name)), "--output-file", str(out),
               str(fmu)]
    start = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True)
    wall = time.perf_counter() - start
    failure = "" if done.returncode == 0 else \
        f"fmusim exited with status {done.returncode}: {(done.stderr or done.stdout).strip()[-500:]}"
    rows = np.atleast_1d(np.genfromtxt(out, delimiter=",", names=True, deletechars="")) if out.is_file() else []
    if failure and len(rows) < 2:
        raise RuntimeError(failure)
    rows = rows[:n + 1]
    values = np.column_stack([rows[name] for name in names])
    return MasterTrace("container-fmusim", step_s, np.asarray(rows["time"]), values, None, wall, load_time_s, failure)


RUNNERS = {"libcosim": run_libcosim, "ecos": run_ecos, "fmpy-ssp": run_fmpy_ssp, "omsimulator": run_omsimulator,
           "container": run_container}


def _recorded_doubles(master: str, ssp_path) -> int:
    """Doubles a master keeps per communication point: fmpy's SSP simulator every variable of the package's FMUs
    (2245 at 1257 points: 3.3 GB for 2 revolutions at 5 us), the others the traced values."""
    if master != "fmpy-ssp":
        return len(TRACED)
    from fmpy import read_model_description

    with zipfile.ZipFile(ssp_path) as package:
        return 1 + sum(len(read_model_description(io.BytesIO(package.read(name))).modelVariables)
                       for name in package.namelist() if name.endswith(".fmu"))


def run_package(master: str, ssp_path, joint, mechanism, revolutions: float, step_s: float, sample_dt_s: float,
                fmusim: str | None = None, load_coupling: str | None = None) -> RunRecord:
    """``revolutions`` crank revolutions of the package ``ssp_path`` (exported with ``joint``, ``mechanism`` and,
    if given, ``load_coupling``) through the third-party ``master`` at the communication step ``step_s`` [s]."""
    if master not in RUNNERS:
        raise ValueError(f"master={master!r}: allowed one of {', '.join(THIRD_PARTY)}")
    stop_time = revolutions * mechanism.period_s
    check_time_series_fits(revolutions, mechanism.period_s, step_s, _recorded_doubles(master, ssp_path),
                           f"{master}'s communication step", "fewer revolutions per run: the master keeps every point")
    extra = {"fmusim": fmusim} if master == "container" and fmusim else {}
    trace = RUNNERS[master](ssp_path, step_s, stop_time, joint.n_points, **extra)
    parameters = RunParameters("cosim", joint, mechanism,
                               details={"master": master, "communication_step_s": step_s, "fmusim": fmusim,
                                        **({"load_coupling": load_coupling} if load_coupling else {})})
    return record_from_trace(trace, joint, mechanism, sample_dt_s, parameters)


def run_master(master: str, joint, mechanism, revolutions: float, step_s: float, sample_dt_s: float,
               fmusim: str | None = None, load_coupling: str = "linearised") -> RunRecord:
    """:func:`run_package` on the package exported with these parameters, step and ``load_coupling``
    (:data:`wearjoint.fmu.ssp.LOAD_COUPLINGS`; linux64 binaries) into a temporary folder."""
    with tempfile.TemporaryDirectory(prefix="wearjoint_master_") as tmp:
        path = ssp.export_ssp(tmp, mechanism=mechanism, joint=joint, stop_time=revolutions * mechanism.period_s,
                              platforms="linux64", step_s=min(step_s, revolutions * mechanism.period_s),
                              load_coupling=load_coupling)
        return run_package(master, path, joint, mechanism, revolutions, step_s, sample_dt_s, fmusim, load_coupling)


def master_available(master: str) -> str | None:
    """None if ``master`` can run here, else what is missing."""
    try:
        if master == "libcosim":
            import libcosimpy  # noqa: F401
        elif master == "ecos":
            _load_ecos()
        elif master in ("fmpy-ssp", "container"):
            import fmpy  # noqa: F401
        elif master == "omsimulator":
            _load_omsimulator()
    except (ImportError, OSError) as exc:   # MasterUnavailable is an ImportError
        return f"{master} needs {_PACKAGES[master]} ({type(exc).__name__}: {exc})"
    return None
