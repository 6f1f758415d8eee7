"""Whether a joint state is one a contact of the joint's materials can reach (docs/reference/model.md §3.14).

A pin in its worn bushing sits at |e| = c + h(phi_e) + its penetration; a co-simulation coupling that blew up
puts it further, through the wall, or drives it into the wall so fast that the damping's force passes anything
the materials carry.  The admissible penetration is ADMISSIBLE_PENETRATION_SHARE of the pin's radius (layout),
the admissible force the Hertz law's K delta^n there; a state deeper or pressed harder than that, one whose pin sits
in a groove worn deeper than the bushing radius (the deepest wear a state holds: the bushing wore through), or one
not finite, is refused: the wear and contact-onset update of
an accepted step (core.wear) returns STEP_INADMISSIBLE and changes nothing (but at the joint's first accepted
point, which a master may take before it connected the inputs).
"""
import math

from .geometry import direction_point
from .jit import kernel
from .layout import (
    ADMISSIBLE_PENETRATION_SHARE, P_BUSHING_RADIUS, P_EXPONENT, P_PIN_RADIUS, P_STIFFNESS, R_ECCENTRICITY_X,
    R_ECCENTRICITY_Y, R_NORMAL_FORCE,
)


@kernel(inline='always')
def admissible_penetration(jp):
    """The deepest the pin may be in the bushing wall [m]: ADMISSIBLE_PENETRATION_SHARE R_i."""
    return ADMISSIBLE_PENETRATION_SHARE * jp[P_PIN_RADIUS]


@kernel(inline='always')
def _wall_along_e(result, jp, wear_depth):
    """(how far the pin is in the bushing wall along its eccentricity [m], |e| + R_i - (R_j + h); h [m]), h the wear
    depth of the bushing point nearest e's direction (point k at phi = (k + 1) 2 pi / N_d, Eq. 3); NaNs if e is not
    finite."""
    ex = result[R_ECCENTRICITY_X]
    ey = result[R_ECCENTRICITY_Y]
    if not (math.isfinite(ex) and math.isfinite(ey)):
        return math.nan, math.nan
    n = wear_depth.shape[0]
    h = wear_depth[direction_point(ex, ey, n)]
    return math.sqrt(ex * ex + ey * ey) + jp[P_PIN_RADIUS] - jp[P_BUSHING_RADIUS] - h, h


@kernel
def wall_overlap(result, jp, wear_depth):
    """How far the pin is in the bushing wall along its eccentricity [m] (:func:`_wall_along_e`); NaN if e is not
    finite."""
    return _wall_along_e(result, jp, wear_depth)[0]


@kernel(inline='always')
def admissible_force(jp):
    """The largest normal force [N] a contact of the joint carries: K delta_adm^n (Eqs. 14-15, the Hertz law's
    elastic force at the admissible penetration; the elastic foundation's is about half of it)."""
    depth = admissible_penetration(jp)
    return jp[P_STIFFNESS] * (depth * math.sqrt(depth) if jp[P_EXPONENT] == 1.5 else depth ** jp[P_EXPONENT])


@kernel(inline='always')
def is_admissible(result, jp, wear_depth):
    """True if the evaluated contact ``result`` (layout.R_*) is within the admissible penetration of the worn
    bushing, its normal force within :func:`admissible_force` and the wall along e worn at most the bushing radius
    R_j deep; the wall is looked up only where |e| passes the unworn clearance plus that penetration."""
    if not result[R_NORMAL_FORCE] <= admissible_force(jp):
        return False
    ex = result[R_ECCENTRICITY_X]
    ey = result[R_ECCENTRICITY_Y]
    free = jp[P_BUSHING_RADIUS] - jp[P_PIN_RADIUS] + admissible_penetration(jp)
    if ex * ex + ey * ey <= free * free:
        return True
    overlap, depth = _wall_along_e(result, jp, wear_depth)
    return overlap <= admissible_penetration(jp) and depth <= jp[P_BUSHING_RADIUS]


__all__ = ["admissible_force", "admissible_penetration", "is_admissible", "wall_overlap"]
