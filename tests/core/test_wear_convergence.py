"""The wear of a load-carrying pin in the slider-crank does not depend on the step (docs/model.md §3.11, §7).

The explicit update with the end-of-step force wore 375 / 318 / 296 / 286 um in two revolutions at
10 / 5 / 2.5 / 1.25 us (printed k_w, wear factor 100: a share lambda = 0.73 at 10 us): +31 % at the
default step.  The relaxed update with the step's mean force must sit within 2 % of the extrapolation
to a vanishing step.
"""
import pytest

from wearjoint import paper_joint
from wearjoint.simulate import SimulationOptions, run_simulation


@pytest.mark.slow
def test_printed_wear_coefficient_at_wear_factor_100_wears_the_same_at_every_step():
    joint = paper_joint(wear_factor=100.0)
    depth = {h: run_simulation(joint, options=SimulationOptions(revolutions=2, integrator="rk4", step_s=h),
                               progress=False).summary()["max_wear_depth_m"] for h in (1e-5, 5e-6, 2.5e-6)}
    extrapolated = 2.0 * depth[2.5e-6] - depth[5e-6]            # first order in the step
    assert 2.5e-4 < extrapolated < 3.2e-4
    for h, d in depth.items():
        assert d == pytest.approx(extrapolated, rel=0.02), (h, d, extrapolated)
