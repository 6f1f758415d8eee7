"""Metrics of a worn bushing profile (depth h over the bushing-frame angle phi): its deepest point, the two lobes,
its features in summary.json, its distance to a reference profile, its ripple and its growth over revolutions.
The run statistics are :mod:`wearjoint.analysis`'s."""
from __future__ import annotations

import math

import numpy as np

LOBE_CENTRES_DEG = (0, 180)


def wrap_deg(angle):
    """Angle(s) [deg] wrapped to [-180, 180)."""
    return (np.asarray(angle) + 180.0) % 360.0 - 180.0


def deepest_point(phi_deg: np.ndarray, depth_m: np.ndarray) -> dict:
    """Max wear depth [m] and its angle (bushing frame, deg in [0, 360); None on an unworn profile, which has no
    deepest point)."""
    deepest = int(np.argmax(depth_m))
    return {"max_wear_depth_m": float(depth_m[deepest]),
            "max_wear_angle_deg": float(phi_deg[deepest] % 360.0) if depth_m[deepest] > 0.0 else None}


def _half(phi_deg: np.ndarray, centre: float):
    """Offsets [rad] from ``centre`` and the points within +-90 deg of it."""
    offset = np.radians(wrap_deg(np.asarray(phi_deg) % 360.0 - centre))
    return offset, np.abs(offset) < 0.5 * math.pi


def lobes(phi_deg: np.ndarray, depth_m: np.ndarray) -> dict:
    """The two wear lobes, centred near 0 deg and near 180 deg (rod frame), where crank and
    rod are collinear.  A lobe is the wear within +-90 deg of its centre; its angle is the
    depth-weighted mean angle there (a circular mean; near 0: in (-90, 90), near 180: in
    (90, 270)), None without wear in that half; its depth is the deepest point there [m]."""
    out = {}
    for centre in LOBE_CENTRES_DEG:
        offset, half = _half(phi_deg, centre)
        weight = depth_m[half]
        out[centre] = {
            "angle_deg": (centre + math.degrees(math.atan2((weight * np.sin(offset[half])).sum(),
                                                           (weight * np.cos(offset[half])).sum()))
                          if weight.sum() > 0.0 else None),
            "depth_m": float(weight.max()) if weight.size else 0.0}
    return out


def profile_features(phi_deg: np.ndarray, depth_m: np.ndarray) -> dict:
    """The deepest point, the two lobes (:func:`lobes`) and the depth at 90 and 270 deg."""
    lobe = lobes(phi_deg, depth_m)
    return {**deepest_point(phi_deg, depth_m),
            "lobe_0_angle_deg": lobe[0]["angle_deg"], "lobe_0_depth_m": lobe[0]["depth_m"],
            "lobe_180_angle_deg": lobe[180]["angle_deg"], "lobe_180_depth_m": lobe[180]["depth_m"],
            "depth_at_90_deg_m": float(np.interp(90.0, phi_deg, depth_m)),
            "depth_at_270_deg_m": float(np.interp(270.0, phi_deg, depth_m))}


def profile_decorrelation(depth_m: np.ndarray, reference_m: np.ndarray) -> float:
    """1 - Pearson correlation of two wear profiles h(phi) (0 for identical shapes)."""
    return float(1.0 - np.corrcoef(depth_m, reference_m)[0, 1])


def profile_relative_l2(depth_m: np.ndarray, reference_m: np.ndarray) -> float:
    """|h - h_ref|_2 / |h_ref|_2 [-]."""
    return float(np.linalg.norm(depth_m - reference_m) / max(np.linalg.norm(reference_m), 1e-300))


def profile_convergence(depth_m: np.ndarray, reference_m: np.ndarray) -> dict:
    """Max depth relative to the reference's minus 1, and the RMS difference of the profiles
    relative to the reference's max depth."""
    scale = reference_m.max()
    return {"max_depth_rel_diff": float(depth_m.max() / scale - 1.0),
            "rms_profile_diff_rel": float(np.sqrt(np.mean((depth_m - reference_m) ** 2)) / scale)}


def moving_average_deg(phi_deg: np.ndarray, depth_m: np.ndarray, window_deg: float) -> np.ndarray:
    """Circular moving average of a profile over ``window_deg`` of arc (points equally spaced on
    the full circle; the window is the odd number of points nearest to window_deg)."""
    h = np.asarray(depth_m, float)
    n = h.size
    m = max(1, int(round(window_deg / (360.0 / n))) // 2)
    padded = np.concatenate([h[-m:], h, h[:m]])
    kernel = np.full(2 * m + 1, 1.0 / (2 * m + 1))
    return np.convolve(padded, kernel, mode="valid")


def profile_ripple(phi_deg: np.ndarray, depth_m: np.ndarray, window_deg: float = 5.0,
                   prominence_rel: float = 0.05) -> dict:
    """Roughness of a worn profile, relative to its max depth: the RMS of (profile - its
    ``window_deg`` circular moving average), and the local maxima whose topographic prominence
    (on the circle) exceeds ``prominence_rel`` of the max depth -- a smooth two-lobe profile has
    two, one per lobe."""
    from scipy.signal import find_peaks

    h = np.asarray(depth_m, float)
    scale = float(h.max())
    if scale <= 0.0:
        return {"ripple_rms_rel": 0.0, "prominent_maxima": 0, "prominent_maxima_deg": []}
    rms = float(np.sqrt(np.mean((h - moving_average_deg(phi_deg, h, window_deg)) ** 2)) / scale)
    n = h.size
    peaks, _ = find_peaks(np.concatenate([h, h, h]), prominence=prominence_rel * scale)
    middle = np.sort(peaks[(peaks >= n) & (peaks < 2 * n)] - n)
    return {"ripple_rms_rel": rms, "prominent_maxima": int(middle.size),
            "prominent_maxima_deg": [float(np.asarray(phi_deg)[k] % 360.0) for k in middle]}


def growth_exponent(revolutions, depth_m) -> float:
    """p of depth ~ revolutions**p over the run's second half, log2(d(R) / d(R/2)) with d(R/2) interpolated:
    the measure two points of an experiment at R/2 and R give (p > 1: the growth accelerates).  A fit over
    the whole run would weigh the running-in of the first revolutions (docs/explanation/wear_study.md)."""
    r, d = np.asarray(revolutions, float), np.asarray(depth_m, float)
    if r.size < 2 or not r[-1] > 0:
        return float("nan")
    half = float(np.interp(0.5 * r[-1], np.r_[0.0, r], np.r_[0.0, d]))
    return float(math.log(d[-1] / half) / math.log(2.0)) if half > 0 and d[-1] > 0 else float("nan")


__all__ = ["wrap_deg", "deepest_point", "lobes", "profile_features", "profile_decorrelation", "profile_relative_l2",
           "profile_convergence", "moving_average_deg", "profile_ripple", "growth_exponent"]
