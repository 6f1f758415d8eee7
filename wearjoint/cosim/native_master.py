"""The co-simulation master's loop compiled ahead of time: a shared library in the user cache.

:func:`native_master` gives :func:`wearjoint.cosim.master_entry_points.master_loop_native` and
``start_point_native`` as Python functions: the IR of the same numba kernels the in-process master runs (the package ships it, as it ships the
native FMUs' kernels: :mod:`wearjoint.fmu.kernel_ir`), turned into an object for this machine's architecture and
linked with its C compiler once per kernel version (``<user cache>/master/``).  A co-simulation then compiles no
numba code for its loop; where no library can be had (no C compiler, a platform without one) it returns None and
the master runs numba's (:func:`wearjoint.cosim.master_loop.master_loop`): the same results bit for bit.
"""
from __future__ import annotations

import ctypes
import os
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

from .._compile.user_cache import user_cache_dir

_LIBRARY = "wearjoint_master"


@dataclass(frozen=True)
class MasterKernels:
    """What :mod:`wearjoint.fmu.kernel_ir` needs to know of the master's kernels (as of a native FMU model's)."""

    name: str = "master"
    ir_modules: tuple = ("cosim/master_loop.py", "cosim/master_layout.py", "cosim/master_entry_points.py",
                         "fmu/__init__.py", "fmu/fmi.py", "fmu/loop_calls.py", "fmu/instance.py", "fmu/extracted.py",
                         "fmu/variables.py", "fmu/joint_entry_points.py", "fmu/slider_crank_entry_points.py",
                         "fmu/state_entry_points.py")
    kernel_header: str | None = None     # ctypes calls it: no C prototype to keep in step
    folder: str | None = None


MASTER = MasterKernels()
# master_loop_native's C arguments (cosim.master_entry_points.SIGNATURE): addresses as integers (AOT: 33)
_ARGUMENTS = (ctypes.c_double, *(ctypes.c_void_p,) * 3, ctypes.c_ssize_t, ctypes.c_void_p, ctypes.c_ssize_t,
              *(ctypes.c_void_p,) * 3, ctypes.c_ssize_t,
              *(ctypes.c_void_p,) * 7, *(ctypes.c_void_p,) * 10, ctypes.c_void_p, ctypes.c_ssize_t, ctypes.c_void_p,
              ctypes.c_void_p, ctypes.c_void_p)


def library_path() -> Path:
    """Where the library of these kernels lives (it may not exist yet)."""
    from ..fmu import platforms
    from ..fmu.kernel_ir import kernel_key

    target = platforms.host_platform()
    return user_cache_dir() / "master" / f"{kernel_key(MASTER)}-{target.name}" / f"{_LIBRARY}{target.extension}"


def build_library(path: Path) -> Path:
    """Compile the master's kernel IR (the package's, else numba's in a fresh process) for this machine and link
    it into ``path``; RuntimeError where that cannot be done here."""
    from ..fmu import platforms
    from ..fmu.kernel_ir import compile_kernel_ir, kernel_objects

    target = platforms.host_platform()
    reason = platforms.missing_reason(target)
    if reason is not None:
        raise RuntimeError(reason)
    path.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="wearjoint_master_") as tmp:
        modules = compile_kernel_ir(Path(tmp) / "ir", MASTER)
        objects = [str(Path(tmp) / path) for path in kernel_objects(Path(tmp) / "ir", modules, target)]
        partial = Path(tmp) / path.name
        flags = [flag for flag in target.link_flags if "version-script" not in flag]
        result = subprocess.run([platforms.compiler(target), *flags, "-o", str(partial), *objects, "-lm"],
                                capture_output=True, text=True)
        if result.returncode != 0:
            raise RuntimeError(f"linking the master's library failed: {result.stderr.strip()[-2000:]}")
        os.replace(partial, path)     # whole or not at all: another process may load it at once
    return path


def _c_function(library, symbol: str, arguments, result_type=ctypes.c_int32):
    """``symbol`` of ``library``, compiled by numba with ``arguments``, as a Python function of them returning its
    result (numba's calling convention: a status, the value of ``result_type`` through a pointer; the kernels have
    no path that raises).  The value's place is the call's own: ctypes releases the GIL, so threads may call at
    once."""
    function = getattr(library, symbol)
    function.argtypes = (ctypes.c_void_p, ctypes.c_void_p, *arguments)
    function.restype = ctypes.c_int32

    def call(*values):
        result, exception = result_type(), ctypes.c_void_p()
        if function(ctypes.byref(result), ctypes.byref(exception), *values) != 0:
            raise RuntimeError(f"the master's compiled {symbol} failed")
        return result.value

    return call


_POINTER, _SIZE, _DOUBLE = ctypes.c_void_p, ctypes.c_ssize_t, ctypes.c_double


def _addresses(arrays):
    return tuple(a.ctypes.data for a in arrays)


class NativeMaster:
    """The library at ``path``: :func:`~wearjoint.cosim.master_loop.master_loop` and
    :func:`~wearjoint.cosim.master_loop.start_point`, their arguments the same (C-contiguous float64 arrays), and
    the kernels a run calls once (:mod:`wearjoint.kernel_calls`)."""

    def __init__(self, path: Path):
        library = ctypes.CDLL(str(path))
        self._loop = _c_function(library, "wearjoint_master_loop", _ARGUMENTS, ctypes.c_ssize_t)
        self._start_point = _c_function(library, "wearjoint_start_point", (_POINTER, _SIZE))
        self._parameters = _c_function(library, "wearjoint_mechanism_parameters", (_POINTER,) * 3)
        self._initial_state = _c_function(library, "wearjoint_initial_state", (_DOUBLE, *(_POINTER,) * 9))
        self._ideal_joint_forces = _c_function(library, "wearjoint_ideal_joint_forces",
                                               (_POINTER, _SIZE, *(_POINTER,) * 13))
        self._bushing_points = _c_function(library, "wearjoint_bushing_points", (*(_POINTER,) * 3, _SIZE))
        self.effective_modulus = _c_function(library, "wearjoint_effective_modulus", (_DOUBLE,) * 4, ctypes.c_double)
        self.materials_contact_stiffness = _c_function(library, "wearjoint_materials_contact_stiffness",
                                                       (_DOUBLE,) * 3, ctypes.c_double)

    def master_loop(self, t_end, register, settings, buf, stats, stages, saved, samples, ws, fmi, published, clock,
                    timespec):
        component, input_vrs, output_vrs, state_slot, *functions = fmi
        derivative_vrs, derivatives = published
        return self._loop(t_end, register.ctypes.data, settings.ctypes.data, buf.ctypes.data, buf.shape[0],
                          stats.ctypes.data, stats.shape[0], stages.ctypes.data, saved.ctypes.data,
                          samples.ctypes.data, samples.shape[0], *_addresses(ws), component,
                          input_vrs.ctypes.data, output_vrs.ctypes.data, state_slot.ctypes.data, *functions,
                          derivative_vrs.ctypes.data, derivative_vrs.shape[0], derivatives.ctypes.data, clock,
                          timespec.ctypes.data)

    def start_point(self, buf):
        self._start_point(buf.ctypes.data, buf.shape[0])

    def mechanism_parameters(self, fields, mp, inverse_mass):
        """The kernels' parameter vector from the mechanism's fields and M^-1 (the SliderCrank FMU's)."""
        return self._parameters(*_addresses((fields, mp, inverse_mass)))

    def initial_state(self, t, mp, ws, y):
        self._initial_state(t, mp.ctypes.data, *_addresses(ws), y.ctypes.data)

    def ideal_joint_forces(self, times, mp, ws, result, y, qdd, body_forces, out):
        self._ideal_joint_forces(times.ctypes.data, times.shape[0], mp.ctypes.data, *_addresses(ws),
                                 *_addresses((result, y, qdd, body_forces, out)))

    def bushing_points(self, phi, cos_phi, sin_phi):
        self._bushing_points(*_addresses((phi, cos_phi, sin_phi)), phi.shape[0])


_loaded: NativeMaster | None = None    # the library this process loaded
_failed = False                        # it could not be built or loaded here: numba's kernels from then on
# library_path() of this process, computed once: it hashes the kernels' sources (~5 ms), and a run where the library
# is not built asks for it several times a chunk (kernel_calls, through the divergence check's stiffness): computed
# each time, that halved the real-time factor of `simulate` without wear
_path: Path | None = None


def native_master(build: bool = True) -> NativeMaster | None:
    """The master's library, loaded once per process (built first if missing and ``build``); None where it cannot be
    built or loaded here, or is missing and ``build`` is false: the caller runs numba's kernels."""
    global _loaded, _failed, _path
    if _loaded is None and not _failed:
        try:
            if _path is None:
                _path = library_path()
            if not _path.is_file():
                if not build:
                    return None
                build_library(_path)
            _loaded = NativeMaster(_path)
        except (OSError, RuntimeError, subprocess.SubprocessError, AttributeError, ImportError):
            _failed = True
    return _loaded
