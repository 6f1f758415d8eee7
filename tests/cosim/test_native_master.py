"""The co-simulation master compiled ahead of time (wearjoint/cosim/native_master.py): the library built from the
shipped IR of the master's numba kernels runs numba's master step for step, to the last bit; where it cannot be
built the master runs numba's kernels."""
import subprocess
import sys

import numpy as np
import pytest

from wearjoint.core import layout as L
from wearjoint.cosim import CoSimulation, CoSimulationOptions, cosimulation, native_master
from wearjoint.cosim.master_layout import B_INPUT, B_TRIG, buffer_views
from wearjoint.cosim.master_loop import communication_step, master_loop
from wearjoint.mechanism_parameters import SliderForceTable
from wearjoint.parameters import ParameterError, SliderCrankParameters, paper_joint
from wearjoint.simulate import SimulationOptions, run_simulation


def _run(options, fmu_path, mechanism, native: bool, monkeypatch):
    """The co-simulation's buffer, samples and counters after three chunks, its master native or numba's."""
    with monkeypatch.context() as patch:
        if not native:
            patch.setattr(cosimulation, "native_master", lambda: None)
        sim = CoSimulation(None, mechanism, options, fmu_path=fmu_path, fmu_backend="native")
    with sim:
        assert (sim._master_loop is master_loop) is not native
        sim.warm_up()
        samples, chunks = np.zeros((3000, L.N_SAMPLE_COLUMNS)), []
        for t in (0.004, 0.008, 0.012):
            n = sim.advance_to(t, samples)
            chunks.append(samples[:n].copy())
        return (sim.buf.copy(), np.concatenate(chunks), sim.wear_profile()[1],
                (sim.communication_steps, sim.rollbacks, sim.free_steps, sim.shrunk_steps, sim.miss_count))


@pytest.mark.parametrize("scheme", ["linearised", "adaptive", "zoh"])
def test_the_compiled_master_runs_numbas_step_for_step(scheme, native_fmu, monkeypatch):
    """Same buffer (state, statistics, recorder), samples, worn profile and counters after the first impacts, with
    wear, rollbacks to contact onsets (adaptive schemes) and the linearised coupling (the default), on the paper's
    mechanism and on one with its clearance at the crank's pivot and a load on the slider."""
    assert native_master.native_master() is not None, "the master's library was not built on this machine"
    options = CoSimulationOptions(revolutions=0.05, scheme=scheme, **({"step_s": 2e-6} if scheme == "zoh" else {}))
    for mechanism in (None, SliderCrankParameters(clearance_joint="crank-ground", slider_force_N=150.0)):
        native, numba = (_run(options, native_fmu, mechanism, flag, monkeypatch) for flag in (True, False))
        for a, b in zip(native[:3], numba[:3]):
            np.testing.assert_array_equal(a, b)
        assert native[3] == numba[3]
        steps, rollbacks = native[3][:2]
        assert steps > 100 and native[2].max() > 0.0 and (rollbacks > 0) == (scheme != "zoh")


def test_the_start_point_is_what_the_first_step_leaves(native_fmu):
    """start_point (native) writes the trigonometry and the FMU's inputs that numba's communication step over no
    time leaves at the start (the master's first inputs; the rotations of its trigonometry count from there)."""
    with CoSimulation(paper_joint(), None, CoSimulationOptions(revolutions=0.01), fmu_path=native_fmu) as sim:
        numba = sim.buf.copy()
        numba[B_TRIG:B_TRIG + 7] = 0.0
        numba[B_INPUT:B_INPUT + 12] = 0.0
        native = numba.copy()
        communication_step(0.0, 0.0, False, numba, *buffer_views(numba), sim.mechanism.workspace,
                           np.zeros((0, L.N_SAMPLE_COLUMNS)))
        native_master.native_master().start_point(native)
        for part in (slice(B_TRIG, B_TRIG + 7), slice(B_INPUT, B_INPUT + 12)):
            np.testing.assert_array_equal(native[part], numba[part])
        assert np.any(native[B_INPUT:B_INPUT + 12] != 0.0) and native[B_TRIG + 6] > 0.0


def test_without_a_c_compiler_the_master_runs_numbas_kernels(native_fmu, tmp_path, monkeypatch):
    """No library in the cache and no compiler to link one: no error, numba's master runs (the same numbers)."""
    monkeypatch.setattr(native_master, "library_path", lambda: tmp_path / "master" / "wearjoint_master.so")
    monkeypatch.setenv("CC", str(tmp_path / "no-such-compiler"))
    monkeypatch.setattr(native_master, "_loaded", None)
    monkeypatch.setattr(native_master, "_failed", False)
    monkeypatch.setattr(native_master, "_path", None)
    assert native_master.native_master(build=False) is None and not native_master._failed   # not built: not tried
    assert native_master.native_master() is None and native_master._failed
    with CoSimulation(paper_joint(), None, CoSimulationOptions(revolutions=0.01), fmu_path=native_fmu) as sim:
        assert sim._master_loop is master_loop
        assert sim.advance_to(0.002, np.zeros((300, L.N_SAMPLE_COLUMNS))) > 0 and sim.communication_steps > 0
    assert not (tmp_path / "master").exists() or not any((tmp_path / "master").iterdir())


def test_a_run_without_the_library_looks_its_path_up_once(tmp_path, monkeypatch):
    """A monolithic run where the library is not built (nobody co-simulated yet): the kernels it calls from Python
    ask for the library at every chunk (the divergence check's stiffness); its path, a hash of the kernels' sources,
    is computed once (each time, it halved the run's real-time factor), and a later ask still finds no library."""
    lookups = []

    def missing_library():
        lookups.append(1)
        return tmp_path / "master" / "wearjoint_master.so"

    monkeypatch.setattr(native_master, "library_path", missing_library)
    monkeypatch.setattr(native_master, "_loaded", None)
    monkeypatch.setattr(native_master, "_failed", False)
    monkeypatch.setattr(native_master, "_path", None)
    run = run_simulation(paper_joint(wear_factor=0.0), options=SimulationOptions(revolutions=1.0), progress=False)
    assert run.summary()["completed"] and len(lookups) == 1
    assert native_master.native_master(build=False) is None and len(lookups) == 1 and not native_master._failed


def test_a_cosimulation_with_its_library_built_imports_no_numba(tmp_path):
    """The README's first command, warm: the loop and the run's kernels come from the library, so neither numba
    nor scipy (numba's BLAS check) is imported; the results are the same files as numba's kernels write."""
    assert native_master.native_master() is not None
    code = ("import sys\nfrom wearjoint.cli import main\n"
            f"assert main(['cosim', '--revolutions', '0.05', '--no-plots', '--quiet', '--out', {str(tmp_path)!r}]) == 0\n"
            "loaded = [name for name in ('numba', 'scipy', 'llvmlite', 'matplotlib') if name in sys.modules]\n"
            "assert not loaded, loaded")
    subprocess.run([sys.executable, "-c", code], check=True, cwd=tmp_path)
    assert (tmp_path / "summary.json").is_file() and (tmp_path / "timeseries.npz").is_file()


def test_the_run_kernels_of_the_library_are_numbas(monkeypatch):
    """kernel_calls gives the library's results where it is built and numba's otherwise: the same numbers, on the
    paper's mechanism and one with its clearance at the slider and a load table on the slider."""
    from wearjoint import kernel_calls

    mechanisms = (SliderCrankParameters(), SliderCrankParameters(
        clearance_joint="rod-slider", crank_speed_rpm=300.0,
        slider_force_table=SliderForceTable((0.0, 90.0, 180.0, 360.0), (0.0, 400.0, 0.0, 0.0))))
    times = np.linspace(0.0, 0.2, 41)

    def results():
        out = []
        for mechanism in mechanisms:
            mp, workspace = kernel_calls.mechanism_arrays(mechanism)
            out += [mp, workspace[L.WORKSPACE_INVERSE_MASS], kernel_calls.initial_state(0.01, mp, workspace),
                    kernel_calls.ideal_joint_forces(times, mp, workspace)]
        return out + [kernel_calls.bushing_point_angles(1257), kernel_calls.effective_modulus(2.07e11, 0.29, 7.17e10, 0.33),
                      kernel_calls.materials_contact_stiffness(0.01, 0.0101, 5.0e10)]

    assert kernel_calls._library() is not None
    native = results()
    monkeypatch.setattr(kernel_calls, "_library", lambda: None)
    numba = results()
    for a, b in zip(native, numba):
        np.testing.assert_array_equal(a, b)
    assert np.ptp(native[3]) > 0.0 and np.ptp(native[7]) > np.ptp(native[3])    # the load shows in the reaction


def test_a_samples_array_the_compiled_loop_cannot_write_is_refused(native_fmu):
    """The loop writes the samples by address: an array of another type, layout or width is refused in one line
    naming it, before any step (a read-only one too)."""
    good = np.zeros((50, L.N_SAMPLE_COLUMNS))
    read_only = good.copy()
    read_only.flags.writeable = False
    with CoSimulation(paper_joint(), None, CoSimulationOptions(revolutions=0.01), fmu_path=native_fmu) as sim:
        for bad in (good.astype(np.float32), np.asfortranarray(good), good[:, :-1], good[::2], read_only,
                    good.tolist()):
            with pytest.raises(ParameterError, match=r"^parameter samples=.* is invalid: allowed a C-contiguous"):
                sim.advance_to(0.001, bad)
        with pytest.raises(ParameterError, match="t_end"):
            sim.advance_to(float("nan"), good)
        assert sim.communication_steps == 0 and sim.advance_to(0.001, good) > 0
