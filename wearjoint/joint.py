"""`ClearanceJoint`: the clearance/wear joint as a force element.

Every host (the monolithic integrator, the FMU slave, the exudyn model) holds
one of these.  ``evaluate`` maps the kinematics of the pin body and the
bushing body to forces and torques on both and never changes the joint;
``advance`` accepts a step (Archard wear, contact-onset bookkeeping).  The
state (wear profile + contact memory) can be copied, restored and serialised.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .core import layout as L
from .core import state_format as SF
from .core.admissibility import wall_overlap
from .core.contact import contact_jacobian, evaluate_contact
from .core.geometry import block_minimum_depth, bushing_points
from .core.joint_access import JointArrays
from .core.wear import (
    STEP_INADMISSIBLE, STEP_OVERSHOT, STEP_REFUSED, _flush_batch, accept_linearised_contact, advance_joint,
    complete_joint_parameters,
    equivalent_radius, hertz_half_width, worn_volume,
)
from .joint_fields import JOINT_FIELDS, coded_value
from .checks import is_real, real_array, refuse, worn_through_message
from .parameters import MAX_WEAR_STEP_S, JointParameters, ParameterError, require

KINEMATICS = "6 finite numbers (x [m], y [m], angle [rad], vx [m/s], vy [m/s], omega [rad/s])"


def _numbers(*arrays) -> str:
    """The values of ``arrays`` as one list, 6 significant digits each."""
    return "[" + ", ".join(f"{v:.6g}" for a in arrays for v in a) + "]"


def overshoot_message(dt: float, params: JointParameters) -> str:
    """What a wearing step of ``dt`` [s] over the wear-step limit (STEP_OVERSHOT, docs/reference/model.md §7) is
    told."""
    which = (f"longer than {MAX_WEAR_STEP_S:g} s" if dt > MAX_WEAR_STEP_S else f"within {MAX_WEAR_STEP_S:g} s, but "
             f"the share k_f k_w F v dt of the contact's penetration it wears passed {params.wear_step_share:g}")
    return (f"a wearing step dt={dt!r} s is over the wear-step limit ({which}): the step no longer resolves the wear; "
            "take shorter steps or a smaller wear_factor (docs/reference/model.md §7; said once per joint)")


class StateError(ParameterError):
    """A serialised state or a profile that fails a check; the message names the check."""


def _refuse(problem: int, values, where: str = "") -> None:
    if problem != SF.OK:
        raise StateError(f"{where}{SF.problem_message(problem, values)}")


def state_bytes(contents: int, head, memory, wear_depth_m) -> bytes:
    """A serialised state (docs/reference/fmu.md, "The state format"): ``contents`` (SF.CONTENTS_*), its
    ``head`` values (none for a joint; an FMU instance's time, initialised flag, inputs, parameters),
    the contact memory and the wear depths."""
    head = np.ascontiguousarray(head, dtype=float)
    data = np.empty(SF.state_size(head.size, len(wear_depth_m)), dtype=np.uint8)
    SF.write_state(data, contents, head, np.ascontiguousarray(memory, dtype=float),
                   np.ascontiguousarray(wear_depth_m, dtype=float))
    return data.tobytes()


def read_state_bytes(data, contents: int, n_head: int, n_points: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(head, memory, wear depths) of a serialised state; StateError naming the first failed check of
    its header, size, checksum, contents and n_points.  The values' ranges are not checked here."""
    raw = np.frombuffer(bytes(data), dtype=np.uint8)
    values = np.zeros(4)
    _refuse(SF.check_header(raw, contents, n_head, n_points, values), values)
    head, memory, depth = np.empty(n_head), np.empty(L.N_MEMORY), np.empty(n_points)
    SF.read_state(raw, head, memory, depth)
    return head, memory, depth


def check_state_values(head, memory, wear_depth_m, params: JointParameters, where: str = "") -> None:
    """StateError naming the first value out of range for a joint of ``params``: an FMU head's time or
    flag, the contact memory (an active contact's onset velocity >= the impact velocity floor), a wear
    depth (finite, in [0, bushing radius])."""
    values = np.zeros(4)
    _refuse(SF.check_values(np.asarray(head, dtype=float), np.asarray(memory, dtype=float),
                            np.asarray(wear_depth_m, dtype=float), params.bushing_radius_m,
                            params.impact_velocity_floor_m_s, values), values, where)


def pack_joint_parameters(p: JointParameters) -> np.ndarray:
    """The flat parameter vector the kernels read (layout.P_*): the slots of :data:`JOINT_FIELDS` from ``p``
    (coded: :func:`~wearjoint.joint_fields.coded_value`), the derived ones by
    :func:`core.wear.complete_joint_parameters`."""
    jp = np.zeros(L.N_JOINT_PARAMETERS)
    for f in JOINT_FIELDS:
        jp[f.slot] = coded_value(f, getattr(p, f.field))
    complete_joint_parameters(jp)
    return jp


@dataclass(frozen=True)
class ContactResult:
    """Forces (global frame, N and N m about each body's reference point) and diagnostics."""

    pin_force: tuple[float, float, float]       # (Fx, Fy, torque) on the pin body
    bushing_force: tuple[float, float, float]   # (Fx, Fy, torque) on the bushing body
    normal_force_N: float
    friction_force_N: float                     # on the pin along t = n rotated +90 deg
    penetration_m: float                        # R_i - |d_min|; negative: the gap
    in_contact: bool
    contact_index: int                          # 0-based bushing point, -1 without contact
    eccentricity_m: tuple[float, float]         # pin centre - bushing centre, bushing frame
    tangential_velocity_m_s: float
    penetration_rate_m_s: float
    contact_angle_rad: float                    # bushing frame, 0..2 pi
    # the contact's extent (zero without contact; filled by ClearanceJoint.evaluate/advance):
    half_width_m: float = 0.0                   # Hertz half-width b at the deepest point, Eq. (30)
    mean_pressure_Pa: float = 0.0               # F_N / (2 b L), Eqs. (25), (29)
    contact_arc_rad: tuple[float, float] = (0.0, 0.0)   # bushing-frame angles (start, end), counter-clockwise,
    #                                             of the arc around the deepest point where the pin overlaps
    #                                             the worn bushing (R_i - |d| > 0): where the wear goes

    @classmethod
    def from_array(cls, r: np.ndarray, **extent) -> "ContactResult":
        return cls((r[L.R_PIN_FX], r[L.R_PIN_FY], r[L.R_PIN_TORQUE]),
                   (r[L.R_BUSHING_FX], r[L.R_BUSHING_FY], r[L.R_BUSHING_TORQUE]),
                   r[L.R_NORMAL_FORCE], r[L.R_FRICTION_FORCE], r[L.R_PENETRATION],
                   bool(r[L.R_CONTACT] > 0.5), int(r[L.R_CONTACT_INDEX]),
                   (r[L.R_ECCENTRICITY_X], r[L.R_ECCENTRICITY_Y]),
                   r[L.R_TANGENTIAL_VELOCITY], r[L.R_PENETRATION_RATE], r[L.R_CONTACT_ANGLE], **extent)


@dataclass(frozen=True)
class JointState:
    """A copy of the joint's state: wear depth per bushing point [m] and contact memory."""

    wear_depth_m: np.ndarray
    memory: np.ndarray


def _split_kinematics(name: str, kinematics) -> tuple[np.ndarray, np.ndarray]:
    """(position, velocity) of a body's 6 kinematics; ParameterError naming ``name`` unless :data:`KINEMATICS`."""
    k = real_array(name, kinematics, KINEMATICS)
    if k.shape != (6,):
        refuse(name, kinematics, KINEMATICS, f"not 6 numbers: shape {k.shape}")
    if not np.all(np.isfinite(k)):
        refuse(name, kinematics, KINEMATICS, "non-finite values")
    return k[:3].copy(), k[3:].copy()


class ClearanceJoint:
    """Planar revolute clearance joint whose bushing wears (paper Secs. 2-5).

    Kinematics are 6 numbers per body, global frame: reference point x, y [m],
    angle [rad], and their rates vx, vy [m/s], omega [rad/s].  The pin body
    (i) carries the pin, the bushing body (j) the wearing bushing; the pin and
    bushing centres sit at ``params.pin_offset_m`` / ``bushing_offset_m`` in
    their bodies' frames (default zero: at the reference points).

    Bushing point k (0-based) sits at the bushing-frame angle
    ``phi_rad[k] = (k + 1) 2 pi / N_d`` (the paper's z = k + 1, Eq. 3): point
    N_d - 1 is at 0 deg, point 0 one spacing past it.
    """

    def __init__(self, params: JointParameters | None = None):
        if params is not None and not isinstance(params, JointParameters):
            raise ParameterError(f"params={params!r} is invalid: allowed a wearjoint.JointParameters (or None: the "
                                 "paper's joint)")
        self.params = JointParameters() if params is None else params
        n = self.params.n_points
        self.parameter_vector = pack_joint_parameters(self.params)
        self.phi_rad, self.cos_phi, self.sin_phi = np.empty(n), np.empty(n), np.empty(n)
        bushing_points(self.phi_rad, self.cos_phi, self.sin_phi)
        self.wear_depth = np.zeros(n)
        self.block_min = np.zeros((n + L.BLOCK_SIZE - 1) // L.BLOCK_SIZE)
        self.memory = np.zeros(L.N_MEMORY)
        self.memory[L.M_START_FORCE] = L.NO_START_FORCE
        self.result = np.zeros(L.N_RESULT)
        self.mask = np.zeros(n, dtype=np.bool_)
        self.work = np.zeros(2 * n)                 # scratch of the wear kernels (not state)
        self.kinematics = np.zeros(L.N_KINEMATIC_INPUTS)   # scratch of the integrators' accepted points
        self.failure = np.zeros(4)                  # the integrators' first inadmissible point (JointArrays.failure)
        self._warned_wear_step = False              # advance warned of a step over the wear-step limit

    @property
    def arrays(self) -> JointArrays:
        """The joint's arrays as the kernels and integrators take them (no copies; ``mask``, ``work`` and
        ``kinematics`` are scratch, ``failure`` the integrators' record of an inadmissible point, not state)."""
        return JointArrays(self.parameter_vector, self.cos_phi, self.sin_phi, self.wear_depth, self.block_min,
                           self.memory, self.mask, self.work, self.result, self.kinematics, self.failure)

    # ------------------------------------------------------------- forces
    def evaluate_array(self, pos_i, vel_i, pos_j, vel_j) -> np.ndarray:
        """Hot path: float64 arrays in, the joint's result array (layout.R_*) out (not a copy)."""
        evaluate_contact(pos_i, vel_i, pos_j, vel_j, self.parameter_vector, self.cos_phi,
                         self.sin_phi, self.wear_depth, self.block_min, self.memory, self.result)
        return self.result

    def linearise_array(self, pos_i, vel_i, pos_j, vel_j, jacobian: np.ndarray) -> np.ndarray:
        """:meth:`evaluate_array`, and into ``jacobian`` (N_RESULT x 12) the exact derivatives of the result with
        respect to the 12 kinematic inputs (:func:`~wearjoint.core.contact.contact_jacobian`)."""
        contact_jacobian(pos_i, vel_i, pos_j, vel_j, self.parameter_vector, self.cos_phi, self.sin_phi,
                         self.wear_depth, self.block_min, self.memory, self.result, jacobian)
        return self.result

    def evaluate(self, pin_kinematics, bushing_kinematics) -> ContactResult:
        """Forces on both bodies for the given kinematics; the joint's state is unchanged."""
        pos_i, vel_i = _split_kinematics("pin_kinematics", pin_kinematics)
        pos_j, vel_j = _split_kinematics("bushing_kinematics", bushing_kinematics)
        return self._contact_result(self.evaluate_array(pos_i, vel_i, pos_j, vel_j).copy(), self.wear_depth)

    def _contact_result(self, r: np.ndarray, depth: np.ndarray) -> ContactResult:
        """The result array as a :class:`ContactResult`, with the contact's extent; warns if the
        pin centre lies outside the bushing (offsets that do not fit the bodies' frames)."""
        p = self.params
        ex, ey = r[L.R_ECCENTRICITY_X], r[L.R_ECCENTRICITY_Y]
        if math.hypot(ex, ey) > p.bushing_radius_m + depth.max():
            warnings.warn(f"the pin centre is {math.hypot(ex, ey):.6g} m from the bushing centre, outside the "
                          f"bushing (radius {p.bushing_radius_m:g} m + wear): check pin_offset_m={p.pin_offset_m} "
                          f"and bushing_offset_m={p.bushing_offset_m} against the bodies' reference points",
                          RuntimeWarning, stacklevel=3)
        if r[L.R_CONTACT] < 0.5 or r[L.R_NORMAL_FORCE] <= 0.0:
            return ContactResult.from_array(r)
        k = int(r[L.R_CONTACT_INDEX])
        rho = equivalent_radius(p.pin_radius_m, p.bushing_radius_m + depth[k], L.choice_code("rho_mode", p.rho_mode))
        b = float(hertz_half_width(r[L.R_NORMAL_FORCE], rho, p.contact_length_m,
                                   self.parameter_vector[L.P_EFFECTIVE_MODULUS]))
        radius = p.bushing_radius_m + depth
        inside = np.hypot(radius * self.cos_phi - ex, radius * self.sin_phi - ey) < p.pin_radius_m
        n = inside.size
        if inside.all():
            arc = (0.0, 2.0 * math.pi)
        else:
            lo, hi = k, k
            while inside[(lo - 1) % n] and (lo - 1) % n != k:
                lo -= 1
            while inside[(hi + 1) % n]:
                hi += 1
            arc = (float(self.phi_rad[lo % n] % (2 * math.pi)), float(self.phi_rad[hi % n] % (2 * math.pi)))
        return ContactResult.from_array(r, half_width_m=b,
                                        mean_pressure_Pa=float(r[L.R_NORMAL_FORCE] / (2.0 * b * p.contact_length_m)),
                                        contact_arc_rad=arc)

    def advance_array(self, pos_i, vel_i, pos_j, vel_j, dt: float, held: bool = False) -> int:
        """Hot path of :meth:`advance`: the kernel's STEP_* code (core.wear.advance_joint): < 0 if the step was
        refused, nothing changed (STEP_REFUSED: its wear would exceed the bushing radius or not be finite;
        STEP_INADMISSIBLE: the pin deeper in the wall than any contact)."""
        return advance_joint(pos_i, vel_i, pos_j, vel_j, dt, held, self.parameter_vector, self.cos_phi,
                             self.sin_phi, self.wear_depth, self.block_min, self.memory,
                             self.mask, self.work, self.result)

    def accept_linearised_array(self, pos_i, vel_i, pos_j, vel_j, dt: float, jacobian: np.ndarray) -> int:
        """:meth:`advance_array` of a held step whose host applies the loads linearised here (``self.result`` and
        ``jacobian``: :meth:`linearise_array` at these kinematics): the wear takes that linearised force's mean over
        the step (core.wear.accept_linearised_contact)."""
        return accept_linearised_contact(self.result, jacobian, pos_i, vel_i, pos_j, vel_j, dt, self.parameter_vector,
                                         self.cos_phi, self.sin_phi, self.wear_depth, self.block_min, self.memory,
                                         self.mask, self.work)

    def advance(self, pin_kinematics, bushing_kinematics, dt: float, held: bool = False) -> ContactResult:
        """Accept a step of length dt [s] ending at these kinematics: the Archard wear of the whole step
        (docs/reference/model.md §3.7 and 3.11) with the step's mean normal force, the trapezoid of its start (the last
        accepted point, on the profile its wear left) and the contact evaluated here; ``held`` (a bool): the
        kinematics were held over the step (a co-simulation slave's inputs), the force evaluated here
        throughout.  Then the contact-onset bookkeeping.  Returns the contact evaluated here, before the
        wear update.  Refused (ParameterError, the joint unchanged): a step whose wear would exceed the bushing
        radius, and kinematics that put the pin deeper in the bushing wall than any contact reaches
        (docs/reference/model.md §3.14).  A wearing step over the wear-step limit (docs/reference/model.md §7) is
        accepted with a RuntimeWarning, once per joint, as the FMU does."""
        require("dt", dt, is_real(dt) and math.isfinite(dt) and dt >= 0.0, "a finite step >= 0 s")
        require("held", held, isinstance(held, (bool, np.bool_)), "True or False")
        pos_i, vel_i = _split_kinematics("pin_kinematics", pin_kinematics)
        pos_j, vel_j = _split_kinematics("bushing_kinematics", bushing_kinematics)
        depth_before = self.wear_depth.copy()      # the contact's extent as evaluated, before the update
        dt = float(dt)
        code = self.advance_array(pos_i, vel_i, pos_j, vel_j, dt, bool(held))
        if code == STEP_INADMISSIBLE and not self.max_wear_depth_m <= self.params.bushing_radius_m:
            raise ParameterError(worn_through_message("before this step", self.max_wear_depth_m,
                                                      self.params.bushing_radius_m)
                                 + ": no step goes on from it (docs/reference/model.md §3.14); the joint is unchanged")
        if code == STEP_INADMISSIBLE:
            p, r = self.params, self.result
            overlap = wall_overlap(r, self.parameter_vector, self.wear_depth)
            raise ParameterError(
                f"parameters pin_kinematics={_numbers(pos_i, vel_i)} and bushing_kinematics={_numbers(pos_j, vel_j)} "
                "are invalid here: they put the pin deeper into the bushing wall or press it harder than any contact "
                f"of this joint, {overlap:.3g} m with a normal force of {r[L.R_NORMAL_FORCE]:.3g} N: allowed at most "
                f"{p.admissible_penetration_m:.3g} m ({L.ADMISSIBLE_PENETRATION_SHARE:g} times the pin radius) and "
                f"{p.admissible_force_N:.3g} N from the last accepted point (a step too long for the contact, "
                "docs/reference/model.md §3.14); the joint is unchanged")
        if code == STEP_REFUSED:
            p = self.params
            raise ParameterError(f"parameter dt={dt!r} is invalid here: the step would wear the bushing by more than "
                                 f"its radius {p.bushing_radius_m!r} m (or by a non-finite depth) at k_w * wear_factor "
                                 f"= {p.wear_coefficient_m2_N!r} * {p.wear_factor!r} m^2/N; allowed a shorter step or a "
                                 "smaller wear_coefficient_m2_N or wear_factor; the joint is unchanged")
        if code == STEP_OVERSHOT and not self._warned_wear_step:
            self._warned_wear_step = True
            warnings.warn(overshoot_message(dt, self.params), RuntimeWarning, stacklevel=2)
        return self._contact_result(self.result.copy(), depth_before)

    def replay_wear(self, loading, scale: float, passes: int = 1) -> float:
        """Cycle jumping's wear (docs/reference/model.md §3.11): wear the profile by the loading rows
        (:func:`wearjoint.core.cycle_jump.replay_wear`, columns LOAD_*) in ``passes`` passes, each row over
        ``scale`` times its duration in all; returns the largest increment of one row [m].  ParameterError
        if the wear would exceed the bushing radius (the joint then unchanged)."""
        from .core.cycle_jump import N_LOAD_COLUMNS, replay_wear
        loading = np.ascontiguousarray(loading, dtype=np.float64)
        if loading.ndim != 2 or loading.shape[1] != N_LOAD_COLUMNS or not np.all(np.isfinite(loading)):
            raise ParameterError(f"loading of shape {loading.shape} is invalid: allowed a finite (n, {N_LOAD_COLUMNS}) "
                                 "array")
        if not (is_real(scale) and math.isfinite(scale) and scale >= 0.0):
            raise ParameterError(f"scale={scale!r} is invalid: allowed a finite value >= 0")
        if isinstance(passes, bool) or not isinstance(passes, (int, np.integer)) or passes < 1:
            raise ParameterError(f"passes={passes!r} is invalid: allowed an integer >= 1")
        before = self.wear_depth.copy()
        kinematics = [np.zeros(3) for _ in range(4)]
        largest = replay_wear(loading, float(scale), int(passes), self.parameter_vector, self.cos_phi, self.sin_phi,
                              self.wear_depth, self.block_min, self.memory.copy(), self.mask, self.work,
                              np.zeros(L.N_RESULT), *kinematics)
        if largest < 0.0:
            self.set_wear_profile(before)
            raise ParameterError(f"scale={scale!r} is invalid here: the replayed wear would exceed the bushing "
                                 f"radius {self.params.bushing_radius_m!r} m; the joint is unchanged")
        return float(largest)

    def restart(self) -> None:
        """Begin a new trajectory on this worn bushing (a host's new run from its initial state): apply the wear
        batch still pending (core.wear.batch_wear) and forget the contact memory, as a new joint given this
        profile."""
        _flush_batch(self.parameter_vector, self.cos_phi, self.sin_phi, self.wear_depth, self.block_min, self.mask,
                     self.work, self.memory)
        self.memory[[L.M_ACTIVE, L.M_IMPACT_VELOCITY]] = 0.0
        self.memory[L.M_START_FORCE] = L.NO_START_FORCE

    # ------------------------------------------------------------- wear profile
    @property
    def phi_deg(self) -> np.ndarray:
        """Bushing point angles in the bushing frame [deg], (0, 360]."""
        return np.degrees(self.phi_rad)

    @property
    def wear_profile(self) -> tuple[np.ndarray, np.ndarray]:
        """(phi_deg, wear_depth_m), copies."""
        return self.phi_deg.copy(), self.wear_depth.copy()

    @property
    def max_wear_depth_m(self) -> float:
        return float(self.wear_depth.max())

    @property
    def max_wear_angle_deg(self) -> float:
        """Bushing-frame angle of the deepest wear, in [0, 360)."""
        return float(self.phi_deg[int(np.argmax(self.wear_depth))] % 360.0)

    @property
    def worn_volume_m3(self) -> float:
        """Volume removed from the bushing: contact length times the worn area [m^3]."""
        return float(worn_volume(self.parameter_vector, self.wear_depth))

    def set_wear_profile(self, wear_depth_m) -> None:
        """Replace the wear depth of every bushing point [m] (finite, in [0, bushing radius])."""
        self.wear_depth[:] = self._check_profile(wear_depth_m, "wear profile: ", "wear_depth_m")
        block_minimum_depth(self.wear_depth, self.block_min)

    def _check_profile(self, wear_depth_m, where: str, name: str, memory=None) -> np.ndarray:
        """``wear_depth_m`` as floats; ParameterError naming ``name`` unless real numbers, StateError unless it (and
        ``memory``) fit this joint: n_points, the ranges."""
        allowed = f"n_points={self.wear_depth.size} depths [m] in [0, {self.params.bushing_radius_m:g}]"
        h = real_array(name, wear_depth_m, allowed)
        if h.shape != self.wear_depth.shape:
            raise StateError(f"{where}an array of shape {h.shape} given, this joint has n_points="
                             f"{self.wear_depth.size}: allowed shape ({self.wear_depth.size},)")
        memory = np.zeros(L.N_MEMORY) if memory is None else real_array("state.memory", memory,
                                                                          f"{L.N_MEMORY} finite numbers")
        if memory.shape != (L.N_MEMORY,):
            raise StateError(f"{where}contact memory of {memory.size} values given, the joint keeps {L.N_MEMORY}")
        check_state_values((), memory, h, self.params, where)
        return h

    def save_profile(self, path) -> Path:
        """Write ``phi_deg,wear_depth_m`` CSV, one row per bushing point (bushing frame): the profile only, not the
        wear batch still pending or the contact memory (:meth:`state_to_bytes` for an exact round trip)."""
        path = Path(path)
        data = np.column_stack([self.phi_deg, self.wear_depth])
        np.savetxt(path, data, delimiter=",", header="phi_deg,wear_depth_m", comments="", fmt="%.17g")
        return path

    def load_profile(self, path) -> None:
        """Read a profile written by :meth:`save_profile` (same n_points)."""
        try:
            data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
        except (OSError, ValueError) as exc:
            raise ParameterError(f"cannot read wear profile {path}: {exc}") from None
        if data.shape[1] != 2:
            raise StateError(f"wear profile {path} has {data.shape[1]} columns, expected 2: phi_deg,wear_depth_m")
        if data.shape[0] != self.wear_depth.size:
            raise StateError(f"wear profile {path} has {data.shape[0]} rows (bushing points), this joint has "
                             f"n_points={self.wear_depth.size}")
        worst = int(np.argmax(np.abs(data[:, 0] - self.phi_deg)))
        if not abs(data[worst, 0] - self.phi_deg[worst]) <= 1e-9:
            raise StateError(f"wear profile {path}: row {worst + 1} has phi_deg={data[worst, 0]!r}, bushing point "
                             f"{worst + 1} of n_points={self.wear_depth.size} is at {self.phi_deg[worst]!r}")
        self.set_wear_profile(data[:, 1])

    # ------------------------------------------------------------- state
    def get_state(self) -> JointState:
        return JointState(self.wear_depth.copy(), self.memory.copy())

    def set_state(self, state: JointState) -> None:
        """Restore a copy; StateError (the joint unchanged) if it does not fit (n_points, ranges)."""
        if not isinstance(state, JointState):
            refuse("state", state, "a JointState (as get_state gives)")
        self._check_profile(state.wear_depth_m, "state: ", "state.wear_depth_m", state.memory)
        self.memory[:] = state.memory
        self.wear_depth[:] = state.wear_depth_m
        block_minimum_depth(self.wear_depth, self.block_min)

    def state_to_bytes(self) -> bytes:
        """Exact serialisation in the state format (docs/reference/fmu.md): contact memory, wear depths."""
        return state_bytes(SF.CONTENTS_JOINT, (), self.memory, self.wear_depth)

    def state_from_bytes(self, data: bytes) -> None:
        """Restore :meth:`state_to_bytes`; StateError naming the failed check (the joint unchanged)."""
        if not isinstance(data, (bytes, bytearray, memoryview)):
            refuse("data", data, "the bytes of a state (as state_to_bytes gives)")
        _, memory, depth = read_state_bytes(data, SF.CONTENTS_JOINT, 0, self.wear_depth.size)
        self.set_state(JointState(depth, memory))
