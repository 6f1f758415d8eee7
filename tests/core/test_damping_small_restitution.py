"""Tsuji's law asked for a small restitution (docs/reference/model.md §3.5, core.damping): gamma solved for e down to
1e-300 gives that e back, the heavily damped impact integrated on its own time scale agrees with an independent
solution, and contact-law reports the smallest a joint takes (the RK4 at a step of 0.02/gamma through the force-free flight back ran over a
minute for e = 1e-4 and never ended for 1e-8)."""
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from wearjoint.cli import main
from wearjoint.core import damping


@pytest.mark.parametrize("n", [1.0, 1.5, 3.0])
@pytest.mark.parametrize("e", [1e-2, 1e-4, 1e-8, 1e-16, 1e-300])
def test_tsuji_damping_gives_back_a_small_restitution(e, n):
    gamma = damping.tsuji_damping(e, n)
    assert damping.tsuji_restitution(gamma, n) == pytest.approx(e, rel=1e-6)
    assert e * gamma ** 2 == pytest.approx(0.5 * (n + 1.0), rel=0.1)     # the heavy damping's limit (n+1)/(2 gamma^2)


def reference_restitution(gamma: float, n: float) -> float:
    """The impact x'' = -max(0, x^n + gamma x^((n-1)/2) x'), x(0) = 0, x'(0) = 1 by scipy's Radau to x = 0."""
    p = 0.5 * (n - 1.0)

    def rhs(_, y):
        x = max(y[0], 0.0)
        return [y[1], -max(0.0, x ** n + gamma * x ** p * y[1])]

    def back(_, y):
        return y[0] + 1e-300       # crossing 0 downwards, not the start at 0

    back.terminal, back.direction = True, -1
    run = solve_ivp(rhs, (0.0, 1e9), [0.0, 1.0], method="Radau", events=back, rtol=1e-10, atol=1e-14)
    return -float(run.y_events[0][0][1])


@pytest.mark.parametrize("gamma", [30.0, 300.0, 3000.0])
def test_a_heavily_damped_impact_rebounds_as_an_independent_solution_says(gamma):
    assert damping.tsuji_restitution(gamma, 1.5) == pytest.approx(reference_restitution(gamma, 1.5), rel=1e-3)


def test_the_restitution_falls_with_gamma_across_the_heavy_and_limit_branches():
    gammas = [9.99, 10.0, 10.01, 9990.0, 9999.99, 1e4, 1.001e4, 1e150]
    values = [damping.tsuji_restitution(g, 1.5) for g in gammas]
    assert all(b < a for a, b in zip(values, values[1:])) and values[-1] > 0.0


def test_contact_law_reports_the_smallest_restitution_a_joint_takes_and_refuses_a_smaller(tmp_path, capsys):
    """e_r from 1e-3 (JointParameters' floor: the joint chattered below it, and from 1e-8 its first impact passed the
    admissible force); the kernels above hold for any e."""
    out = tmp_path / "law"
    assert main(["contact-law", "--restitution", "1e-3", "--out", str(out), "--no-plots", "--quiet"]) == 0
    table = np.genfromtxt(out / "contact_law.csv", delimiter=",", names=True)
    for law in ("tsuji", "lankarani_nikravesh_exact"):
        assert np.allclose(table["restitution_" + law], 1e-3, rtol=1e-6, atol=0.0)
    capsys.readouterr()
    assert main(["contact-law", "--restitution", "1e-4", "--out", str(tmp_path / "refused"), "--quiet"]) == 2
    assert "--restitution=1e-4 (restitution) is invalid: allowed in [0.001, 1]" in capsys.readouterr().err
