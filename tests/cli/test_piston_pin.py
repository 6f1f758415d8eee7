"""A mechanism besides the paper's: a compressor's piston pin (the clearance at the rod-slider joint, a 6 mm pin in
a 6.08 mm bushing) under a steady 150 N load with gravity along the slide towards the crank.  After the start-up it
never leaves contact: the summary names that regime, and a validation names the metric its one-sided wear leaves
undefined."""
import json
import subprocess
import sys

import pytest

from wearjoint import SliderCrankParameters
from wearjoint.parameters import paper_joint
from wearjoint.simulate import SimulationOptions, run_simulation

MECHANISM = SliderCrankParameters(crank_length_m=0.03, rod_length_m=0.15, rod_mass_kg=0.4, rod_inertia_kg_m2=7.5e-4,
                                  crank_speed_rpm=240.0, slider_mass_kg=1.5, slider_force_N=150.0,
                                  gravity_m_s2=(-9.81, 0.0), clearance_joint="rod-slider")
JOINT = {"pin_radius_m": 0.006, "bushing_radius_m": 0.00608, "contact_length_m": 0.012}
OPTIONS = ["--crank-length-m", "0.03", "--rod-length-m", "0.15", "--rod-mass-kg", "0.4", "--rod-inertia-kg-m2",
           "7.5e-4", "--crank-speed-rpm", "240", "--slider-mass-kg", "1.5", "--slider-force-N", "150",
           "--gravity-m-s2=-9.81,0", "--clearance-joint", "rod-slider", "--pin-radius-m", "0.006",
           "--bushing-radius-m", "0.00608", "--contact-length-m", "0.012"]


def test_a_joint_that_never_leaves_contact_after_the_start_up_is_in_permanent_contact():
    """After the start-up (the pin starts centred, out of contact) it never separates, so the regime is permanent
    contact, not impacting; the joint carries the ideal joint's force; an unworn bushing has no deepest point (its
    angle is null, not the first point's)."""
    joint = paper_joint(MECHANISM, wear_factor=0.0, **JOINT)
    summary = run_simulation(joint, MECHANISM, SimulationOptions(revolutions=2), progress=False).summary()
    assert summary["regime"] == "permanent contact" and summary["contact_fraction"] == 1.0
    assert summary["impacts_per_revolution"] == 0 and summary["start_up"]["revolutions"] == 1
    assert summary["max_contact_force_N"] == pytest.approx(summary["ideal_joint_force_max_N"], rel=0.01)
    assert summary["max_wear_depth_m"] == 0.0 and summary["max_wear_angle_deg"] is None


def test_validate_names_the_metrics_a_one_sided_wear_leaves_undefined(tmp_path):
    """The pin wears one half of its bushing only: the lobe near 0 deg has no angle, so that metric is not judged,
    and the verdict, summary.json and report.md say so (it was dropped: "14 of 14", nothing said)."""
    done = subprocess.run([sys.executable, "-m", "wearjoint.cli", "validate", "--quick", *OPTIONS,
                           "--wear-coefficient-m2-N", "1e-13", "--engines", "monolithic,cosim", "--no-law-spread",
                           "--out", str(tmp_path)], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["metrics_undefined"] == ["cosim: lobe_angle_near_0_deg"]
    assert "(1 undefined: cosim: lobe_angle_near_0_deg)" in done.stdout
    assert "- cosim: lobe_angle_near_0_deg: undefined, not judged" in (tmp_path / "report.md").read_text()
