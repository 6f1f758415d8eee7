"""Where the clearance joint sits in the slider-crank: its pin body and bushing body (layout.CLEARANCE_*).

The mechanism's state y = [q, q_dot] (Eq. 38) holds the crank, the rod and the slider; the clearance joint
reads its pin body's and its bushing body's kinematics from it and loads them back (the ground has no
coordinates: its pose and velocity are zero).  Crank-rod: pin on the crank's tip, bushing in the rod's big
end (the paper's); rod-slider: pin in the slider, bushing in the rod's small end; crank-ground: the crank's
journal in a bushing fixed in the frame at the pivot.
"""
import math

import numpy as np

from .jit import kernel
from .layout import CRANK, GROUND, MP_CLEARANCE_JOINT, N_COORDINATES, ROD, SLIDER

# pin body, bushing body of each location (offsets into q; GROUND: none)
JOINT_BODIES = np.array([[CRANK, ROD], [SLIDER, ROD], [CRANK, GROUND]])


@kernel(inline='always')
def clearance_location(mp):
    """The clearance joint's location (layout.CLEARANCE_*) in the mechanism parameters ``mp``."""
    return int(mp[MP_CLEARANCE_JOINT])


@kernel(inline='always')
def joint_bodies(mp):
    """(pin body, bushing body) of the clearance joint: offsets into q, layout.GROUND for the frame."""
    location = clearance_location(mp)
    return JOINT_BODIES[location, 0], JOINT_BODIES[location, 1]


@kernel(inline='always')
def body_angle(y, body):
    """The angle [rad] of ``body`` in state y (0 for the ground)."""
    return 0.0 if body == GROUND else y[body + 2]


@kernel(inline='always')
def body_rate(y, body):
    """The angular velocity [rad/s] of ``body`` in state y (0 for the ground)."""
    return 0.0 if body == GROUND else y[N_COORDINATES + body + 2]


@kernel(inline='always')
def body_state(y, body):
    """(x [m], y [m], angle [rad], vx [m/s], vy [m/s], omega [rad/s]) of ``body`` in state y (zeros for the
    ground)."""
    if body == GROUND:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    n = N_COORDINATES
    return y[body], y[body + 1], y[body + 2], y[n + body], y[n + body + 1], y[n + body + 2]


@kernel(inline='always')
def bodies_trig(y, pin, bushing):
    """(cos, sin) of the pin body's angle, then of the bushing body's, in state y."""
    a = body_angle(y, pin)
    b = body_angle(y, bushing)
    return math.cos(a), math.sin(a), math.cos(b), math.sin(b)


@kernel(inline='always')
def bodies_kinematics(y, pin, bushing, out):
    """out[0:12] = the joint's kinematic inputs (layout.N_KINEMATIC_INPUTS: x, y, angle, vx, vy, omega of the
    pin body, then of the bushing body) from state y."""
    out[0], out[1], out[2], out[3], out[4], out[5] = body_state(y, pin)
    out[6], out[7], out[8], out[9], out[10], out[11] = body_state(y, bushing)


@kernel
def joint_kinematics(y, mp, out):
    """:func:`bodies_kinematics` of the clearance joint of ``mp``."""
    pin, bushing = joint_bodies(mp)
    bodies_kinematics(y, pin, bushing, out)


__all__ = ["JOINT_BODIES", "body_angle", "body_rate", "body_state", "bodies_kinematics", "bodies_trig",
           "clearance_location", "joint_bodies", "joint_kinematics"]
