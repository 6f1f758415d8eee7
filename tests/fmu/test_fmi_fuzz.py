"""The native FMU under hypothesis state machines (tests/fmi_state_machines.py): FMI 2.0 and 3.0,
Co-Simulation and Model Exchange, legal and illegal call orders with odd values, and corrupted
serialised states.  Each machine runs in a child process: a crash of the FMU fails the test instead of
ending pytest.  The default suite runs a bounded number of examples; ``-m slow`` runs long."""
import json
import subprocess
import sys
from pathlib import Path

import pytest

fmpy = pytest.importorskip("fmpy")

MACHINES = ["calls-2-cs", "calls-2-me", "calls-3-cs", "calls-3-me", "corrupt-2", "corrupt-3"]
HERE = Path(__file__).resolve().parents[1]   # tests/, beside fmi_state_machines.py


@pytest.fixture(scope="module")
def fuzz_fmus(tmp_path_factory):
    """{FMI version: unzipped directory} of small native FMUs (64 bushing points, this machine's binary)."""
    from wearjoint.fmu.build_native import build_fmu

    dirs = {}
    for version in (2, 3):
        path = build_fmu(tmp_path_factory.mktemp(f"fuzz{version}"), n_points=64, fmi_version=version,
                         platform_names=["linux64"])
        dirs[version] = fmpy.extract(str(path), str(tmp_path_factory.mktemp(f"fuzz{version}_unzipped")))
    return dirs


def run_machine(fuzz_fmus, machine: str, examples: int, steps: int, env=None, derandomize: bool = False) -> dict:
    """Run one machine in a child process; its counts.  Fails on a crash or a property violated.
    ``derandomize``: the same examples every run (a bounded run then covers every rule every time)."""
    version = int(machine.split("-")[1])
    done = subprocess.run([sys.executable, str(HERE / "fmi_state_machines.py"), fuzz_fmus[version], machine,
                           str(examples), str(steps), *(["derandomize"] if derandomize else [])],
                          capture_output=True, text=True, timeout=3000, env=env)
    assert done.returncode == 0, f"{machine}: exit status {done.returncode}\n{done.stdout[-4000:]}\n{done.stderr[-6000:]}"
    counts = json.loads(done.stdout.strip().splitlines()[-1])
    print(machine, counts)
    return counts


def check_counts(machine: str, counts: dict) -> None:
    assert counts.get("non-finite outputs behind OK", 0) == 0
    if machine.startswith("calls"):
        assert counts["calls"] > 0 and counts.get("status 0", 0) > 0 and counts.get("status 3", 0) > 0
    else:
        corrupted = [k for k in counts if k.startswith("accepted") and "unchanged" not in k]
        assert not corrupted, counts
        for kind in ("flipped bits", "planted value", "truncated or extended"):
            unchanged = counts.get(f"accepted {kind} (unchanged bytes)", 0)   # flips that cancel
            assert counts.get(f"tried {kind}", 0) > 0 and counts[f"refused {kind}"] + unchanged == counts[f"tried {kind}"]


@pytest.mark.parametrize("machine", MACHINES)
def test_state_machine_bounded(fuzz_fmus, machine):
    check_counts(machine, run_machine(fuzz_fmus, machine, examples=25, steps=30, derandomize=True))


@pytest.mark.slow
@pytest.mark.parametrize("machine", MACHINES)
def test_state_machine_long(fuzz_fmus, machine):
    check_counts(machine, run_machine(fuzz_fmus, machine, examples=600, steps=60))


def test_a_huge_step_is_refused(fuzz_fmus):
    """A finite but absurd step in contact (h = 1e300 s would wear the bushing by 3.6e297 m) is refused
    with Discard and changes nothing: the worn profile stays unworn, a sane step then runs with
    finite outputs."""
    from fmi_state_machines import DISCARD, OK, Instance, contact_inputs

    i = Instance(fuzz_fmus[2], 2, "cs")
    try:
        i.setup()
        i.fmu.enterInitializationMode()
        i.fmu.exitInitializationMode()
        i.set_reals(i.inputs, contact_inputs(4.77e-6, 0.0))
        assert i.do_step(0.0, 1e300) == DISCARD
        status, values = i.get_reals(i.outputs)
        assert status == OK and all(abs(v) < float("inf") for v in values), values
        assert values[i.outputs.index(i.vr["max_wear_depth"])] == 0.0
        assert i.do_step(0.0, 3e-5) == OK                # the whole wear interval: its wear applied at once
        status, values = i.get_reals(i.outputs)
        assert status == OK and all(abs(v) < float("inf") for v in values)
        assert 0.0 < values[i.outputs.index(i.vr["max_wear_depth"])] < 1e-6
    finally:
        i.fmu.freeInstance()
