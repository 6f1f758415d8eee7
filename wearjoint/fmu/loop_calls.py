"""What a compiled loop needs to call an FMU: the C functions by address (:func:`c_call`, numba intrinsics), so
that its code holds no address and compiles ahead of time (cosim.master_entry_points), and the one place a failed
call is recorded (:func:`failed_call`; :func:`wearjoint.fmu.fmi.raise_failed_call` turns it into an exception)."""
from __future__ import annotations

from llvmlite import ir
from numba.core import types
from numba.extending import intrinsic

from ..core.jit import kernel
from .fmi import FMI_WARNING


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


def c_call(*kinds):
    """A numba intrinsic ``call(address, *arguments)``: the C function at ``address`` (an integer) called with one
    argument per kind of ``kinds`` ("pointer": an address as an integer, "double", "int": C int, "size": size_t),
    its C int result.  A compiled master calls the FMU's functions through these: the addresses are arguments, so
    its code holds none and compiles ahead of time (cosim.master_entry_points)."""
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
