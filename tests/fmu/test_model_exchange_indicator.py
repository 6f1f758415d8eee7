"""The joint FMU's Model Exchange event indicator, the signed penetration, as third-party root finders meet it: a
pin touching the bushing (penetration exactly 0) is on the contact's side (DBL_MIN), so a root finder that lands on
an exact zero sees a sign change or none, never a zero it cannot leave; the Reference-FMUs' fmusim with CVODE stopped
("cvRcheck2: root found at and very near t") where a pin left its worn groove slowly, and runs through now, wearing
what Co-Simulation wears."""
from __future__ import annotations

import ctypes
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy_instance import Joint  # noqa: E402
from third_party_tools import FMUSIM  # noqa: E402

from wearjoint import JointParameters  # noqa: E402

CLEARANCE_M = JointParameters().clearance_m


@pytest.mark.parametrize("version", [2, 3])
def test_a_touching_pin_is_on_the_contacts_side_of_the_indicator(fmus, version):
    """The pin centre exactly a clearance from the bushing centre: penetration 0 as an output, the indicator the
    smallest positive double (>= 0: contact, as the in-process Model Exchange reads it); 1 um in and out: the
    penetration itself (FMI 2.0 and 3.0)."""
    joint = Joint(fmus[version], version, "me").start(JointParameters(wear_factor=0.0))
    try:
        indicator = (ctypes.c_double * 1)()
        for offset, expected in ((0.0, sys.float_info.min), (1e-6, None), (-1e-6, None)):
            joint.set(["pin_x"], [CLEARANCE_M + offset])
            penetration, = joint.get(["penetration"])
            joint.fmu.getEventIndicators(indicator, 1)
            if expected is None:
                assert penetration == pytest.approx(offset, abs=1e-15) and indicator[0] == penetration
            else:
                assert penetration == 0.0 and indicator[0] == expected
    finally:
        joint.free()


def _orbit_csv(path: Path, stop_s: float, dt_s: float = 1e-5) -> Path:
    """A pin orbiting the bushing centre at 30 rad/s, a clearance + 4 um sin(900 t) from it, turning at 15.7
    rad/s: in contact half the time, leaving the groove it wears slowly."""
    t = np.arange(0.0, stop_s + dt_s / 2, dt_s)
    r, phi = CLEARANCE_M + 4e-6 * np.sin(900.0 * t), 30.0 * t
    rows = np.column_stack([t, r * np.cos(phi), r * np.sin(phi), 15.7 * t, np.full_like(t, 15.7)])
    np.savetxt(path, rows, delimiter=",", header="time,pin_x,pin_y,pin_angle,pin_omega", comments="", fmt="%.17g")
    return path


def _fmusim(fmu: Path, interface: str, inputs: Path, out: Path, stop_s: float) -> dict:
    args = [FMUSIM, "--interface-type", interface, *(["--solver", "cvode"] if interface == "me" else []),
            "--stop-time", str(stop_s), "--output-interval", "1e-5", "--input-file", str(inputs),
            "--output-file", str(out), str(fmu)]
    done = subprocess.run(args, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0 and "ERROR" not in done.stdout + done.stderr, done.stdout + done.stderr
    header = [h.strip('"') for h in out.read_text().splitlines()[0].split(",")]
    last = np.loadtxt(out, delimiter=",", skiprows=1, ndmin=2)[-1]
    return {name: last[header.index(name)] for name in ("time", "worn_volume", "max_wear_depth")}


def test_fmusim_with_cvode_runs_through_a_slow_separation_and_wears_what_co_simulation_wears(native_fmu, tmp_path):
    if not Path(FMUSIM).is_file():
        pytest.skip(f"no fmusim at {FMUSIM} ($FMUSIM; ../shared/tools/fmusim builds it)")
    stop = 0.01
    inputs = _orbit_csv(tmp_path / "orbit.csv", stop)
    me = _fmusim(native_fmu, "me", inputs, tmp_path / "me.csv", stop)
    cs = _fmusim(native_fmu, "cs", inputs, tmp_path / "cs.csv", stop)
    assert math.isclose(me["time"], stop - 1e-5, rel_tol=1e-9) or math.isclose(me["time"], stop, rel_tol=1e-9)
    assert me["worn_volume"] > 0.0
    assert me["worn_volume"] == pytest.approx(cs["worn_volume"], rel=1e-3)
    assert me["max_wear_depth"] == pytest.approx(cs["max_wear_depth"], rel=1e-3)
