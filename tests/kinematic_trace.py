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
