"""The coupling-accuracy study's pieces: the conforming groove it wears into a bushing, its statistics and z."""
import math

import numpy as np
import pytest

from wearjoint.core.geometry import bushing_point_angles
from wearjoint.parameters import paper_joint
from wearjoint.studies.coupling_accuracy import case_setup, conforming_groove, relative_differences, table, z_scores

JOINT = paper_joint(wear_factor=0.0)


@pytest.mark.parametrize("direction", [0.3, 2.0, -2.8])
def test_a_conforming_groove_is_the_pins_circle_pushed_depth_past_the_clearance(direction):
    depth = 0.58e-3
    wear = conforming_groove(JOINT, depth, direction)
    phi = bushing_point_angles(JOINT.n_points)
    rho = JOINT.bushing_radius_m + wear
    e = JOINT.bushing_radius_m - JOINT.pin_radius_m + depth
    centre = e * np.array([math.cos(direction), math.sin(direction)])
    distance = np.hypot(rho * np.cos(phi) - centre[0], rho * np.sin(phi) - centre[1])
    worn = wear > 0.0
    # every worn point lies on the pin's circle; every unworn one outside it (or on it at the groove's edges)
    assert np.allclose(distance[worn], JOINT.pin_radius_m, rtol=0, atol=1e-12)
    assert np.all(distance[~worn] >= JOINT.pin_radius_m - 1e-12)
    # the deepest point is the direction's, depth + 0 there: R_j + depth = e + R_i - c
    deepest = np.argmax(wear)
    assert abs(math.remainder(phi[deepest] - direction, 2 * math.pi)) <= 2 * math.pi / JOINT.n_points
    assert wear.max() == pytest.approx(depth, rel=1e-6)
    # its width: the pin's circle meets the bushing where cos(a) = (e^2 + R_j^2 - R_i^2) / (2 e R_j)
    half = math.acos((e * e + JOINT.bushing_radius_m ** 2 - JOINT.pin_radius_m ** 2) / (2 * e * JOINT.bushing_radius_m))
    assert worn.sum() == pytest.approx(2 * half / (2 * math.pi) * JOINT.n_points, abs=2)


def test_z_is_the_difference_in_combined_standard_errors():
    statistic = {"mean": 10.0, "se": 3.0}
    reference = {"mean": 2.0, "se": 4.0}
    names = ("impacts_per_revolution", "contact_fraction", "max_normal_force_N", "chattering_share")
    z = z_scores({k: statistic for k in names}, {k: reference for k in names})
    assert z["impacts_per_revolution"] == pytest.approx(8.0 / 5.0)
    nil = {"mean": 1.0, "se": 0.0}
    assert z_scores({k: nil for k in names}, {k: nil for k in names})["contact_fraction"] == 0.0


def test_the_table_gives_each_statistics_difference_in_standard_errors_and_in_per_cent_of_the_reference():
    """Where the runs settle on one periodic motion the standard errors vanish and z alone says nothing of size: a
    row 0.1 % off the reference is z -21 (tight-joint's co-simulation at 1 us), so each cell gives both."""
    names = ("impacts_per_revolution", "contact_fraction", "max_normal_force_N", "chattering_share")
    reference = {k: {"mean": 2937.25, "se": 0.05} for k in names}
    row = {k: {"mean": 2933.46, "se": 0.17} for k in names}
    row["chattering_share"] = {"mean": 1.0, "se": 0.0}
    reference["chattering_share"] = {"mean": 1.0, "se": 0.0}
    relative = relative_differences(row, reference)
    assert relative["max_normal_force_N"] == pytest.approx(100 * (2933.46 - 2937.25) / 2937.25)
    assert relative["chattering_share"] == 0.0
    row["z"] = z_scores(row, reference)
    text = table([{"case": "tight-joint", "rows": {"monolithic rk4 2.5 us": {**reference, "steps_per_revolution": 0.0},
                                                    "cosim step_s=1e-6": {**row, "steps_per_revolution": 1.0}}}])
    assert "2.93e+03 ± 0.17 (z -21.4, -0.1 %)" in text
    assert "| tight-joint | monolithic rk4 2.5 us |  |  | 2.94e+03 ± 0.05 |" in text


def test_the_tight_joint_case_is_joint_j_in_the_papers_mechanism():
    """docs/how-to/choose_step_and_master.md's joint J: a 15 mm pin, 0.05 mm clearance, 10 mm long, a bronze bushing,
    friction 0.15, unworn and not wearing, in the paper's slider-crank."""
    joint, mechanism, profile = case_setup("tight-joint", 1.0)
    assert (joint.pin_radius_m, joint.bushing_radius_m - joint.pin_radius_m) == pytest.approx((0.015, 5e-5))
    assert (joint.contact_length_m, joint.friction_coefficient, joint.wear_factor) == (0.01, 0.15, 0.0)
    assert (joint.bushing_youngs_modulus_Pa, joint.bushing_poisson_ratio) == (110e9, 0.34)
    assert profile is None and mechanism == case_setup("paper", 1.0)[1]


def test_the_study_keeps_every_finished_row_when_a_later_one_fails(tmp_path, monkeypatch):
    """--out's JSON and table hold the reference and every finished configuration as the study goes: a master that
    fails after them leaves them on disk (a third-party master's row is labelled by its coupling and step)."""
    import json

    from wearjoint.studies import coupling_accuracy

    def failing(*args, **kwargs):
        raise RuntimeError("the master stopped")

    monkeypatch.setattr(coupling_accuracy, "run_master", failing)
    arguments = ["--cases", "paper", "--starts", "2", "--revolutions", "0.02", "--settling", "0", "--cosim-steps",
                 "5e-6", "--masters", "container", "--out", str(tmp_path)]
    with pytest.raises(RuntimeError, match="the master stopped"):
        coupling_accuracy.main(arguments)
    (case,) = json.loads((tmp_path / "coupling_accuracy.json").read_text())
    assert list(case["rows"]) == ["monolithic rk4 2.5 us", "cosim default", "cosim adaptive 5 us"]
    assert case["rows"]["cosim adaptive 5 us"]["steps_per_revolution"] > 0
    # the real-time factor is the simulations' alone: above the one of the wall time with loading and compiling
    simulated = 2 * 0.02 * coupling_accuracy.SliderCrankParameters().period_s
    for row in case["rows"].values():
        assert simulated / row["wall_s"] < row["realtime_factor"] < math.inf
    assert "| paper | cosim adaptive 5 us |" in (tmp_path / "coupling_accuracy.md").read_text()
