"""The co-simulation master's layout: its schemes, the FMU outputs it reads, its state buffer (``B_*``), its
register (``G_*``), its settings (``C_*``) and the FMI calls it makes (``F_*``): what the Python side shares with the
compiled loop (:mod:`wearjoint.cosim.master_loop`; its library compiled ahead of time, :mod:`.native_master`), which
a co-simulation reads without importing numba."""
from __future__ import annotations

import ctypes

import numpy as np

from ..core import layout as L
from ..fmu.fmi import function_address
from ..fmu.instance import N_INPUTS
from ..fmu.variables import JACOBIAN_SLOTS, RESULT_SLOTS

SCHEMES = ("zoh", "extrapolation", "adaptive", "linearised")
ADAPTIVE_SCHEMES = ("adaptive", "linearised")   # long steps in free flight, rollbacks to contact onsets

# --- the FMU outputs the master reads, in this order, and where each goes in a result (layout.R_*)
OUTPUT_NAMES = ("pin_force_x", "pin_force_y", "pin_torque", "bushing_force_x", "bushing_force_y",
                "bushing_torque", "normal_force", "friction_force", "penetration", "contact",
                "eccentricity_x", "eccentricity_y", "tangential_velocity")
OUTPUT_RESULT_INDEX = np.array([RESULT_SLOTS[name] for name in OUTPUT_NAMES])   # the FMU's table (fmu.variables)
N_OUTPUTS = len(OUTPUT_NAMES)
O_PENETRATION = OUTPUT_NAMES.index("penetration")
O_CONTACT = OUTPUT_NAMES.index("contact")
O_NORMAL_FORCE = OUTPUT_NAMES.index("normal_force")

# --- the master's state buffer: one float64 array, so the per-step kernel takes few arguments.
# Everything a rollback restores is at its start (one copy saves it).
N_STATE = 2 * L.N_COORDINATES
B_Y = 0                                   # mechanism state [q, q_dot]
B_OUTPUT = B_Y + N_STATE                     # FMU outputs at t (OUTPUT_NAMES), aliased by a ctypes array
B_PREVIOUS_FORCES = B_OUTPUT + N_OUTPUTS  # FMU forces at the accepted point before t (extrapolation)
B_PREVIOUS_CONTACT = B_PREVIOUS_FORCES + 6   # 1.0 if the pin touched there
B_LAST_STEP = B_PREVIOUS_CONTACT + 1      # length of the step that ended at t [s]
B_TRIG = B_LAST_STEP + 1                  # crank angle, its cos, sin, rod angle, cos, sin at t; rotations left
B_ROLLBACK_END = B_TRIG + 7
B_DY = B_ROLLBACK_END                     # f(t, y) with the held forces
B_INPUT = B_DY + N_STATE                     # FMU inputs at the end of the step, aliased by a ctypes array
B_RESULT = B_INPUT + N_INPUTS             # outputs in the layout.R_* result layout (for record_step)
B_FORCES = B_RESULT + L.N_RESULT          # (Fx, Fy, T) on the crank then the rod
B_STAGES = B_FORCES + 6                   # RK4 stage scratch (4 rows of the state size)
B_TRACK = B_STAGES + 4 * N_STATE             # record_step bookkeeping (samples, previous contact)
B_MP = B_TRACK + L.N_TRACK                # mechanism parameter vector
B_EXTRAPOLATE = B_MP + L.N_MECHANISM_PARAMETERS   # 1.0: extrapolate the forces during contact
B_LINEARISE = B_EXTRAPOLATE + 1           # 1.0: linearise the loads during contact (scheme linearised)
B_LINEARISED_AT = B_LINEARISE + 1         # the time of the linearisation at B_LINEARISATION [s] (-1: none)
B_LINEARISATION = B_LINEARISED_AT + 1     # the FMU's loads and their Jacobian there (layout.LIN_*)
B_STATS = B_LINEARISATION + L.N_LINEARISATION   # per-revolution statistics (rows of layout.N_STATS)


# --- master_loop's register: the loop's state between calls, then its counters (this call, from G_STEPS
# on: reset by the caller) and its failure
G_T = 0                  # time reached [s]
G_PREVIOUS_PENETRATION = 1   # FMU penetration at the accepted point before t [m]
G_CONTACT_STEP = 2       # adaptive: the communication step in contact now [s] (0: step_s)
G_STEPS = 3              # communication steps accepted
G_ROLLBACKS = 4          # rollbacks
G_FMI_TIME = 5           # wall time in FMI calls [s], estimated from every FMI_TIMING_EVERY-th iteration's
G_FREE_STEPS = 6         # accepted steps that started in free flight
G_SHRUNK_STEPS = 7       # accepted steps in contact shorter than step_s (the force missed its extrapolation)
G_FAILED_CALL = 8        # index into FMI_CALLS of the call that failed, 0 if none
G_FAILED_STATUS = 9      # its fmi2Status
G_FAILED_TIME = 10       # the communication point it was made for [s]
G_MISS_SQ_SUM = 11       # adaptive and linearised, steps in contact with a predicted force: the sum of the squared
G_MISS_MAX = 12          # relative misses of the prediction (|F(t + h) - F_predicted| / max(|F(t + h)|, |F(t)|,
G_MISS_COUNT = 13        # 100 N)), their largest and their number: the coupling's error estimate
N_REGISTER = 14
FMI_CALLS = ("", "fmi2DoStep", "fmi2SetReal", "fmi2GetReal", "fmi2GetFMUstate", "fmi2SetFMUstate",
             "fmi2FreeFMUstate")
F_DO_STEP, F_SET_REAL, F_GET_REAL, F_GET_STATE, F_SET_STATE, F_FREE_STATE = range(1, len(FMI_CALLS))
# the FMU outputs the linearised scheme reads in contact: its published derivatives (layout.LIN_JACOBIAN's rows
# PUBLISHED_LINEARISED_LOADS), the columns layout.RELATIVE_COLUMNS (40 of 60: the others are minus their partners')
MASTER_DERIVATIVE_OUTPUTS = tuple(name for name, (_, column) in JACOBIAN_SLOTS.items() if column in L.RELATIVE_COLUMNS)
# --- master_loop's settings; C_REUSE_STATE: 1.0 if getFMUstate overwrites the state it is given (FMI's "typically";
# the pythonfmu slave returns a new one and loses the old), else each state is freed before the next;
# C_TOLERANCE: the relative force miss the adaptive contact step is controlled to (0: the fixed rule)
C_ADAPTIVE, C_STEP, C_MAX_STEP, C_MIN_STEP, C_ONSET, C_REUSE_STATE, C_TOLERANCE, C_LINEARISE = range(8)
N_SETTINGS = 8


def buffer_views(buf):
    """The 2-D views of ``buf`` the master's step takes: the per-revolution statistics (rows of layout.N_STATS) and
    the RK4 stage scratch (4 rows of the state size)."""
    return (buf[B_STATS:].reshape((-1, L.N_STATS)),
            buf[B_STAGES:B_STAGES + 4 * N_STATE].reshape((4, N_STATE)))


def monotonic_clock() -> int:
    """The address of libc's clock_gettime, for master_loop's split of FMI time and master time."""
    return function_address(ctypes.CDLL(None).clock_gettime)
