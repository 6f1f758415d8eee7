"""The chunked run loop shared by the simulation engines.

An engine (``simulate.Simulation``, ``cosim.CoSimulation``) offers
``advance_to(t_end, samples) -> n``, ``t``, ``max_wear_depth_m()``,
``wear_profile() -> (phi_deg, wear_depth_m, worn_volume_m3)`` and ``close()``.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from .core import layout as L
from .progress import Progress


@dataclass
class ChunkedRun:
    samples: np.ndarray          # (n, layout.N_SAMPLE_COLUMNS)
    wear_growth_m: np.ndarray    # max wear depth after each complete revolution
    wall_time_s: float
    completed: bool              # False if Ctrl-C stopped the run


def run_in_chunks(engine, revolutions: float, period_s: float, sample_dt_s: float, label: str,
                  progress: bool = True, chunks_per_revolution: int = 8) -> ChunkedRun:
    """Advance ``engine`` by ``revolutions`` crank revolutions in chunks of 1/chunks_per_revolution
    revolution, collecting samples and the wear growth; a progress line on stderr for
    runs longer than a few seconds; Ctrl-C stops after the current chunk and keeps what
    was finished."""
    t_final = revolutions * period_s
    chunk = period_s / chunks_per_revolution
    buffer = np.zeros((int(chunk / sample_dt_s) + 16, L.N_SAMPLE_COLUMNS))
    samples, growth = [], []
    bar = Progress(t_final, label, enabled=progress)
    completed = True
    wall0 = time.perf_counter()
    try:
        for i in range(int(math.ceil(revolutions * chunks_per_revolution - 1e-9))):
            n = engine.advance_to(min(t_final, (i + 1) * chunk), buffer)
            samples.append(buffer[:n].copy())
            if (i + 1) % chunks_per_revolution == 0:
                growth.append(engine.max_wear_depth_m())
            bar.update(engine.t)
    except KeyboardInterrupt:
        completed = False
    wall = time.perf_counter() - wall0
    bar.close()
    return ChunkedRun(np.concatenate(samples) if samples else np.zeros((0, L.N_SAMPLE_COLUMNS)),
                      np.asarray(growth), wall, completed)
