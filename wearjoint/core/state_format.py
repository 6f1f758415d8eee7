"""The serialised state (docs/reference/fmu.md, "The state format"): one layout for the in-process joint,
both FMU backends, both FMI versions and the wear-study checkpoints, written, read and checked by
these kernels only: Python calls them, the native FMU runs the same code compiled ahead of time.

Little-endian: a 24-byte header (magic ``WJSTATE\\0``, then uint32 format version, contents,
n_points, payload bytes), the payload (float64: the contents' head values, the contact memory, the
wear depths), then the CRC-32C (Castagnoli) of header and payload as uint32.  A SliderCrank
FMU's state (``CONTENTS_MECHANISM``) has no bushing points and writes its contact memory as zeros.
Every platform the joint runs on is little-endian; the kernels still read and write byte by byte,
so a buffer needs no alignment.

A check returns 0 or a problem code (``PROBLEMS``) and fills ``values`` with what it compared.
"""
import re

import numpy as np

from .jit import kernel
from .layout import (
    M_ACTIVE, M_BATCH_MOMENT_X, M_BATCH_MOMENT_Y, M_BATCH_INDEX, M_BATCH_TIME, M_IMPACT_VELOCITY,
    M_START_FORCE, N_MEMORY, NO_START_FORCE,
)

MAGIC = b"WJSTATE\0"
MAGIC_WORD = int.from_bytes(MAGIC, "little")
FORMAT_VERSION = 4    # 2: the contact memory holds the start force of the next step; 3: and the wear batch;
# 4: an FMU instance's head ends with the flags its host's calls left (derivatives read, onsets accepted)
CONTENTS_JOINT = 1   # contact memory and wear depths (ClearanceJoint)
CONTENTS_FMU = 2     # time, initialised flag, inputs, parameters, then a joint's (an FMU instance)
CONTENTS_MECHANISM = 3   # time, initialised flag, inputs, parameters, y = [q, q_dot] (a SliderCrank FMU instance)
HEADER_BYTES = 24
CHECKSUM_BYTES = 4
FMU_HEAD_TIME, FMU_HEAD_INITIALISED, FMU_HEAD_INPUTS = 0, 1, 2   # the FMU head: time, flag, inputs, parameters

# problem code -> message; {i:k} is values[i] as an integer (d), a float (g, shortest repr) or hex (x),
# numbered in the order they appear (the C layer formats them with printf)
(OK, SHORT, BAD_MAGIC, VERSION, SIZE, CHECKSUM, CONTENTS, N_POINTS, PAYLOAD, TIME, INITIALISED,
 DEPTH_NON_FINITE, DEPTH_NEGATIVE, DEPTH_TOO_DEEP, ACTIVE_FLAG, ONSET_VELOCITY, START_FORCE, BATCH) = range(18)
PROBLEMS = {
    OK: "",
    SHORT: "the state has {0:d} bytes, fewer than the {1:d} of its header and checksum",
    BAD_MAGIC: "the state does not begin with the magic bytes WJSTATE\\0 of a wearjoint state",
    VERSION: "the state has format version {0:d}, this build reads version {1:d}",
    SIZE: "the state has {0:d} bytes, its header declares {1:d} (a payload of {2:d} bytes)",
    CHECKSUM: "the state's CRC-32C is 0x{0:x}, its header and payload give 0x{1:x}: the bytes are corrupted",
    CONTENTS: "the state's contents are kind {0:d}, expected kind {1:d} (1: a joint's, 2: a joint FMU instance's, "
              "3: a SliderCrank FMU instance's)",
    N_POINTS: "the state holds {0:d} bushing points, this joint has n_points={1:d}",
    PAYLOAD: "the state's payload has {0:d} bytes, its contents and n_points={1:d} take {2:d}",
    TIME: "the state's time={0:g} s is invalid: allowed a finite value",
    INITIALISED: "the state's initialised flag={0:g} is invalid: allowed 0 or 1",
    DEPTH_NON_FINITE: "wear_depth[{0:d}]={1:g} m is not finite: allowed a depth in [0, {2:g}] m",
    DEPTH_NEGATIVE: "wear_depth[{0:d}]={1:g} m is negative: allowed a depth in [0, {2:g}] m",
    DEPTH_TOO_DEEP: "wear_depth[{0:d}]={1:g} m is deeper than the bushing radius: allowed a depth in [0, {2:g}] m",
    ACTIVE_FLAG: "the contact memory's active flag={0:g} is invalid: allowed 0 or 1",
    ONSET_VELOCITY: "the contact memory's onset velocity={0:g} m/s with active flag={1:g} is invalid: allowed a "
                    "finite value >= impact_velocity_floor={2:g} m/s while a contact is active, 0 otherwise",
    START_FORCE: "the contact memory's start force={0:g} N is invalid: allowed a finite force >= 0, or -1 before the "
                 "first accepted step",
    BATCH: "the contact memory's wear batch value {0:g} (slot {1:d}) is invalid: allowed finite sums >= 0, a finite "
           "first moment and a bushing point index in [0, {2:d})",
}


_PLACEHOLDER = re.compile(r"\{(\d):([dgx])\}")


def problem_message(problem: int, values) -> str:
    """The message of ``problem`` with the values it compared."""
    def text(match):
        value = values[int(match[1])]
        return repr(float(value)) if match[2] == "g" else f"{int(value):{'08x' if match[2] == 'x' else 'd'}}"
    return _PLACEHOLDER.sub(text, PROBLEMS[problem])


def printf_problems() -> list[tuple[str, str]]:
    """Each problem's message as a printf format of strings and the kind of each value (the C layer's)."""
    table = []
    for problem in sorted(PROBLEMS):
        template = PROBLEMS[problem]
        fields = _PLACEHOLDER.findall(template)
        if [int(index) for index, _ in fields] != list(range(len(fields))) or "%" in template:
            raise RuntimeError(f"state problem {problem}: values must appear in order 0, 1, 2 and no '%'")
        table.append((_PLACEHOLDER.sub("%s", template), "".join(kind for _, kind in fields)))
    return table


def _crc_tables() -> np.ndarray:
    """Slicing-by-8 tables of the reflected CRC-32C polynomial 0x82F63B78."""
    tables = np.zeros((8, 256), dtype=np.uint32)
    for n in range(256):
        c = n
        for _ in range(8):
            c = (c >> 1) ^ 0x82F63B78 if c & 1 else c >> 1
        tables[0, n] = c
    for n in range(256):
        c = int(tables[0, n])
        for t in range(1, 8):
            c = int(tables[0, c & 0xFF]) ^ (c >> 8)
            tables[t, n] = c
    return tables


_CRC_TABLES = _crc_tables()


@kernel
def crc32c(data, n):
    """CRC-32C of the first ``n`` bytes of ``data`` (uint8); of b"123456789" it is 0xE3069283."""
    t = _CRC_TABLES
    c = np.uint32(0xFFFFFFFF)
    i = 0
    while i + 8 <= n:
        lo = c ^ (np.uint32(data[i]) | (np.uint32(data[i + 1]) << 8) | (np.uint32(data[i + 2]) << 16)
                  | (np.uint32(data[i + 3]) << 24))
        c = (t[7, lo & 0xFF] ^ t[6, (lo >> 8) & 0xFF] ^ t[5, (lo >> 16) & 0xFF] ^ t[4, lo >> 24]
             ^ t[3, data[i + 4]] ^ t[2, data[i + 5]] ^ t[1, data[i + 6]] ^ t[0, data[i + 7]])
        i += 8
    while i < n:
        c = t[0, (c ^ data[i]) & 0xFF] ^ (c >> 8)
        i += 1
    return c ^ np.uint32(0xFFFFFFFF)


@kernel
def state_size(n_head, n_points):
    """Bytes of a state with ``n_head`` head values and ``n_points`` wear depths."""
    return HEADER_BYTES + 8 * (n_head + N_MEMORY + n_points) + CHECKSUM_BYTES


@kernel
def _put_u32(data, at, value):
    for k in range(4):
        data[at + k] = (value >> (8 * k)) & 0xFF


@kernel
def _get_u32(data, at):
    value = 0
    for k in range(4):
        value |= np.int64(data[at + k]) << (8 * k)
    return value


@kernel
def _put_values(data, at, values):
    for i in range(values.size):
        bits = np.float64(values[i]).view(np.uint64)
        for k in range(8):
            data[at + 8 * i + k] = (bits >> np.uint64(8 * k)) & np.uint64(0xFF)


@kernel
def _get_values(data, at, values):
    for i in range(values.size):
        bits = np.uint64(data[at + 8 * i])
        for k in range(1, 8):
            bits = bits | (np.uint64(data[at + 8 * i + k]) << np.uint64(8 * k))
        values[i] = np.uint64(bits).view(np.float64)


@kernel
def write_state(data, contents, head, memory, wear_depth):
    """The state of ``head`` (the contents' leading values), ``memory`` and ``wear_depth`` into
    ``data`` (uint8, ``state_size`` bytes), checksum included."""
    n = data.size
    for k in range(8):
        data[k] = (MAGIC_WORD >> (8 * k)) & 0xFF
    _put_u32(data, 8, FORMAT_VERSION)
    _put_u32(data, 12, contents)
    _put_u32(data, 16, wear_depth.size)
    _put_u32(data, 20, n - HEADER_BYTES - CHECKSUM_BYTES)
    _put_values(data, HEADER_BYTES, head)
    _put_values(data, HEADER_BYTES + 8 * head.size, memory)
    _put_values(data, HEADER_BYTES + 8 * (head.size + memory.size), wear_depth)
    _put_u32(data, n - CHECKSUM_BYTES, crc32c(data, n - CHECKSUM_BYTES))


@kernel
def _differs(found, expected, values):
    """Whether a header field ``found`` is not ``expected`` (then ``values`` holds the two)."""
    if found == expected:
        return False
    values[0], values[1] = found, expected
    return True


@kernel
def check_header(data, contents, n_head, n_points, values):
    """0 if ``data`` is an intact state of ``contents`` with ``n_head`` head values for ``n_points``
    bushing points, else the first problem found (header, size, checksum, then what it holds)."""
    n = data.size
    if n < HEADER_BYTES + CHECKSUM_BYTES:
        values[0], values[1] = n, HEADER_BYTES + CHECKSUM_BYTES
        return SHORT
    for k in range(8):
        if data[k] != (MAGIC_WORD >> (8 * k)) & 0xFF:
            return BAD_MAGIC
    if _differs(_get_u32(data, 8), FORMAT_VERSION, values):
        return VERSION
    payload = _get_u32(data, 20)
    if n != HEADER_BYTES + payload + CHECKSUM_BYTES:
        values[0], values[1], values[2] = n, HEADER_BYTES + payload + CHECKSUM_BYTES, payload
        return SIZE
    if _differs(_get_u32(data, n - CHECKSUM_BYTES), crc32c(data, n - CHECKSUM_BYTES), values):
        return CHECKSUM
    if _differs(_get_u32(data, 12), contents, values):
        return CONTENTS
    if _differs(_get_u32(data, 16), n_points, values):
        return N_POINTS
    if payload != 8 * (n_head + N_MEMORY + n_points):
        values[0], values[1], values[2] = payload, n_points, 8 * (n_head + N_MEMORY + n_points)
        return PAYLOAD
    return OK


@kernel
def read_state(data, head, memory, wear_depth):
    """Copy a state's values (checked by :func:`check_header`) into ``head``, ``memory`` and ``wear_depth``."""
    _get_values(data, HEADER_BYTES, head)
    _get_values(data, HEADER_BYTES + 8 * head.size, memory)
    _get_values(data, HEADER_BYTES + 8 * (head.size + memory.size), wear_depth)


@kernel
def check_fmu_head(head, values):
    """0 if an FMU state's time is finite and its initialised flag 0 or 1, else the problem."""
    time, flag = head[FMU_HEAD_TIME], head[FMU_HEAD_INITIALISED]
    if not np.isfinite(time):
        values[0] = time
        return TIME
    if flag != 0.0 and flag != 1.0:
        values[0] = flag
        return INITIALISED
    return OK


@kernel
def check_wear_depth(wear_depth, bushing_radius, values):
    """0 if every depth is finite and in [0, bushing_radius], else the problem at the first that is not
    (``values``: its 1-based index, its value, the bushing radius)."""
    for k in range(wear_depth.size):
        h = wear_depth[k]
        problem = (DEPTH_NON_FINITE if not np.isfinite(h) else DEPTH_NEGATIVE if h < 0.0
                   else DEPTH_TOO_DEEP if h > bushing_radius else OK)
        if problem != OK:
            values[0], values[1], values[2] = k + 1, h, bushing_radius
            return problem
    return OK


@kernel
def check_memory(memory, velocity_floor, values):
    """0 if the contact memory is one the kernels write: active flag 0 or 1, the onset velocity finite
    and >= ``velocity_floor`` while active, 0 otherwise, the start force finite and >= 0 or NO_START_FORCE."""
    active, velocity = memory[M_ACTIVE], memory[M_IMPACT_VELOCITY]
    if active != 0.0 and active != 1.0:
        values[0] = active
        return ACTIVE_FLAG
    if not (np.isfinite(velocity) and velocity >= velocity_floor) if active == 1.0 else velocity != 0.0:
        values[0], values[1], values[2] = velocity, active, velocity_floor
        return ONSET_VELOCITY
    start = memory[M_START_FORCE]
    if not (np.isfinite(start) and (start >= 0.0 or start == NO_START_FORCE)):
        values[0] = start
        return START_FORCE
    return OK


@kernel
def check_batch(memory, n_points, values):
    """0 if the contact memory's wear batch (layout.M_BATCH_*) is one the kernels write: finite sums >= 0, a
    finite first moment of the load, an integral bushing point index in [0, n_points) (0 in a state without points)."""
    for m in range(M_BATCH_TIME, M_BATCH_INDEX + 1):
        value = memory[m]
        if m == M_BATCH_MOMENT_X or m == M_BATCH_MOMENT_Y:
            good = np.isfinite(value)
        elif m == M_BATCH_INDEX:
            good = value == np.floor(value) and (0.0 <= value < n_points or value == 0.0)   # 0 without points
        else:
            good = np.isfinite(value) and value >= 0.0
        if not good:
            values[0], values[1], values[2] = value, m, n_points
            return BATCH
    return OK


@kernel
def check_values(head, memory, wear_depth, bushing_radius, velocity_floor, values):
    """0 if a state's values are in range: an FMU head's time and flag (if ``head`` has any), the
    contact memory (onset velocity >= ``velocity_floor``), the wear depths up to ``bushing_radius``;
    else the first problem."""
    problem = check_fmu_head(head, values) if head.size > 0 else OK
    if problem == OK:
        problem = check_memory(memory, velocity_floor, values)
    if problem == OK:
        problem = check_batch(memory, wear_depth.shape[0], values)
    if problem == OK:
        problem = check_wear_depth(wear_depth, bushing_radius, values)
    return problem
