"""The machines the native FMU carries binaries for, and how each is built.

One ahead-of-time compilation of the kernels gives their LLVM IR (:mod:`wearjoint.fmu.aot`);
each platform gets objects from that same IR with only its target triple and data layout
replaced, and a C compiler for that platform links them with the FMI layer (``fmu_src/``).
No equation is compiled from anything but that IR.

Platform names are the FMI 2.0 folder names (``linux64``, ``win64``); for machines FMI 2.0
names no folder for, FMI 2.0.4 section 2.3 says to use the FMI 3.0 platform tuple
(``aarch64-linux``, ``aarch64-darwin``).  FMI 3.0 FMUs use the tuples throughout
(``x86_64-linux``, ``x86_64-windows``, ``aarch64-linux``, ...); those are accepted as names too.

From a Linux x86-64 machine the FMU is built for linux64 and cross-built for win64 (MinGW-w64)
and aarch64-linux (the GNU aarch64 cross compiler); ``.ci/install-cross-toolchains`` installs
both and the emulators the tests run them under (wine, qemu-user).  On any other machine the
build makes the binary of that machine (its triple from LLVM, its C compiler ``$CC``).
"""
from __future__ import annotations

import os
import platform as _platform
import shutil
import sys
from dataclasses import dataclass

from ..parameters import ParameterError
from . import variables as fv

# C flags of every build: ISO C11 (no GNU floating-point contraction: a fused multiply-add would
# change the numbers), warnings as errors; link-time optimisation inlines the FMI glue across its files
# (fmi2SetReal -> model_set_float64 -> joint_set_input; measured in CHANGELOG.md)
COMMON_C_FLAGS = ("-O2", "-flto", "-std=c11", "-ffp-contract=off", "-Wall", "-Wextra", "-Wno-unused-parameter", "-Werror")
ELF_LINK_FLAGS = ("-shared", "-fPIC", "-Wl,-z,defs", "-Wl,--version-script=exports.map")
# MinGW: C99 printf (%zu) from libmingwex instead of msvcrt's; the FMI headers export the fmi2*/fmi3*
# functions (__declspec(dllexport)), so nothing else is exported
MINGW_FLAGS = ("-static-libgcc", "-D__USE_MINGW_ANSI_STDIO=1")   # also the test hosts' (tests/fmi_host.py)
WINDOWS_LINK_FLAGS = ("-shared", *MINGW_FLAGS, "-Wl,--no-undefined")


@dataclass(frozen=True)
class Platform:
    """One machine an FMU binary is built for."""
    name: str                 # FMI 2.0 folder (or FMI 3.0 tuple where FMI 2.0 names none)
    fmi3_folder: str          # FMI 3.0 platform tuple
    triple: str               # LLVM target triple of the kernel objects
    cpu: str                  # LLVM CPU of the kernel objects (the baseline of the architecture)
    cross_compiler: str       # the C compiler that builds for it from another machine
    apt_packages: tuple       # Debian packages that provide cross_compiler
    extension: str            # of the shared library
    link_flags: tuple
    emulator: tuple = ()      # how a Linux x86-64 machine runs its programs (tests), () = natively

    def folder(self, fmi_version: int) -> str:
        """binaries/<folder> of this platform in an FMU of ``fmi_version``."""
        return self.name if fmi_version == 2 else self.fmi3_folder

    def binary_arcname(self, fmi_version: int, model_name: str = fv.MODEL_NAME) -> str:
        return f"binaries/{self.folder(fmi_version)}/{model_name}{self.extension}"

    def exports_flag(self, fmi_version: int) -> tuple:
        """Linker flags that export the FMI functions only."""
        if self.extension == ".dylib":
            return (f"-Wl,-exported_symbol,_fmi{fmi_version}*",)
        return ()


PLATFORMS = {p.name: p for p in (
    Platform("linux64", "x86_64-linux", "x86_64-unknown-linux-gnu", "x86-64", "x86_64-linux-gnu-gcc",
             ("gcc-x86-64-linux-gnu",), ".so", ELF_LINK_FLAGS),
    Platform("win64", "x86_64-windows", "x86_64-w64-windows-gnu", "x86-64", "x86_64-w64-mingw32-gcc",
             ("gcc-mingw-w64-x86-64",), ".dll", WINDOWS_LINK_FLAGS, ("wine",)),
    Platform("aarch64-linux", "aarch64-linux", "aarch64-unknown-linux-gnu", "generic", "aarch64-linux-gnu-gcc",
             ("gcc-aarch64-linux-gnu", "libc6-dev-arm64-cross"), ".so", ELF_LINK_FLAGS,
             ("qemu-aarch64", "-L", "/usr/aarch64-linux-gnu")),
    # built only on a Mac, for that Mac (not tested here: no macOS machine)
    Platform("darwin64", "x86_64-darwin", "x86_64-apple-macosx10.15.0", "x86-64", "", (), ".dylib",
             ("-dynamiclib", "-fPIC")),
    Platform("aarch64-darwin", "aarch64-darwin", "arm64-apple-macosx11.0.0", "generic", "", (), ".dylib",
             ("-dynamiclib", "-fPIC")),
)}
CROSS_PLATFORMS = ("linux64", "win64", "aarch64-linux")   # what a Linux x86-64 machine can build
_ALIASES = {p.fmi3_folder: p.name for p in PLATFORMS.values()}


def host_platform() -> Platform:
    """The platform of this machine; RuntimeError on one the FMU is not built for."""
    machine = _platform.machine().lower()
    arm = machine in ("aarch64", "arm64")
    if machine not in ("x86_64", "amd64") and not arm:
        raise RuntimeError(f"the native FMU is built for x86-64 and aarch64 machines; this one is {machine}")
    if sys.platform.startswith("linux"):
        return PLATFORMS["aarch64-linux" if arm else "linux64"]
    if sys.platform == "darwin":
        return PLATFORMS["aarch64-darwin" if arm else "darwin64"]
    if sys.platform == "win32" and not arm:
        return PLATFORMS["win64"]
    raise RuntimeError(f"the native FMU is not built on {sys.platform} {machine}")


def compiler(target: Platform) -> str | None:
    """The C compiler for ``target`` found on this machine, or None: the host's is ``$CC``
    (default cc on a Mac, gcc elsewhere), another's its cross compiler."""
    if target == host_platform():
        name = os.environ.get("CC") or ("cc" if sys.platform == "darwin" else "gcc")
    else:
        name = target.cross_compiler
    return shutil.which(name) if name else None


def missing_reason(target: Platform) -> str | None:
    """Why ``target`` cannot be built here (one line naming what to install), or None."""
    host = host_platform()
    if target != host and not target.cross_compiler:
        return f"{target.name} is built only on a machine of that platform (this one is {host.name})"
    if compiler(target) is None:
        if target == host:
            name = os.environ.get("CC") or "gcc"
            return f"{target.name} needs a C compiler: {name!r} not found (install gcc or set CC)"
        return (f"{target.name} needs the cross compiler {target.cross_compiler} "
                f"(apt-get install {' '.join(target.apt_packages)}; or run .ci/install-cross-toolchains)")
    return None


def parse_platforms(text) -> tuple[str, ...] | None:
    """``--platforms`` as canonical names: None for ``auto``/None, else the comma-separated names
    (FMI 2.0 names or FMI 3.0 tuples); ParameterError naming the bad one."""
    if text is None or (isinstance(text, str) and text.strip() == "auto"):
        return None
    names = [n.strip() for n in text.split(",")] if isinstance(text, str) else [str(n) for n in text]
    chosen = []
    for name in names:
        canonical = _ALIASES.get(name, name)
        if canonical not in PLATFORMS:
            raise ParameterError(f"parameter platforms={text!r} is invalid ({name!r} is no platform): allowed auto "
                                 "or a comma-separated list "
                                 f"of {', '.join(PLATFORMS)} (or the FMI 3.0 names "
                                 f"{', '.join(p.fmi3_folder for p in PLATFORMS.values())})")
        if canonical not in chosen:
            chosen.append(canonical)
    return tuple(chosen)


def select(requested=None) -> tuple[list[Platform], dict[str, str]]:
    """The platforms to build and the ones skipped with their reason.

    ``requested`` None: this machine's platform plus every cross platform whose compiler is
    installed (the others skipped, with what to install).  A list: exactly those; a platform that
    cannot be built here raises RuntimeError naming what to install.
    """
    names = parse_platforms(requested)
    host = host_platform()
    if names is None:
        candidates = [host.name, *(n for n in CROSS_PLATFORMS if n != host.name)]
        chosen, skipped = [], {}
        for name in candidates:
            reason = missing_reason(PLATFORMS[name])
            if reason is None:
                chosen.append(PLATFORMS[name])
            elif name == host.name:
                raise RuntimeError(f"the native FMU: {reason}")
            else:
                skipped[name] = reason
        return chosen, skipped
    for name in names:
        reason = missing_reason(PLATFORMS[name])
        if reason is not None:
            raise RuntimeError(f"cannot build platform {name}: {reason}")
    return [PLATFORMS[n] for n in names], {}
