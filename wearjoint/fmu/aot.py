"""Ahead-of-time compilation of a model's kernels for its native FMU.

A native FMU runs the very kernels the library runs: the numba ``cfunc`` entry points of its
model (:data:`ENTRY_POINTS`: ``joint``, the ClearanceWearJoint FMU, from
:mod:`wearjoint.fmu.joint_entry_points`, the kernels :class:`wearjoint.ClearanceJoint` runs;
``slider-crank``, the SliderCrank FMU, from :mod:`wearjoint.fmu.slider_crank_entry_points`, the
mechanism kernels of the monolithic engine).  For each, numba's optimised LLVM IR is taken,
the ``cfunc`` wrapper (which reports Python exceptions through the CPython API) is dropped,
and the compiled function behind it is exported under a stable C name with numba's calling
convention ``int32 f(void *retptr, void *excinfo, arguments...)`` (status 0 =
success).  Every other function becomes internal, unreferenced code is removed
(global dead-code elimination), and the module's IR is written out: the one
compilation of the kernels every platform's binary comes from.  :func:`emit_object`
turns that IR into an object for a platform (:mod:`wearjoint.fmu.platforms`) by
replacing only the target triple and data layout: a position-independent object for
the architecture's baseline CPU (generic x86-64, generic aarch64), so the FMU runs on
any machine of that architecture.  The IR has no fast-math flags, so no platform fuses
a multiply and an add: aarch64 gives the x86-64 numbers bit for bit.

The kernels are compiled with ``error_model="numpy"`` and without NRT
(``core.jit.kernel``): they have no path that raises, allocates or touches
Python.  :func:`compile_ir` proves it: the only symbols an object may
leave undefined are C math functions (:data:`ALLOWED_UNDEFINED`), otherwise the
build fails.

Run as ``python -m wearjoint.fmu.aot MODEL OUT_DIR [SYMBOL,...]`` in a fresh process with
``NUMBA_CPU_NAME=generic``; :func:`wearjoint.fmu.kernel_ir.compile_kernel_ir` does that (where the package
ships no IR for these kernels), in two processes on two cores (:data:`PARTS`), which share numba's cache.  The entry points are compiled there, never taken from numba's cache (a cached function has
no IR); the kernels they call may be: numba caches each with the bitcode that links it into a caller.  Writes per entry point
``<symbol>.ll``; prints the number of numba's compilations so far after each (the builder's progress
bar).
"""
from __future__ import annotations

import functools
import importlib
import re
import sys
from pathlib import Path

# model -> (module of its cfuncs, {stable C symbol: (cfunc, its number of arguments)}); the C
# prototypes (the model's kernel header: fmu_src/joint/joint_kernels.h, fmu_src/slider_crank/slider_crank_kernels.h; the state
# format's, wearjoint_*_state*, in fmu_src/fmi/state_format.h for both) take two
# more (return value, exception info).  A cfunc whose argument count differs from its
# prototype's fails the build.
# the FMU state's entry points (fmu/state_entry_points.py), in both models
STATE_ENTRY_POINTS = {
    "wearjoint_state_size": ("state_size_native", 2),
    "wearjoint_write_state": ("write_state_native", 8),
    "wearjoint_check_header": ("check_header_native", 6),
    "wearjoint_read_state": ("read_state_native", 7),
    "wearjoint_check_values": ("check_values_native", 8),
}
ENTRY_POINTS = {
    "joint": ("wearjoint.fmu.joint_entry_points", {
        "wearjoint_evaluate": ("evaluate_native", 11),
        "wearjoint_jacobian": ("jacobian_native", 11),
        "wearjoint_advance": ("advance_native", 14),
        "wearjoint_accept": ("accept_native", 15),
        "wearjoint_update_contact_memory": ("update_contact_memory_native", 3),
        "wearjoint_bushing_points": ("bushing_points_native", 4),
        "wearjoint_block_minima": ("block_minima_native", 4),
        "wearjoint_worn_volume": ("worn_volume_native", 3),
        "wearjoint_wall_overlap": ("wall_overlap_native", 5),
        "wearjoint_complete_parameters": ("complete_parameters_native", 1),
        **STATE_ENTRY_POINTS,
    }),
    "slider-crank": ("wearjoint.fmu.slider_crank_entry_points", {
        "slider_crank_parameters": ("parameters_native", 3),
        "slider_crank_initial_state": ("initial_state_native", 10),
        "slider_crank_derivative": ("derivative_native", 12),
        "slider_crank_step": ("step_native", 18),
        "slider_crank_joint_kinematics": ("joint_kinematics_native", 3),
        **STATE_ENTRY_POINTS,
    }),
    # not an FMU: the co-simulation master's loop (wearjoint.cosim.native_master)
    "master": ("wearjoint.cosim.master_entry_points", {
        "wearjoint_master_loop": ("master_loop_native", 33), "wearjoint_start_point": ("start_point_native", 2),
        "wearjoint_mechanism_parameters": ("parameters_native", 3),
        "wearjoint_initial_state": ("initial_state_native", 10),
        "wearjoint_ideal_joint_forces": ("ideal_joint_forces_native", 15),
        "wearjoint_bushing_points": ("bushing_points_native", 4),
        "wearjoint_effective_modulus": ("effective_modulus_native", 4),
        "wearjoint_materials_contact_stiffness": ("materials_contact_stiffness_native", 3)}),
}
# model -> the entry points of the second of two AOT processes, in order (the first takes the rest).  The
# first starts with the contact's evaluation, which the second's last entry point calls again: by then it
# is in the numba cache the two share, and the second loads it instead of compiling it a second time.
PARTS = {
    "joint": ("wearjoint_accept", "wearjoint_update_contact_memory", "wearjoint_state_size", "wearjoint_write_state",
              "wearjoint_check_header", "wearjoint_read_state", "wearjoint_check_values", "wearjoint_bushing_points",
              "wearjoint_block_minima", "wearjoint_worn_volume", "wearjoint_complete_parameters", "wearjoint_advance"),
    "slider-crank": ("wearjoint_state_size", "wearjoint_write_state", "wearjoint_check_header", "wearjoint_read_state",
                     "wearjoint_check_values"),
    "master": ("wearjoint_ideal_joint_forces", "wearjoint_initial_state", "wearjoint_mechanism_parameters",
               "wearjoint_bushing_points", "wearjoint_effective_modulus", "wearjoint_materials_contact_stiffness"),
}

# what a kernel object may need from outside: libm (and memset/memcpy from libc)
ALLOWED_UNDEFINED = frozenset({"sqrt", "cos", "sin", "sincos", "atan2", "asin", "pow", "ceil", "floor", "rint", "round",
                               "fabs", "exp", "log", "fmin", "fmax", "memset", "memcpy", "memmove"})


class EntryPoint:
    """A native FMU's C entry point: a function of kernels and its C signature (numba types), compiled
    into a numba ``cfunc`` only by :meth:`compile` (a ``cfunc`` compiles where it is defined: each AOT
    process compiles its own entry points, nothing else does)."""

    def __init__(self, function, signature):
        self.function = function
        self.signature = signature

    def compile(self):
        """The ``cfunc`` (not cached: a cached ``cfunc`` has no IR; the kernels it calls may be)."""
        from numba import cfunc

        return cfunc(self.signature, error_model="numpy")(self.function)


def entry_point(signature):
    """Decorator: the function as an :class:`EntryPoint` of C signature ``signature``."""
    return lambda function: EntryPoint(function, signature)


def _drop_function(ir: str, name: str) -> str:
    """``ir`` without the definition of function ``name``."""
    lines = ir.splitlines()
    out, skipping = [], False
    for line in lines:
        if not skipping and line.startswith("define") and (f'@"{name}"(' in line or f"@{name}(" in line):
            skipping = True
        if not skipping:
            out.append(line)
        elif line == "}":
            skipping = False
    return "\n".join(out) + "\n"


def _export_ir(cfunc, symbol: str) -> str:
    """The IR of ``cfunc``'s library with its wrapper dropped and the compiled function renamed to ``symbol``."""
    wrapper = cfunc.native_name
    inner = wrapper[len("cfunc."):]
    ir = _drop_function(cfunc._library.get_llvm_str(), wrapper)
    return re.sub(r'@"?' + re.escape(inner) + r'"?(?=[(\s,)])', "@" + symbol, ir)


def _undefined_symbols(module) -> set[str]:
    names = {f.name for f in module.functions if f.is_declaration and not f.name.startswith("llvm.")}
    names |= {g.name for g in module.global_variables if g.is_declaration}
    return names


@functools.lru_cache(maxsize=None)   # one per platform per process (every object of a build reuses it)
def _target_machine(triple: str, cpu: str):
    import llvmlite.binding as llvm

    llvm.initialize_all_targets()
    llvm.initialize_all_asmprinters()
    return llvm.Target.from_triple(triple).create_target_machine(cpu=cpu, features="", opt=3, reloc="pic",
                                                                   codemodel="default")


def compile_ir(model: str, out_dir: Path, only=None) -> dict:
    """Every entry point of ``model`` (or those named in ``only``, in that order), its IR internalised
    and stripped to what it needs, into ``out_dir``; returns {symbol: IR file name}."""
    import llvmlite.binding as llvm

    module_name, symbols = ENTRY_POINTS[model]
    if only is not None:
        symbols = {symbol: symbols[symbol] for symbol in only}
    entry_points = importlib.import_module(module_name)

    triple = llvm.get_process_triple()   # numba wrote the IR for this machine (generic CPU)
    machine = _target_machine(triple, "x86-64" if triple.startswith("x86_64") else "generic")
    out_dir.mkdir(parents=True, exist_ok=True)
    modules = {}
    for symbol, (name, n_arguments) in symbols.items():
        cfunc = getattr(entry_points, name).compile()
        if len(cfunc._sig.args) != n_arguments:
            raise RuntimeError(f"AOT: {name} takes {len(cfunc._sig.args)} arguments, the C prototype of {symbol} "
                               f"{n_arguments}: update both together")
        module = llvm.parse_assembly(_export_ir(cfunc, symbol))
        module.triple = triple
        module.data_layout = str(machine.target_data)
        for function in module.functions:
            if not function.is_declaration and function.name != symbol:
                function.linkage = "internal"
        for variable in module.global_variables:
            if not variable.is_declaration:
                variable.linkage = "internal"
        passes = llvm.create_new_module_pass_manager()
        passes.add_global_dead_code_eliminate_pass()
        passes.add_strip_dead_prototype_pass()
        passes.run(module, llvm.create_pass_builder(machine, llvm.create_pipeline_tuning_options()))
        module.verify()
        if module.get_function(symbol).is_declaration:
            raise RuntimeError(f"AOT: {name} compiled to no definition of {symbol}")
        leftover = _undefined_symbols(module) - ALLOWED_UNDEFINED
        if leftover:
            raise RuntimeError(f"AOT: {name} still needs {', '.join(sorted(leftover))} (a raise, allocation or "
                               "Python path survived in the kernels; the native FMU must need libc/libm only)")
        (out_dir / f"{symbol}.ll").write_text(str(module))
        modules[symbol] = f"{symbol}.ll"
    return modules


def emit_object(ir_path: Path, triple: str, cpu: str) -> bytes:
    """The object code of the IR in ``ir_path`` for ``triple`` and ``cpu``: the IR with only its
    target triple and data layout replaced."""
    import llvmlite.binding as llvm

    machine = _target_machine(triple, cpu)
    module = llvm.parse_assembly(Path(ir_path).read_text())
    module.triple = triple
    module.data_layout = str(machine.target_data)
    module.verify()
    return machine.emit_object(module)


if __name__ == "__main__":
    from .._compile.notice import watching   # each compilation's count on stdout: the builder's progress bar

    with watching("fmu", on_compile=lambda count: print(count, flush=True), quiet=True):
        compile_ir(sys.argv[1], Path(sys.argv[2]), sys.argv[3].split(",") if len(sys.argv) > 3 else None)
