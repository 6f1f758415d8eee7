"""The co-simulation master compiled ahead of time (wearjoint/cosim/native_master.py): the library built from the
shipped IR of the master's numba kernels runs numba's master step for step, to the last bit; where it cannot be
built the master runs numba's kernels."""
import numpy as np
import pytest

from wearjoint.core import layout as L
from wearjoint.cosim import CoSimulation, CoSimulationOptions, cosimulation, native_master
from wearjoint.cosim.master_loop import B_INPUT, B_TRIG, master_loop
from wearjoint.parameters import SliderCrankParameters, paper_joint


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
        cosimulation.communication_step(0.0, 0.0, False, numba, *cosimulation.buffer_views.py_func(numba),
                                        sim.mechanism.workspace, np.zeros((0, L.N_SAMPLE_COLUMNS)))
        native_master.native_master().start_point(native)
        for part in (slice(B_TRIG, B_TRIG + 7), slice(B_INPUT, B_INPUT + 12)):
            np.testing.assert_array_equal(native[part], numba[part])
        assert np.any(native[B_INPUT:B_INPUT + 12] != 0.0) and native[B_TRIG + 6] > 0.0


def test_without_a_c_compiler_the_master_runs_numbas_kernels(native_fmu, tmp_path, monkeypatch):
    """No library in the cache and no compiler to link one: no error, numba's master runs (the same numbers)."""
    monkeypatch.setattr(native_master, "library_path", lambda: tmp_path / "master" / "wearjoint_master.so")
    monkeypatch.setenv("CC", str(tmp_path / "no-such-compiler"))
    native_master.native_master.cache_clear()
    try:
        assert native_master.native_master() is None
        with CoSimulation(paper_joint(), None, CoSimulationOptions(revolutions=0.01), fmu_path=native_fmu) as sim:
            assert sim._master_loop is master_loop
            assert sim.advance_to(0.002, np.zeros((300, L.N_SAMPLE_COLUMNS))) > 0 and sim.communication_steps > 0
        assert not (tmp_path / "master").exists() or not any((tmp_path / "master").iterdir())
    finally:
        native_master.native_master.cache_clear()
