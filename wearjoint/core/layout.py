"""Index layout of the plain arrays the numba kernels share.

Kernels take parameters and results as flat float64 arrays (numba compiles
module-level integers as constants); these names are the only place the
positions are defined.
"""

# --- the wear-step limit (docs/reference/model.md §7): in a conforming contact an explicit step wears
# lambda = k_f k_w |v_t| dt of the penetration (k_f the foundation modulus, k_w with the wear factor).
# The foundation's update relaxes each point's pressure exactly over the step (core.wear.foundation_wear);
# the explicit placements (patch, penetration) overshoot past about 1
WEAR_STEP_SHARE = 4.0            # the largest lambda of one accepted step of the foundation's update
WEAR_STEP_SHARE_EXPLICIT = 0.3   # the largest share of the penetration one explicit (patch, penetration) step wears
MAX_WEAR_STEP_S = 3e-5           # and never a longer accepted step with wear [s] (the statistics, docs/reference/model.md §7)
WEAR_BATCH_SHARE = 0.1           # the largest lambda of a wear batch: its lag stays a tenth of the overlap (§3.11)
# the joint FMU's accept entry point's ``held``: 0 the step's end kinematics, 1 held over it, 2 held and its host
# linearising the loads at its start (the wear takes that linearised force's mean: core.wear.accept_linearised_contact)
HELD_LINEARISED = 2
# --- admissible states (docs/reference/model.md §3.14): a pin further into the bushing wall than this share of its radius is no
# contact of the joint's materials (at 2 % the mean pressure over the pin's projected area passes any bushing's yield)
ADMISSIBLE_PENETRATION_SHARE = 0.02

# --- joint parameter vector.  Every slot but the derived ones (P_WEAR_COEFFICIENT, P_EFFECTIVE_MODULUS,
# P_FOUNDATION_MODULUS, P_DAMPING_COEFFICIENT; P_STIFFNESS where given as 0) is given (JointParameters, or the
# FMU's parameters: wearjoint.fmu.variables maps each to its slot); the derived slots are filled by
# core.wear.complete_joint_parameters.
P_PIN_RADIUS = 0          # R_i [m]
P_BUSHING_RADIUS = 1      # R_j [m]
P_PIN_OFFSET_X = 2        # s_i^P in the pin body frame [m]
P_PIN_OFFSET_Y = 3
P_BUSHING_OFFSET_X = 4    # s_j^P in the bushing body frame [m]
P_BUSHING_OFFSET_Y = 5
P_STIFFNESS = 6           # K [N/m^n]; given as 0: derived from the radii and materials (Eqs. 16-17)
P_EXPONENT = 7            # n [-]
P_RESTITUTION = 8         # e_r [-]
P_FRICTION = 9            # mu [-]
P_V0 = 10                 # friction tolerance velocities [m/s]
P_V1 = 11
P_WEAR_COEFFICIENT = 12   # derived: k_w times the wear acceleration factor [m^2/N]
P_CONTACT_LENGTH = 13     # L [m]
P_EFFECTIVE_MODULUS = 14  # derived: E* of Eq. 32 [Pa]
P_RHO_MODE = 15           # RHO_* (docs/reference/model.md §3.2)
P_WEAR_PLACEMENT = 16     # PLACEMENT_* (docs/reference/model.md §3.7)
P_SLIDING = 17            # SLIDING_* (docs/reference/model.md §3.8)
P_VELOCITY_FLOOR = 18     # Lankarani-Nikravesh: floor on the stored impact velocity [m/s] (docs/reference/model.md §3.5)
P_PIN_YOUNGS_MODULUS = 19     # E_i [Pa]
P_PIN_POISSON_RATIO = 20      # nu_i [-]
P_BUSHING_YOUNGS_MODULUS = 21  # E_j [Pa]
P_BUSHING_POISSON_RATIO = 22  # nu_j [-]
P_ARCHARD_COEFFICIENT = 23    # k_w as given [m^2/N]
P_WEAR_FACTOR = 24            # wear acceleration factor [-]
P_CONTACT_MODEL = 25          # CONTACT_* (docs/reference/model.md §3.10)
P_FOUNDATION_MODULUS = 26     # derived: k_f L / R_i of the elastic foundation [N/m^2] (docs/reference/model.md §3.10)
P_CONTACT_DAMPING = 27        # DAMPING_* (docs/reference/model.md §3.5)
P_RESTITUTION_SPEED = 28      # impact speed at which the Hunt-Crossley damping restitutes e_r [m/s]
P_WEAR_INTERVAL = 29          # the foundation's wear is applied once per this much contact time [s] (0: every step)
P_EFFECTIVE_MASS = 30         # Tsuji: the mass the contact decelerates along its normal [kg]
P_DAMPING_COEFFICIENT = 31    # derived: the damping law's coefficient (core.damping.damping_coefficient)
N_JOINT_PARAMETERS = 32

# --- the choice parameters: each name (the parameter sets' value) and its code (the kernels' and the FMUs' value),
# written once; a new choice is a row here and its branch in the kernel that reads the slot
RHO_CONFORMAL, RHO_PAPER = 0, 1                                        # P_RHO_MODE
PLACEMENT_PATCH, PLACEMENT_PENETRATION, PLACEMENT_FOUNDATION = 0, 1, 2  # P_WEAR_PLACEMENT
SLIDING_ROTATION, SLIDING_TANGENTIAL = 0, 1                            # P_SLIDING
CONTACT_FOUNDATION, CONTACT_DEEPEST = 0, 1                             # P_CONTACT_MODEL
DAMPING_HUNT_CROSSLEY, DAMPING_LANKARANI_NIKRAVESH, DAMPING_TSUJI, DAMPING_LANKARANI_NIKRAVESH_EXACT = 0, 1, 2, 3

# --- contact memory (the joint's scalar state besides the wear profile)
M_ACTIVE = 0              # 1.0 while a contact that began on an accepted step lasts
M_IMPACT_VELOCITY = 1     # delta_dot^(-) stored at that contact's onset [m/s]
M_START_FORCE = 2         # F_N at the last accepted point on its worn profile: the next step's start [N]
# the wear batch not yet applied (core.wear.batch_wear, docs/reference/model.md §3.11): its accepted steps' summed time [s],
# relative rotation |d alpha| [rad], tangential slide |v_T| dt [m], load (F_N times the sliding measure in use),
# the load's first moment (sum of load times eccentricity [m]: the batch is applied at the load-weighted mean
# eccentricity) and the last step's deepest bushing point
M_BATCH_TIME = 3
M_BATCH_ANGLE = 4
M_BATCH_SLIDE = 5
M_BATCH_LOAD = 6
M_BATCH_MOMENT_X = 7
M_BATCH_MOMENT_Y = 8
M_BATCH_INDEX = 9
N_MEMORY = 10
NO_START_FORCE = -1.0     # M_START_FORCE before the first accepted point

# --- result of one joint evaluation
R_PIN_FX = 0              # force on the pin body, global frame [N]
R_PIN_FY = 1
R_PIN_TORQUE = 2          # torque about the pin body's reference point [N m]
R_BUSHING_FX = 3
R_BUSHING_FY = 4
R_BUSHING_TORQUE = 5
R_NORMAL_FORCE = 6        # F_N >= 0 [N]
R_FRICTION_FORCE = 7      # friction on the pin along t (signed) [N]
R_PENETRATION = 8         # delta_max = R_i - |d_min| [m]; negative without contact (minus the gap)
R_CONTACT = 9             # 1.0 in contact, else 0.0
R_CONTACT_INDEX = 10      # bushing point index (0-based) of the deepest point, -1 if none
R_ECCENTRICITY_X = 11     # pin centre relative to bushing centre, bushing frame [m]
R_ECCENTRICITY_Y = 12
R_TANGENTIAL_VELOCITY = 13  # pin relative to bushing along t [m/s]
R_PENETRATION_RATE = 14   # delta_dot [m/s]
R_CONTACT_ANGLE = 15      # bushing-frame angle of the contact point [rad], or of e without contact
N_RESULT = 16
N_KINEMATIC_INPUTS = 12   # x, y, theta, vx, vy, omega of the pin body, then of the bushing body

# --- contact search blocks (see geometry.find_deepest_point)
BLOCK_SIZE = 32

# --- slider-crank parameter vector (SliderCrankParameters packed by wearjoint.slider_crank; the fields' table is
# wearjoint.mechanism_parameters.MECHANISM_FIELDS: field k of the user's values fills slot k, scaled)
MP_CRANK_LENGTH = 0
MP_ROD_LENGTH = 1
MP_CRANK_MASS = 2
MP_CRANK_INERTIA = 3
MP_ROD_MASS = 4
MP_ROD_INERTIA = 5
MP_SLIDER_MASS = 6
MP_SLIDER_INERTIA = 7
MP_GRAVITY_X = 8          # gravity along the slider's axis [m/s^2] (mechanism frame)
MP_GRAVITY_Y = 9          # gravity across the slide [m/s^2] (the paper's: -9.81)
MP_OMEGA = 10             # crank speed magnitude [rad/s]; theta1 = theta0 - omega t
MP_THETA0 = 11
MP_ALPHA = 12             # Baumgarte
MP_BETA = 13
MP_SLIDER_FORCE = 14      # constant load on the slider [N], positive towards the crank's pivot
MP_LOAD_ROWS = 15         # rows of the slider-load table (0: none)
MAX_LOAD_ROWS = 361       # the most rows a slider-load table has (every degree, 0 and 360 included)
MP_LOAD_ANGLES = 16       # the table's crank angles [rad], 0 ... 2 pi increasing, MAX_LOAD_ROWS slots
MP_LOAD_FORCES = MP_LOAD_ANGLES + MAX_LOAD_ROWS   # the table's loads [N], MAX_LOAD_ROWS slots
MP_CLEARANCE_JOINT = MP_LOAD_FORCES + MAX_LOAD_ROWS  # the joint with the clearance (CLEARANCE_*); the others are ideal
N_MECHANISM_FIELDS = MP_CLEARANCE_JOINT + 1  # the slots the fields fill (core.slider_load.mechanism_parameter_vector)
MP_SLIDER_FORCE_INPUT = N_MECHANISM_FIELDS       # a master's load on the slider [N] (the SliderCrank FMU's input)
N_MECHANISM_PARAMETERS = MP_SLIDER_FORCE_INPUT + 1
# what core.slider_load.load_table_problem finds wrong with a slider-load table: kind * LOAD_TABLE_ROW_BASE + row
LOAD_TABLE_ROWS, LOAD_TABLE_START, LOAD_TABLE_END, LOAD_TABLE_RISE, LOAD_TABLE_PERIODIC = 1, 2, 3, 4, 5
LOAD_TABLE_ROW_BASE = 1000

# state vector y = [q (9), q_dot (9)], q = [x1 y1 th1 x2 y2 th2 x3 y3 th3] (Eq. 38)
N_COORDINATES = 9
# the mechanism kernels' workspace (kernel_calls.mechanism_arrays makes it): jac and schur (N x N), phi, phi_dot, gamma,
# M^-1 (Eq. 42) and the applied forces (N each)
WORKSPACE_SHAPES = ((N_COORDINATES, N_COORDINATES),) * 2 + ((N_COORDINATES,),) * 5
WORKSPACE_INVERSE_MASS = 5
Y_SLIDER_X = 6
Y_SLIDER_V = 15
# body blocks inside q: crank 0..2, rod 3..5, slider 6..8; GROUND stands for the fixed frame (no coordinates)
CRANK = 0
ROD = 3
SLIDER = 6
GROUND = -1
# where the clearance joint is (MP_CLEARANCE_JOINT), its pin body and bushing body (core.joint_location):
# crank-rod (pin on the crank's tip, bushing in the rod's big end: the paper's), rod-slider (pin in the slider,
# bushing in the rod's small end), crank-ground (the crank's journal in a bushing fixed in the frame)
CLEARANCE_CRANK_ROD, CLEARANCE_ROD_SLIDER, CLEARANCE_CRANK_GROUND = 0, 1, 2
# field -> its (name, code) pairs, in the order of their codes (0, 1, ...: the FMUs check 0 <= code < count)
CHOICES = {
    "rho_mode": (("conformal", RHO_CONFORMAL), ("paper", RHO_PAPER)),
    "wear_placement": (("patch", PLACEMENT_PATCH), ("penetration", PLACEMENT_PENETRATION),
                       ("foundation", PLACEMENT_FOUNDATION)),
    "sliding_distance": (("rotation", SLIDING_ROTATION), ("tangential", SLIDING_TANGENTIAL)),
    "contact_model": (("foundation", CONTACT_FOUNDATION), ("deepest", CONTACT_DEEPEST)),
    "contact_damping": (("hunt-crossley", DAMPING_HUNT_CROSSLEY), ("lankarani-nikravesh", DAMPING_LANKARANI_NIKRAVESH),
                        ("tsuji", DAMPING_TSUJI), ("lankarani-nikravesh-exact", DAMPING_LANKARANI_NIKRAVESH_EXACT)),
    "clearance_joint": (("crank-rod", CLEARANCE_CRANK_ROD), ("rod-slider", CLEARANCE_ROD_SLIDER),
                        ("crank-ground", CLEARANCE_CRANK_GROUND)),
}
if any([code for _, code in pairs] != list(range(len(pairs))) for pairs in CHOICES.values()):
    raise RuntimeError("core.layout.CHOICES: each parameter's codes must be 0, 1, ... in order")


def choice_names(field: str) -> tuple[str, ...]:
    """The names a choice parameter takes, in the order of their codes."""
    return tuple(name for name, _ in CHOICES[field])


def choice_code(field: str, name: str) -> int:
    """The code of choice ``name`` of ``field`` (the kernels' and the FMUs' value)."""
    return dict(CHOICES[field])[name]


CLEARANCE_JOINTS = choice_names("clearance_joint")

# --- how the contact forces enter the mechanism
MODE_IDEAL = 0            # the clearance joint's revolute as a constraint (closed-form baseline)
MODE_CLEARANCE = 1        # constraint removed, ClearanceJoint evaluated inside the RHS
MODE_EXTERNAL = 2         # constraint removed, forces given (held from a co-simulation slave)
MODE_LINEARISED = 3       # constraint removed, forces linear in the joint's kinematics (a co-simulation slave's
                          # forces and their Jacobian at the step's start: F0 + J (u - u0), core.linearisation)

# --- a linearisation of the joint's loads (MODE_LINEARISED): at the kinematic inputs u0, the loads F0 (the pin
# body's force x, y and torque, the bushing body's, then the normal force) and their Jacobian J (row-major,
# N_LINEARISED_LOADS x N_KINEMATIC_INPUTS), then scratch for the kinematics' change
N_LINEARISED_LOADS = 7
LIN_INPUTS = 0
LIN_LOADS = LIN_INPUTS + 12
LIN_JACOBIAN = LIN_LOADS + N_LINEARISED_LOADS
LIN_SCRATCH = LIN_JACOBIAN + N_LINEARISED_LOADS * 12
N_LINEARISATION = LIN_SCRATCH + 12
# what a joint FMU publishes of it (its d_*_d_* outputs, fmu.variables.LINEARISED_ROWS): the rows of the pin body's
# force x, y and torque, the bushing body's torque and the normal force; the bushing body's force is minus the pin
# body's (Eq. 22)
PUBLISHED_LINEARISED_LOADS = (0, 1, 2, 5, 6)
N_PUBLISHED_LINEARISED_LOADS = len(PUBLISHED_LINEARISED_LOADS)
# the loads depend on the bodies' relative position and velocity: the derivatives along the bushing body's x, y, vx,
# vy (kinematic inputs 6, 7, 9, 10) are minus those along the pin body's (0, 1, 3, 4), exactly in the kernels (their
# forward mode is linear in the direction); a master may read only the other columns of the published rows
ALL_KINEMATIC_COLUMNS = tuple(range(N_KINEMATIC_INPUTS))
RELATIVE_COLUMNS = (0, 1, 2, 3, 4, 5, 8, 11)
TRANSLATION_PAIRS = ((6, 0), (7, 1), (9, 3), (10, 4))
# the SliderCrank FMU's inputs (fmu.slider_crank.INPUTS): the joint's six loads, the slider's load, then the
# linearisation a joint FMU publishes (integrated with load_coupling linearised): the normal force, the published
# rows of J, the inputs u0 they were evaluated at
MECHANISM_INPUT_SLIDER_FORCE = 6
MECHANISM_INPUT_NORMAL_FORCE = 7
MECHANISM_INPUT_DERIVATIVES = 8
MECHANISM_INPUT_EVALUATED = MECHANISM_INPUT_DERIVATIVES + N_PUBLISHED_LINEARISED_LOADS * 12
N_MECHANISM_INPUTS = MECHANISM_INPUT_EVALUATED + 12

# --- per-revolution statistics (one row per crank revolution)
S_IMPACTS = 0             # contact onsets at accepted points
S_CONTACT_TIME = 1        # time in contact [s]
S_TIME = 2                # time covered [s]
S_ACC_MAX = 3             # slider acceleration extremes [m/s^2]
S_ACC_MIN = 4
S_FORCE_MAX = 5           # max normal force [N]
S_ECC_MAX = 6             # max |eccentricity| [m]
N_STATS = 7

# --- time series samples
T_TIME = 0
T_CRANK_ANGLE = 1         # theta1 [rad]
T_SLIDER_X = 2
T_SLIDER_V = 3
T_SLIDER_A = 4
T_PIN_FX = 5              # contact force on the pin (its body), global [N]
T_PIN_FY = 6
T_NORMAL_FORCE = 7
T_FRICTION_FORCE = 8
T_ECC_X = 9               # eccentricity in the bushing body's frame [m]
T_ECC_Y = 10
T_PENETRATION = 11        # signed: negative is the gap
T_CONTACT = 12
T_RELATIVE_OMEGA = 13     # omega_pin body - omega_bushing body [rad/s] (the rotation sliding rate, Eq. 33)
T_TANGENTIAL_VELOCITY = 14  # pin relative to bushing along t at the contact [m/s]
N_SAMPLE_COLUMNS = 15
SAMPLE_NAMES = ("time_s", "crank_angle_rad", "slider_x_m", "slider_v_m_s", "slider_a_m_s2",
                "pin_force_x_N", "pin_force_y_N", "normal_force_N", "friction_force_N",
                "eccentricity_x_m", "eccentricity_y_m", "penetration_m", "contact", "relative_omega_rad_s",
                "tangential_velocity_m_s")

# --- recorder bookkeeping
K_PREVIOUS_CONTACT = 0
K_NEXT_SAMPLE = 1
K_SAMPLE_DT = 2
K_N_SAMPLES = 3
K_PREVIOUS_PENETRATION = 4   # signed penetration at the previous accepted point [m]
N_TRACK = 5
