"""What the run-time side knows of FMI: status codes and names, the FMUs' backends, the error an FMU call
raises, the C prototypes of the calls the Model Exchange master makes, and where a failed call a compiled loop
recorded (:mod:`wearjoint.fmu.loop_calls`) is turned into an exception (:func:`raise_failed_call`).  It imports no
numba."""
from __future__ import annotations

import ctypes

from ..checks import RunDiverged

FMI_OK, FMI_WARNING, FMI_DISCARD, FMI_ERROR, FMI_FATAL = range(5)     # fmi2Status and fmi3Status share them
STATUS_NAMES = ("ok", "warning", "discard", "error", "fatal", "pending")
BACKENDS = ("native", "pythonfmu")      # how the joint FMU is built (wearjoint.fmu.build)
DEFAULT_BACKEND = "native"
INTERFACES = ("co-simulation", "model-exchange")     # the joint FMU's interfaces a master uses

# C prototypes of the FMI functions the compiled masters call (pointers as addresses)
STATUS_CALL = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_void_p)
REAL_VALUES_CALL = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_size_t, ctypes.c_void_p)
SET_TIME_CALL = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_double)
COMPLETED_STEP_CALL = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_int, ctypes.c_void_p, ctypes.c_void_p)
COMPONENT_CALL = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p)
EVENT_INDICATORS_CALL = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_size_t)


class FmuError(RuntimeError):
    """An FMI call failed, or the FMU could not be built or loaded; the message carries the FMU's log."""


def c_function(function, prototype):
    """``function`` (a ctypes function of a loaded library) as a bare C function pointer of ``prototype``."""
    return prototype(function_address(function))


def function_address(function) -> int:
    """The address of ``function``, a ctypes function of a loaded library."""
    return ctypes.cast(function, ctypes.c_void_p).value


def status_text(status: int) -> str:
    """``fmi2Discard``-style name of a status."""
    return "fmi2" + (STATUS_NAMES[status].capitalize() if 0 <= status < len(STATUS_NAMES) else str(status))


def raise_failed_call(status: int, call: str, t: float, log_tail: str, refused_state: bool) -> None:
    """Raise for a status worse than a warning: :class:`RunDiverged` where the FMU refused the run's state
    (``refused_state``: a doStep's discard, an accepted Model Exchange step's error), else :class:`FmuError`;
    ``log_tail`` the FMU's last log lines."""
    if status <= FMI_WARNING:
        return
    if refused_state:
        raise RunDiverged(f"the run diverged at t = {t:.6g} s: the joint FMU's {call} returned "
                          f"{status_text(status)}{log_tail}")
    raise FmuError(f"FMU call {call} returned {status_text(status)} at t={t:.9g} s{log_tail}")
