"""The paper's slider-crank (Sec. 6.1): parameter packing, initial state, closed form."""
from __future__ import annotations

import numpy as np

from . import kernel_calls
from .core import layout as L
from .mechanism_parameters import SliderCrankParameters


def pack_mechanism_parameters(p: SliderCrankParameters) -> np.ndarray:
    """The flat parameter vector the kernels read (layout.MP_*)."""
    return kernel_calls.mechanism_arrays(p)[0]


class SliderCrank:
    """Rigid slider-crank of Eqs. 38-44; the ideal mechanism keeps the clearance joint's revolute
    (``clearance_joint``) as a constraint, otherwise that joint is open (its loads come from a
    clearance joint, in-process or from a co-simulation slave)."""

    def __init__(self, params: SliderCrankParameters | None = None):
        self.params = params or SliderCrankParameters()
        self.parameter_vector, self.workspace = kernel_calls.mechanism_arrays(self.params)

    def initial_state(self) -> np.ndarray:
        """y0 = [q, q_dot] with the pin centred and the ideal kinematic velocities."""
        return kernel_calls.initial_state(0.0, self.parameter_vector, self.workspace)

    def ideal_joint_force(self, t) -> np.ndarray:
        """|Reaction| [N] of the clearance joint made ideal (``clearance_joint``'s revolute) at times t [s], with
        gravity and the slider's load: what the joint would carry without clearance (the kernels' ideal mechanism
        on its consistent state)."""
        return kernel_calls.ideal_joint_forces(np.atleast_1d(np.asarray(t, dtype=float)), self.parameter_vector,
                                               self.workspace)

    def ideal_slider_acceleration(self, points: int = 721) -> tuple[np.ndarray, np.ndarray]:
        """(times [s], the ideal joint's slider acceleration [m/s^2]) at ``points`` times over one revolution,
        in closed form (:meth:`closed_form`)."""
        grid = np.linspace(0.0, self.params.period_s, points)
        return grid, self.closed_form(grid)["slider_a_m_s2"]

    def crank_angle(self, t) -> np.ndarray:
        """Driven crank angle theta1(t) = theta0 - omega t [rad]."""
        return self.parameter_vector[L.MP_THETA0] - self.params.omega_rad_s * np.asarray(t, dtype=float)

    def closed_form(self, t) -> dict:
        """Ideal slider-crank kinematics in closed form at times t [s].

        Slider x = l1 cos th + sqrt(l2^2 - l1^2 sin^2 th) with th = theta1(t);
        its velocity and acceleration by differentiation (th_dot = -omega);
        rod angle th2 = -asin(l1 sin th / l2).
        """
        l1 = self.params.crank_length_m
        l2 = self.params.rod_length_m
        th = self.crank_angle(t)
        w = -self.params.omega_rad_s
        s = l1 * np.sin(th)
        c = l1 * np.cos(th)
        r = np.sqrt(l2 * l2 - s * s)
        dx = -s - s * c / r
        ddx = -c - ((c * c - s * s) / r + s * s * c * c / r ** 3)
        return {"slider_x_m": c + r, "slider_v_m_s": dx * w, "slider_a_m_s2": ddx * w * w,
                "rod_angle_rad": np.arcsin(-s / l2), "crank_angle_rad": th}
