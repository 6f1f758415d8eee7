"""The wear factor's bias of a run's max depth (wearjoint.sweep.bias): stated where it was measured, shared by runs
that agree in it."""
from wearjoint.sweep.bias import WEAR_FACTOR_BIAS, common_bias, wear_factor_bias


def test_wear_factor_bias_is_stated_only_where_measured():
    assert wear_factor_bias(100.0, 1000).rel == WEAR_FACTOR_BIAS[100.0][1000]
    assert wear_factor_bias(1.0, 1234).rel == 0.0 and wear_factor_bias(0.0, 10).rel == 0.0   # no factor, no wear
    assert wear_factor_bias(100.0, 5000).rel is None and wear_factor_bias(20.0, 1000).rel is None
    assert wear_factor_bias(100.0, 1000, cycle_jump=True).rel is None
    # cycle jumping runs at F = 1: no wear-factor bias (it had said "unknown"), where its own estimate is named
    jumped = wear_factor_bias(1.0, 300_000, cycle_jump=True)
    assert jumped.rel == 0.0 and "summary.json's cycle_jumping" in jumped.note
    assert wear_factor_bias(20.0, 1000).text == "unknown"


def test_runs_that_agree_in_bias_share_it():
    """A sensitivity study's cycle-jumping runs (F = 1 each) said "bias unknown: the runs differ in wear factor or
    revolutions"; runs that differ in value are unknown still, runs of one value with different reasons name both."""
    runs = {wear_factor_bias(1.0, 20, cycle_jump=True), wear_factor_bias(1.0, 40, cycle_jump=True)}
    shared = common_bias(runs)
    assert shared.rel == 0.0 and shared.text == "0 %" and "each run's summary.json" in shared.note
    assert common_bias({wear_factor_bias(1.0, 20)}) == wear_factor_bias(1.0, 20)
    assert common_bias(runs | {wear_factor_bias(20.0, 1000)}).rel is None
    both = common_bias({wear_factor_bias(1.0, 20), wear_factor_bias(0.0, 20)})
    assert both.rel == 0.0 and both.note == "none: F = 1 (brute force); none: no wear"


def test_the_measured_bias_belongs_to_the_paper_case_only():
    """The table was measured on the paper's mechanism and joint at k_w 5.576e-11: another mechanism, joint
    geometry or k_w gets unknown and the command that measures it for its own case and horizon."""
    from wearjoint.parameters import SliderCrankParameters, paper_joint
    from wearjoint.sweep.bias import summary_biases

    def summary(mechanism=SliderCrankParameters(), **changes):
        joint = paper_joint(mechanism, **{"wear_coefficient_m2_N": 5.576e-11, "wear_factor": 100.0, **changes})
        return {"revolutions": 10.0, "parameters": {"joint": joint.to_dict(), "mechanism": mechanism.to_dict()}}

    assert summary_biases(summary())["max_wear_depth_m"].rel == WEAR_FACTOR_BIAS[100.0][1000]
    seeded = summary(SliderCrankParameters(initial_crank_angle_deg=0.5))
    assert summary_biases(seeded)["max_wear_depth_m"].rel == WEAR_FACTOR_BIAS[100.0][1000]
    for other in (summary(SliderCrankParameters(crank_speed_rpm=300.0)), summary(bushing_radius_m=0.0102),
                  summary(wear_coefficient_m2_N=1e-12)):
        bias = summary_biases(other)["max_wear_depth_m"]
        assert bias.rel is None
        assert "--convergence jump,100 --revolutions 1000" in bias.note
