"""Contact damping laws (docs/reference/model.md §3.5): the coefficient each law's normal force uses, chosen so
that ``restitution`` is the coefficient of restitution of a single impact, and the restitution a
coefficient gives.

The laws (``jp[P_CONTACT_DAMPING]``), F_e the elastic force, delta_dot the penetration rate:

* 0, Hunt-Crossley: F_N = F_e max(0, 1 + alpha delta_dot), alpha constant.  A free impact at speed v
  rebounds at e where -a e - ln(1 - a e) = a - ln(1 + a), a = alpha v, for any elastic law F_e(delta)
  and any mass (integrate m v dv / (1 + alpha v) = -F_e d delta over the impact).  alpha = a(e_r) / v_r
  makes e_r exact at v_r; a slower impact rebounds more, a faster one less.
* 1, Lankarani-Nikravesh (paper Eq. 15): F_N = F_e (1 + chi delta_dot / delta_dot^-), chi = 3(1 - e_r^2)/4,
  delta_dot^- the approach speed stored at the onset: the closed form above with a = chi, the same
  restitution at every speed, but not e_r (0.913 for e_r = 0.9, 0.684 for 0.3).
* 2, Tsuji (Tsuji et al. 1992; Chrono's SMC): F_N = max(0, F_e + c sqrt(F_e / delta) delta_dot),
  c = gamma sqrt(m_eff): a damping gamma sqrt(m_eff k) with k = F_e / delta the contact's secant stiffness,
  gamma sqrt(m_eff K) delta^((n-1)/2) for F_e = K delta^n.  In units of the impact (delta* = (m v^2 / K)^(1/(n+1)),
  t* = delta*/v) an impact of a body of mass m_eff is x'' = -max(0, x^n + gamma x^((n-1)/2) x'), so its
  restitution depends on gamma and n only: not on the speed, nor on K.
* 3, Lankarani-Nikravesh exact: the paper's F_e (1 + chi delta_dot / delta_dot^-) with chi = a(e_r) of the closed
  form above in place of 3(1 - e_r^2)/4: e_r at every speed, for any mass and elastic law.
"""
import math

from .jit import kernel
from .layout import (
    DAMPING_HUNT_CROSSLEY, DAMPING_LANKARANI_NIKRAVESH, DAMPING_LANKARANI_NIKRAVESH_EXACT, P_CONTACT_DAMPING,
    P_EFFECTIVE_MASS, P_EXPONENT, P_RESTITUTION, P_RESTITUTION_SPEED,
)
_BISECTIONS = 100
_TSUJI_STEP = 2e-3            # RK4 step of the dimensionless impact (it lasts ~3 units): e to ~1e-6
# Tsuji's heavy damping, gamma above _TSUJI_HEAVY (e < 0.0115 for n = 1.5): the impact stops at x ~ s = gamma^(-2/(n+1))
# within a time ~s, creeps back at ~1/gamma^2 and lets go there (the force would have to pull to slow it further):
# e -> (n+1) / (2 gamma^2).  A step of _TSUJI_STEP (0.1 gamma)^(-2/(n+1)) (the same share of s at every gamma, the
# light step at gamma = 10) ending where the force lets go takes a few thousand steps at any gamma (0.02/gamma and the
# force-free flight back took over a minute for e = 1e-4); from _TSUJI_ASYMPTOTIC on (e < 1.25e-8) that limit is within
# 1e-6 of the impact integrated at a 100 times shorter step (n from 1 to 6), closer than this RK4's 3e-4, and the
# creep no longer moves x by a resolved amount from gamma ~ 1e7 (x stalls, the flight never ends).
_TSUJI_HEAVY = 10.0
_TSUJI_ASYMPTOTIC = 1e4


@kernel
def hunt_crossley_residual(a, e):
    """a - ln(1 + a) + a e + ln(1 - a e): zero where F_e max(0, 1 + alpha delta_dot) with a = alpha v
    rebounds at e from speed v (> 0 below the root in a, < 0 above it)."""
    return a - math.log(1.0 + a) + a * e + math.log(1.0 - a * e)


@kernel
def _above(mode, x, value, exponent):
    """Whether the root of :func:`_bisect`'s equation lies above ``x``: mode 0, a(e = value) against
    :func:`hunt_crossley_residual`; 1, e(a = value); 2, Tsuji's gamma(e = value)."""
    if mode == 0:
        return hunt_crossley_residual(x, value) > 0.0
    if mode == 1:
        return hunt_crossley_residual(value, x) > 0.0
    return tsuji_restitution(x, exponent) > value


@kernel
def _bisect(mode, value, exponent, lo, hi, iterations):
    """The root in (lo, hi) of the equation of :func:`_above`, by bisection."""
    for _ in range(iterations):
        mid = 0.5 * (lo + hi)
        if _above(mode, mid, value, exponent):
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@kernel
def hunt_crossley_damping(restitution):
    """a = alpha v [-] at which the Hunt-Crossley force rebounds at ``restitution`` from speed v: the
    root of :func:`hunt_crossley_residual` in (0, 1/e) (0 for e = 1)."""
    if restitution >= 1.0:
        return 0.0
    return _bisect(0, restitution, 0.0, 0.0, 1.0 / restitution, _BISECTIONS)


@kernel
def hunt_crossley_restitution(damping):
    """Restitution [-] of an impact under F_e max(0, 1 + alpha delta_dot) with a = alpha v = ``damping``:
    the root e in (0, min(1, 1/a)) of :func:`hunt_crossley_residual`."""
    if damping <= 0.0:
        return 1.0
    return _bisect(1, damping, 0.0, 0.0, min(1.0, 1.0 / damping), _BISECTIONS)


@kernel(inline='always')
def _tsuji_acceleration(x, u, gamma, exponent, power):
    if x <= 0.0:
        return 0.0
    force = x ** exponent + gamma * x ** power * u
    return -force if force > 0.0 else 0.0


@kernel
def tsuji_restitution(gamma, exponent):
    """Restitution [-] of the dimensionless impact x'' = -max(0, x^n + gamma x^((n-1)/2) x'), x(0) = 0,
    x'(0) = 1, n = ``exponent``: RK4 until x returns to 0, the exit speed interpolated there.  Heavily damped
    (gamma > _TSUJI_HEAVY) the step follows the impact's time scale gamma^(-2/(n+1)) and the exit speed the speed
    where the force lets go on the way out (from there x^((n+1)/2) + gamma x' <= 0 as x falls at constant x': a
    force-free flight back); from _TSUJI_ASYMPTOTIC on, the limit (n+1) / (2 gamma^2)."""
    if gamma >= _TSUJI_ASYMPTOTIC:
        return 0.5 * (exponent + 1.0) / gamma / gamma
    power = 0.5 * (exponent - 1.0)
    heavy = gamma > _TSUJI_HEAVY
    dt = _TSUJI_STEP / (0.1 * gamma) ** (2.0 / (exponent + 1.0)) if heavy else _TSUJI_STEP / max(1.0, 0.1 * gamma)
    x, u = 0.0, 1.0
    for _ in range(100_000_000):
        if heavy and u < 0.0 and x ** exponent + gamma * x ** power * u <= 0.0:
            return -u
        k1x, k1u = u, _tsuji_acceleration(x, u, gamma, exponent, power)
        k2x = u + 0.5 * dt * k1u
        k2u = _tsuji_acceleration(x + 0.5 * dt * k1x, k2x, gamma, exponent, power)
        k3x = u + 0.5 * dt * k2u
        k3u = _tsuji_acceleration(x + 0.5 * dt * k2x, k3x, gamma, exponent, power)
        k4x = u + dt * k3u
        k4u = _tsuji_acceleration(x + dt * k3x, k4x, gamma, exponent, power)
        x_next = x + dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x)
        u_next = u + dt / 6.0 * (k1u + 2.0 * k2u + 2.0 * k3u + k4u)
        if x_next <= 0.0:
            return -(u + (u_next - u) * x / (x - x_next))
        x, u = x_next, u_next
    return 0.0


@kernel
def tsuji_damping(restitution, exponent):
    """gamma [-] at which the Tsuji impact of :func:`tsuji_restitution` rebounds at ``restitution``: the inverse of
    its limit (n+1) / (2 gamma^2) where that is above _TSUJI_ASYMPTOTIC, else by bisection."""
    if restitution >= 1.0:
        return 0.0
    limit = math.sqrt(0.5 * (exponent + 1.0)) / math.sqrt(restitution)
    if limit >= _TSUJI_ASYMPTOTIC:
        return limit
    hi = 1.0
    while tsuji_restitution(hi, exponent) > restitution and hi < 1e6:
        hi *= 2.0
    return _bisect(2, restitution, exponent, 0.0, hi, 60)


@kernel
def damping_coefficient(jp):
    """The coefficient the normal force of law ``jp[P_CONTACT_DAMPING]`` uses: alpha = a(e_r)/v_r [s/m]
    (Hunt-Crossley), chi = 3(1 - e_r^2)/4 [-] (Lankarani-Nikravesh, Eq. 15), or c = gamma(e_r, n) sqrt(m_eff)
    [kg^0.5] (Tsuji)."""
    law = int(jp[P_CONTACT_DAMPING])
    restitution = jp[P_RESTITUTION]
    if law == DAMPING_HUNT_CROSSLEY:
        return hunt_crossley_damping(restitution) / jp[P_RESTITUTION_SPEED]
    if law == DAMPING_LANKARANI_NIKRAVESH:
        return 0.75 * (1.0 - restitution * restitution)
    if law == DAMPING_LANKARANI_NIKRAVESH_EXACT:
        return hunt_crossley_damping(restitution)
    return tsuji_damping(restitution, jp[P_EXPONENT]) * math.sqrt(jp[P_EFFECTIVE_MASS])
