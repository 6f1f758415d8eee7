"""A recorded kinematic trace of the slider-crank, to drive a joint FMU and the in-process joint."""
import numpy as np

from wearjoint.core import layout as L
from wearjoint.simulate import Simulation, SimulationOptions


def slider_crank_trace(joint, n_rows: int, step_s: float) -> np.ndarray:
    """Kinematics of the pin body (crank) and bushing body (rod) every ``step_s`` of a monolithic
    slider-crank run with ``joint``: rows (t, h, the 12 FMU inputs)."""
    sim = Simulation(joint, None, SimulationOptions(revolutions=n_rows * step_s / 0.4 + 1.0))
    rows = np.empty((n_rows, 14))
    samples = np.zeros((8, L.N_SAMPLE_COLUMNS))
    y, m = sim.y, L.N_COORDINATES
    for i in range(n_rows):
        rows[i, :2] = (sim.t, step_s)
        for body, column in ((L.CRANK, 2), (L.ROD, 8)):
            rows[i, column:column + 3] = y[body:body + 3]
            rows[i, column + 3:column + 6] = y[m + body:m + body + 3]
        sim.advance_to((i + 1) * step_s, samples)
    return rows


def run_joint_on_trace(params, rows, model_exchange: bool = False):
    """The in-process ClearanceJoint with ``params`` driven through ``rows``: the FMU's scalar outputs
    evaluated at every row before its step is accepted (over h with the inputs held, or in Model Exchange
    over t_i - t_(i-1) from the start time 0, ending there), and the final wear profile."""
    from wearjoint import ClearanceJoint
    from wearjoint.fmu import variables as fv

    joint = ClearanceJoint(params)
    names = [v.name for v in fv.SCALAR_OUTPUTS]
    outputs = np.empty((len(rows), len(names)))
    previous_t = 0.0
    for i, row in enumerate(rows):
        k = row[2:]
        result = joint.evaluate_array(k[0:3], k[3:6], k[6:9], k[9:12])
        outputs[i] = [result[fv.RESULT_SLOTS[n]] if n in fv.RESULT_SLOTS
                      else joint.max_wear_depth_m if n == "max_wear_depth" else joint.worn_volume_m3 for n in names]
        joint.advance_array(k[0:3], k[3:6], k[6:9], k[9:12], row[0] - previous_t if model_exchange else row[1],
                            not model_exchange)
        previous_t = row[0]
    return outputs, joint.wear_depth.copy()


def orbiting_pin_trace(joint, n_rows: int, step_s: float, sweeps_per_s: float = 1000.0, bounces_per_s: float = 1000.0,
                       amplitude_m: float = 4e-6, spin_rad_s: float = 15.7) -> np.ndarray:
    """A pin body driven round inside a fixed bushing body (both centres at the reference points): the
    eccentricity's direction sweeps ``sweeps_per_s`` times a second, its length is c + 3/4 ``amplitude_m``
    + ``amplitude_m`` sin(2 pi ``bounces_per_s`` t), so the pin enters and leaves contact gently (onset
    speeds of mm/s to cm/s) and, while the bushing wears, ever more gently; the pin body spins at
    ``spin_rad_s`` (the sliding of the wear).  Rows (t, h, the 12 FMU inputs)."""
    t = np.arange(n_rows) * step_s
    sweep, bounce = 2.0 * np.pi * sweeps_per_s, 2.0 * np.pi * bounces_per_s
    e = joint.clearance_m + 0.75 * amplitude_m + amplitude_m * np.sin(bounce * t)
    e_dot = amplitude_m * bounce * np.cos(bounce * t)
    c, s = np.cos(sweep * t), np.sin(sweep * t)
    rows = np.zeros((n_rows, 14))
    rows[:, 0], rows[:, 1] = t, step_s
    rows[:, 2], rows[:, 3], rows[:, 4] = e * c, e * s, spin_rad_s * t
    rows[:, 5], rows[:, 6], rows[:, 7] = e_dot * c - e * sweep * s, e_dot * s + e * sweep * c, spin_rad_s
    return rows
