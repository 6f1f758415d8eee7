"""What the run-time side knows of FMI: status codes and names, the FMUs' backends, the error an FMU call
raises, the C prototypes of the calls the compiled masters make (ctypes prototypes, and :func:`c_call` for a
master compiled ahead of time, which knows the functions by address only), and the one place a failed call is
recorded (compiled loops) and turned into an exception (:func:`raise_failed_call`)."""
from __future__ import annotations

import ctypes

from ..checks import RunDiverged
from ..core.jit import kernel

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


def c_call(*kinds):
    """A numba intrinsic ``call(address, *arguments)``: the C function at ``address`` (an integer) called with one
    argument per kind of ``kinds`` ("pointer": an address as an integer, "double", "int": C int, "size": size_t),
    its C int result.  A compiled master calls the FMU's functions through these: the addresses are arguments, so
    its code holds none and compiles ahead of time (cosim.master_entry_points)."""
    from llvmlite import ir
    from numba.core import types
    from numba.extending import intrinsic

    c_types = [{"pointer": ir.IntType(8).as_pointer(), "double": ir.DoubleType(), "int": ir.IntType(32),
                "size": ir.IntType(64)}[kind] for kind in kinds]
    numba_types = {"double": types.float64, "int": types.int32, "size": types.uint64}

    def typer(address, arguments):
        def codegen(context, builder, signature, values):
            function = builder.inttoptr(values[0], ir.FunctionType(ir.IntType(32), c_types).as_pointer())
            return builder.call(function, [
                builder.inttoptr(value, c_type) if kind == "pointer"
                else context.cast(builder, value, numba_type, numba_types[kind])
                for kind, c_type, value, numba_type in zip(kinds, c_types, values[1:], signature.args[1:])])
        return types.int32(address, *arguments), codegen

    arity = {1: lambda typingctx, address, a: typer(address, (a,)),   # numba's intrinsics take no *arguments
             2: lambda typingctx, address, a, b: typer(address, (a, b)),
             4: lambda typingctx, address, a, b, c, d: typer(address, (a, b, c, d))}[len(kinds)]
    arity.__name__ = arity.__qualname__ = "c_call_" + "_".join(kinds)    # numba keys an intrinsic by its name
    return intrinsic(arity)


# the FMI 2.0 co-simulation calls of cosim.master_loop and the clock it times them with, by address
call_do_step = c_call("pointer", "double", "double", "int")           # fmi2DoStep(c, t, h, noSetFMUStatePriorToCurrentPoint)
call_real_values = c_call("pointer", "pointer", "size", "pointer")    # fmi2SetReal / fmi2GetReal(c, vrs, n, values)
call_with_state = c_call("pointer", "pointer")     # fmi2GetFMUstate / fmi2FreeFMUstate(c, &state), fmi2SetFMUstate(c, state)
call_clock = c_call("int", "pointer")               # clock_gettime(clock id, &timespec)


@kernel(inline='always')   # call sites with literal call indices: one compile each, were it a call
def failed_call(register, at, call, status, t):
    """A compiled loop's FMI call check: True if ``status`` is worse than a warning, and then, unless a failure
    is already recorded, ``register[at:at + 3]`` = (the call's index in the caller's table of calls, its
    status, the time [s] it was made for)."""
    if status > FMI_WARNING:
        if register[at] == 0.0:
            register[at] = call
            register[at + 1] = status
            register[at + 2] = t
        return True
    return False


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
