"""The coupling-accuracy study's pieces: the conforming groove it wears into a bushing, its statistics and z."""
import math

import numpy as np
import pytest

from wearjoint.core.geometry import bushing_point_angles
from wearjoint.parameters import paper_joint
from wearjoint.studies.coupling_accuracy import conforming_groove, z_scores

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
