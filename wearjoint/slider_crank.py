"""The paper's slider-crank (Sec. 6.1): parameter packing, initial state, closed form."""
from __future__ import annotations

import numpy as np

from .core import layout as L
from .core.slider_crank import ideal_joint_forces, initial_state, make_workspace
from .core.slider_load import mechanism_parameter_vector
from .mechanism_parameters import FIELD_SCALES, SliderCrankParameters, field_vector


def pack_mechanism_parameters(p: SliderCrankParameters) -> np.ndarray:
    """The flat parameter vector the kernels read (layout.MP_*)."""
    mp = np.zeros(L.N_MECHANISM_PARAMETERS)
    mechanism_parameter_vector(field_vector(p), FIELD_SCALES, mp)
    return mp


class SliderCrank:
    """Rigid slider-crank of Eqs. 38-44; ``ideal=True`` keeps the crank-rod revolute
    as a constraint, otherwise the crank-rod joint is open (its loads come from a
    clearance joint, in-process or from a co-simulation slave)."""

    def __init__(self, params: SliderCrankParameters | None = None):
        self.params = params or SliderCrankParameters()
        self.parameter_vector = pack_mechanism_parameters(self.params)
        self.workspace = make_workspace(self.parameter_vector)

    def initial_state(self) -> np.ndarray:
        """y0 = [q, q_dot] with the pin centred and the ideal kinematic velocities."""
        y = np.zeros(2 * L.N_COORDINATES)
        initial_state(0.0, self.parameter_vector, self.workspace, y)
        return y

    def ideal_joint_force(self, t) -> np.ndarray:
        """|Reaction| [N] of the ideal crank-rod revolute at times t [s], with gravity and the slider's load: what
        the joint would carry without clearance (the kernels' ideal mechanism on its consistent state)."""
        times = np.atleast_1d(np.asarray(t, dtype=float))
        out = np.empty(times.shape)
        n = L.N_COORDINATES
        ideal_joint_forces(times, self.parameter_vector, self.workspace, np.zeros(L.N_RESULT), np.zeros(2 * n),
                           np.zeros(n), np.zeros(6), out)
        return out

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
