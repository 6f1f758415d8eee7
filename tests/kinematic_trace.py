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
    evaluated at every row before its step is accepted (over h, or in Model Exchange over
    t_i - t_(i-1) from the start time 0), and the final wear profile."""
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
        joint.advance_array(k[0:3], k[3:6], k[6:9], k[9:12], row[0] - previous_t if model_exchange else row[1])
        previous_t = row[0]
    return outputs, joint.wear_depth.copy()
