"""The kernels a run calls a few times from Python: the mechanism's parameter vector, M^-1 and start, its ideal
joint's reaction, the bushing's points, the materials' stiffness.

Each is taken from the co-simulation master's library compiled ahead of time where it is built
(:func:`wearjoint.cosim.native_master.native_master`), else from numba: the same kernels, the same numbers.  A
co-simulation whose library is built thus loads no numba kernel (numba's first one costs ~0.4 s: its registries and
a BLAS check); numba's are imported only where the library is missing.
"""
from __future__ import annotations

import numpy as np

from .core import layout as L
from .mechanism_parameters import FIELD_SCALES, SliderCrankParameters, field_vector


def _library():
    try:
        from .cosim.native_master import native_master
    except ImportError:     # a copy of the package without the co-simulation (the pythonfmu FMU's): numba's
        return None
    return native_master(build=False)


def mechanism_arrays(params: SliderCrankParameters) -> tuple[np.ndarray, tuple]:
    """(the kernels' parameter vector (layout.MP_*), the mechanism kernels' workspace with M^-1 (Eq. 42))."""
    fields = np.ascontiguousarray(field_vector(params), dtype=float)
    mp = np.zeros(L.N_MECHANISM_PARAMETERS)
    workspace = tuple(np.zeros(shape) for shape in L.WORKSPACE_SHAPES)
    library = _library()
    if library is None or library.mechanism_parameters(fields, mp, workspace[L.WORKSPACE_INVERSE_MASS]) != 0:
        from .core.slider_crank import inverse_mass_diagonal
        from .core.slider_load import mechanism_parameter_vector

        mechanism_parameter_vector(fields, FIELD_SCALES, mp)
        inverse_mass_diagonal(mp, workspace[L.WORKSPACE_INVERSE_MASS])
    return mp, workspace


def initial_state(t: float, mp: np.ndarray, workspace: tuple) -> np.ndarray:
    """The ideal mechanism's consistent state y = [q, q_dot] at time t [s] (core.slider_crank.initial_state)."""
    y = np.zeros(2 * L.N_COORDINATES)
    library = _library()
    if library is None:
        from .core.slider_crank import initial_state as kernel

        kernel(t, mp, workspace, y)
    else:
        library.initial_state(t, mp, workspace, y)
    return y


def ideal_joint_forces(times: np.ndarray, mp: np.ndarray, workspace: tuple) -> np.ndarray:
    """|The ideal clearance joint's reaction| [N] at ``times`` [s] (core.slider_crank.ideal_joint_forces)."""
    times = np.ascontiguousarray(times, dtype=float)
    out = np.empty(times.shape)
    n = L.N_COORDINATES
    scratch = (np.zeros(L.N_RESULT), np.zeros(2 * n), np.zeros(n), np.zeros(6), out)
    library = _library()
    if library is None:
        from .core.slider_crank import ideal_joint_forces as kernel

        kernel(times, mp, workspace, *scratch)
    else:
        library.ideal_joint_forces(times, mp, workspace, *scratch)
    return out


def bushing_point_angles(n_points: int) -> np.ndarray:
    """phi_z of the bushing's points [rad] (:func:`wearjoint.core.geometry.bushing_point_angles`, Eq. 3)."""
    library = _library()
    if library is None:
        from .core.geometry import bushing_point_angles as numba_angles

        return numba_angles(n_points)
    phi, cos_phi, sin_phi = np.empty(n_points), np.empty(n_points), np.empty(n_points)
    library.bushing_points(phi, cos_phi, sin_phi)
    return phi


def effective_modulus(pin_youngs_modulus_Pa: float, pin_poisson_ratio: float, bushing_youngs_modulus_Pa: float,
                      bushing_poisson_ratio: float) -> float:
    """E* [Pa] of Eq. (32) (core.wear.effective_modulus)."""
    library = _library()
    if library is None:
        from .core.wear import effective_modulus as kernel
    else:
        kernel = library.effective_modulus
    return float(kernel(pin_youngs_modulus_Pa, pin_poisson_ratio, bushing_youngs_modulus_Pa, bushing_poisson_ratio))


def materials_contact_stiffness(pin_radius_m: float, bushing_radius_m: float, effective_modulus_Pa: float) -> float:
    """K [N/m^1.5] of a pin inside a bushing, Eqs. (16)-(17) (core.wear.materials_contact_stiffness)."""
    library = _library()
    if library is None:
        from .core.wear import materials_contact_stiffness as kernel
    else:
        kernel = library.materials_contact_stiffness
    return float(kernel(pin_radius_m, bushing_radius_m, effective_modulus_Pa))
