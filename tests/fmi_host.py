"""Helpers to build and run the C FMI hosts ``tests/c_host/fmi2_host.c`` (FMI 2.0) and
``tests/c_host/fmi3_host.c`` (FMI 3.0), both on ``host_common.c`` and the rest of the script machinery
they share (:data:`COMMON_SOURCES`; see the README there): the proof
that an FMU works from C with no Python on the host.  The hosts are portable C (dlopen or
LoadLibrary): built for linux64 here, or cross-built for win64 (run under wine) and aarch64-linux
(run under qemu-aarch64), they load the FMU binary of their own platform."""
from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path
from typing import Sequence, Union

import pytest

C_HOST_DIR = Path(__file__).resolve().parent / "c_host"
HOST_SOURCES = tuple(C_HOST_DIR / name for name in ("fmi2_host.c", "fmi2_host_commands.c"))
FMI3_HOST_SOURCES = (C_HOST_DIR / "fmi3_host.c",)
# the script machinery both hosts share
COMMON_SOURCES = tuple(C_HOST_DIR / name for name in ("host_common.c", "host_os.c", "host_parse.c", "host_commands.c",
                                                      "host_trace.c"))

CLEAN_ENV = {"PATH": "/usr/bin:/bin"}
VALGRIND_ARGS = ("valgrind", "--leak-check=full", "--error-exitcode=3")

Script = Union[str, Sequence[str], os.PathLike]


def fmi2_headers_dir() -> Path | None:
    """The FMI 2.0 headers shipped with fmpy (``<site-packages>/fmpy/c-code``), or None."""
    import importlib.util

    spec = importlib.util.find_spec("fmpy")
    if spec is None or spec.origin is None:
        return None
    d = Path(spec.origin).parent / "c-code"
    return d if (d / "fmi2FunctionTypes.h").is_file() else None


def fmi3_headers_dir() -> Path | None:
    """The FMI 3.0 headers shipped with fmpy (the same ``c-code`` folder), or None."""
    d = fmi2_headers_dir()
    return d if d is not None and (d / "fmi3FunctionTypes.h").is_file() else None


def gcc_or_skip(fmi_version: int = 2) -> str:
    gcc = shutil.which("gcc")
    if gcc is None:
        pytest.skip("gcc is not installed")
    if (fmi2_headers_dir() if fmi_version == 2 else fmi3_headers_dir()) is None:
        pytest.skip(f"the FMI {fmi_version}.0 headers (fmpy/c-code) are not available")
    return gcc


# how each platform's host is compiled on this (Linux x86-64) machine, and run
def _host_compilers() -> dict:
    from wearjoint.fmu.platforms import MINGW_FLAGS, PLATFORMS

    return {"linux64": ("gcc", ()), "win64": (PLATFORMS["win64"].cross_compiler, MINGW_FLAGS),
            "aarch64-linux": (PLATFORMS["aarch64-linux"].cross_compiler, ())}


HOST_COMPILERS = _host_compilers()


def wine_environment() -> dict:
    """wine's environment: a prefix kept in the user cache (made once, ~10 s), no debug output, no
    Mono/Gecko installer dialogs."""
    from wearjoint._compile.cache import user_cache_dir

    user_cache_dir().mkdir(parents=True, exist_ok=True)   # wine makes the prefix, not its parent
    return {**CLEAN_ENV, "HOME": str(Path.home()), "WINEPREFIX": str(user_cache_dir() / "wine"), "WINEDEBUG": "-all",
            "WINEDLLOVERRIDES": "mscoree,mshtml="}


def platform_runner(platform: str) -> tuple[list[str], dict]:
    """The command prefix and environment that run ``platform``'s programs here."""
    from wearjoint.fmu.platforms import PLATFORMS

    if platform == "win64":
        return ["wine"], wine_environment()
    return list(PLATFORMS[platform].emulator), dict(CLEAN_ENV)


def missing_platform_tool(platform: str) -> str | None:
    """What is missing to build and run ``platform``'s programs here (its compiler, its emulator), or None."""
    from wearjoint.fmu.platforms import PLATFORMS

    for tool in (HOST_COMPILERS[platform][0], *PLATFORMS[platform].emulator[:1]):
        if shutil.which(tool) is None:
            return f"{platform}: {tool} is not installed (run .ci/install-cross-toolchains)"
    return None


def platform_or_skip(platform: str) -> None:
    """Skip unless ``platform``'s cross compiler and emulator are installed."""
    missing = missing_platform_tool(platform)
    if missing:
        pytest.skip(missing)


def _build_host(sources: Sequence[Path], headers: Path | None, out_dir: Path, extra_flags: Sequence[str],
                platform: str = "linux64") -> Path:
    """Compile a host from its own ``sources`` (the first names the program) and :data:`COMMON_SOURCES`."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    compiler, platform_flags = HOST_COMPILERS[platform]
    exe = out_dir / (sources[0].stem + (".exe" if platform == "win64" else ""))
    cmd = [compiler, "-O2", "-g", "-Wall", "-Wextra", *platform_flags, *extra_flags, f"-I{headers}",
           *map(str, (*sources, *COMMON_SOURCES)), "-o", str(exe), *(() if platform == "win64" else ("-ldl",))]
    proc = subprocess.run(cmd, capture_output=True, text=True, env=CLEAN_ENV)
    if proc.returncode != 0:
        raise RuntimeError(f"building the C host failed:\n{' '.join(cmd)}\n{proc.stderr}")
    return exe


def build_c_host(out_dir: Path, extra_flags: Sequence[str] = (), platform: str = "linux64") -> Path:
    """Compile the FMI 2.0 host into ``out_dir/fmi2_host`` and return its path.

    ``gcc -O2 -g -Wall -Wextra -I<fmi2 headers> <HOST_SOURCES> <COMMON_SOURCES> -o fmi2_host -ldl``
    (one process, one core); for ``platform`` win64 or aarch64-linux with its cross compiler
    (:data:`HOST_COMPILERS`).  Raises ``RuntimeError`` with the compiler's output if it fails.
    """
    return _build_host(HOST_SOURCES, fmi2_headers_dir(), out_dir, extra_flags, platform)


def build_fmi3_host(out_dir: Path, extra_flags: Sequence[str] = (), platform: str = "linux64") -> Path:
    """Compile the FMI 3.0 host into ``out_dir/fmi3_host`` and return its path (as
    :func:`build_c_host`, with ``fmi3_host.c``).  Run it with :func:`run_c_host`, the
    instantiationToken in place of the GUID."""
    return _build_host(FMI3_HOST_SOURCES, fmi3_headers_dir(), out_dir, extra_flags, platform)


def run_c_host(host: Path, fmu_dir: Path, model_identifier: str, guid: str, script: Script, *,
               host_args: Sequence[str] = (), valgrind: bool = False, platform: str = "linux64",
               timeout: float = 600.0) -> tuple[int, str, str]:
    """Run a C host (either) on an unzipped FMU with a clean environment; return (returncode, stdout, stderr).

    ``script`` is the script text (``str``), a sequence of lines, or a path (``os.PathLike``) to an
    existing script file.  Text is written to a temporary file that is removed afterwards.
    The environment is only ``PATH=/usr/bin:/bin``: no PYTHONPATH, LD_LIBRARY_PATH or LD_PRELOAD.
    ``valgrind=True`` runs under ``valgrind --leak-check=full --error-exitcode=3`` (valgrind's
    report is at the end of stderr).  ``host_args`` go before the positional arguments
    (e.g. ``["--no-unload"]``).  ``platform`` win64 runs the host under wine, aarch64-linux under
    qemu-aarch64 (:func:`platform_runner`).
    """
    tmp_name = None
    if isinstance(script, os.PathLike):
        script_path = os.fspath(script)
    else:
        text = script if isinstance(script, str) else "\n".join(script)
        fd, tmp_name = tempfile.mkstemp(prefix="fmi2_host_", suffix=".txt")
        with os.fdopen(fd, "w") as f:
            f.write(text if text.endswith("\n") else text + "\n")
        script_path = tmp_name
    runner, env = platform_runner(platform)
    cmd = [*(VALGRIND_ARGS if valgrind else ()), *runner, str(host), *host_args, str(fmu_dir),
           model_identifier, guid, script_path]
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=timeout)
    finally:
        if tmp_name is not None:
            os.unlink(tmp_name)
    return proc.returncode, proc.stdout, proc.stderr


def needed_libraries(path: Path) -> set[str]:
    """DT_NEEDED entries of an ELF file (``readelf -d``); skips the test if readelf is missing."""
    if shutil.which("readelf") is None:
        pytest.skip("readelf is not installed")
    out = subprocess.run(["readelf", "-d", str(path)], capture_output=True, text=True,
                         env=CLEAN_ENV, check=True).stdout
    return set(re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", out))


def stderr_value(stderr: str, key: str) -> float:
    """The number after ``key`` on its (last) line of stderr, e.g. ``trace_seconds``."""
    values = re.findall(rf"^{re.escape(key)} (\S+)$", stderr, flags=re.M)
    assert values, f"{key} not in stderr:\n{stderr[-2000:]}"
    return float(values[-1])


def trace_rows(stdout: str) -> list[list[str]]:
    """The ``out <t> v1 v2 ...`` lines of a trace, as lists of strings (t first)."""
    return [line.split()[1:] for line in stdout.splitlines() if line.startswith("out ")]


def value_lines(stdout: str) -> list[str]:
    """Every ``real/integer/boolean/string <vr> <value>`` line, in order."""
    return [line for line in stdout.splitlines()
            if line.split(" ", 1)[0] in ("real", "integer", "boolean", "string")]


def write_trace_file(path: Path, rows: Sequence[Sequence[float]]) -> Path:
    """Rows ``t h u1 .. un`` written with repr() so the host reads back the same doubles."""
    path.write_text("# t h u...\n" + "".join(" ".join(repr(float(v)) for v in row) + "\n"
                                             for row in rows))
    return path


def assert_valgrind_clean(stderr: str) -> None:
    """valgrind's report (end of stderr) shows no error and no definite leak."""
    assert "ERROR SUMMARY: 0 errors" in stderr, stderr[-3000:]
    assert ("definitely lost: 0 bytes" in stderr or "no leaks are possible" in stderr), stderr[-3000:]


def valgrind_or_skip() -> None:
    if shutil.which("valgrind", path=CLEAN_ENV["PATH"]) is None:
        pytest.skip("valgrind is not installed")


def event_lines(stdout: str) -> list[tuple[float, str]]:
    """The ``event <t> <kind>`` lines of a ``trace_me``, as (t, kind)."""
    return [(float(line.split()[1]), line.split()[2]) for line in stdout.splitlines() if line.startswith("event ")]


# ------------------------------------------------------------------ scripts for the joint FMU
def start_script(fmi_version: int, vr: dict, params, interface: str = "instantiate", n_points: int | None = None,
                 name: str = "joint") -> str:
    """Instantiate (``instantiate`` or ``instantiate_me``) and initialise with ``params``' FMU
    parameters; FMI 3.0: ``n_points`` set in Configuration Mode first.  A Model Exchange instance is
    left in Continuous-Time Mode."""
    from wearjoint.fmu import variables as fv

    reals, integers = fv.fmi_parameter_values_by_type(params)
    real_set, integer_set = ("set_real", "set_integer") if fmi_version == 2 else ("set_float64", "set_int64")
    config = (f"enter_config\nset_uint64 {vr['n_points']}={n_points}\nexit_config\n"
              if fmi_version == 3 and n_points else "")
    script = (f"{interface} {name}\n{config}{'setup 0' + chr(10) if fmi_version == 2 else ''}enter_init\n"
              f"{real_set} {' '.join(f'{vr[k]}={v!r}' for k, v in reals.items())}\n"
              f"{integer_set} {' '.join(f'{vr[k]}={v}' for k, v in integers.items())}\nexit_init\n")
    if interface == "instantiate_me":
        script += ("new_discrete_states" if fmi_version == 2 else "update_discrete_states") + \
            "\nenter_continuous_time_mode\n"
    return script


def trace_command(vr: dict, path, me: bool = False, order: str = "", also_read: tuple = ()) -> str:
    """``trace`` (``trace_me``) of the rows in ``path`` through the 12 inputs, reading every scalar output, then the
    outputs named in ``also_read`` (their columns follow the scalar outputs')."""
    from wearjoint.fmu import variables as fv

    outputs = [vr[v.name] for v in fv.SCALAR_OUTPUTS] + [vr[name] for name in also_read]
    return (f"{'trace_me' if me else 'trace'} {path} 12 {','.join(str(vr[v.name]) for v in fv.INPUTS)} "
            f"{','.join(map(str, outputs))} {order}\n")


def profile_command(fmi_version: int, vr: dict, n_points: int) -> str:
    """The command that prints the worn profile (FMI 2.0: n_points scalars; FMI 3.0: one array)."""
    from wearjoint.fmu import variables as fv

    if fmi_version == 2:
        return "get_real " + " ".join(str(vr[fv.wear_depth_name(z)]) for z in range(1, n_points + 1)) + "\n"
    return f"get_float64 {vr['wear_depth']}:{n_points}\n"


def profile_values(stdout: str, fmi_version: int, vr: dict, n_points: int):
    """The last worn profile :func:`profile_command` printed."""
    import numpy as np

    if fmi_version == 2:
        return np.array([float(line.split()[2]) for line in value_lines(stdout)[-n_points:]])
    line = [line for line in stdout.splitlines() if line.startswith(f"float64 {vr['wear_depth']} ")][-1].split()[2:]
    assert len(line) == n_points
    return np.array(line, dtype=float)


# ------------------------------------------------------------------ sanitizer builds
SANITIZER_FLAGS = ("-fsanitize=address,undefined", "-fno-sanitize-recover=all", "-fno-omit-frame-pointer", "-g")
SANITIZER_REPORTS = ("ERROR: AddressSanitizer", "runtime error:", "ERROR: LeakSanitizer")


def sanitized_fmu(fmu_path: Path, out_dir: Path, fmi_version: int) -> Path:
    """The native FMU unzipped into ``out_dir`` with its linux64 binary relinked from the FMU's own
    sources (C layer and kernel objects, the build's arguments) plus :data:`SANITIZER_FLAGS`."""
    import zipfile

    from wearjoint.fmu import build_native, platforms
    from wearjoint.fmu import variables as fv

    with zipfile.ZipFile(fmu_path) as z:
        z.extractall(out_dir)
    sources = Path(out_dir) / "sources"
    target = platforms.PLATFORMS["linux64"]
    objects = [f"kernels/linux64/{p.name}" for p in sorted((sources / "kernels" / "linux64").glob("*.o"))]
    cmd = ["gcc", *SANITIZER_FLAGS, *build_native.link_arguments(target, fmi_version, objects)]
    done = subprocess.run(cmd, capture_output=True, text=True, cwd=sources)
    if done.returncode != 0:
        raise RuntimeError(f"linking the sanitized FMU failed:\n{' '.join(cmd)}\n{done.stderr}")
    binary = f"{fv.MODEL_NAME}{target.extension}"
    shutil.move(sources / binary, Path(out_dir) / target.binary_arcname(fmi_version))
    return Path(out_dir)


def sanitizer_runtime_environment() -> dict:
    """For a Python child process that loads a sanitized FMU: the runtimes preloaded, leaks not
    reported (the interpreter's own), the first report fatal."""
    libraries = [subprocess.run(["gcc", f"-print-file-name={name}"], capture_output=True, text=True).stdout.strip()
                 for name in ("libasan.so", "libubsan.so")]
    return {**os.environ, "LD_PRELOAD": ":".join(libraries), "ASAN_OPTIONS": "detect_leaks=0:abort_on_error=1",
            "UBSAN_OPTIONS": "halt_on_error=1:print_stacktrace=1"}


# ------------------------------------------------------------------ the C host's own test FMU
DAHLQUIST_SOURCES = tuple(C_HOST_DIR / "test_fmu" / name for name in ("dahlquist.c", "dahlquist_states.c"))
DAHLQUIST_MODEL_DESCRIPTION = C_HOST_DIR / "test_fmu" / "modelDescription.xml"
DAHLQUIST_ID = "dahlquist"
DAHLQUIST_GUID = "{a3f0e8de-5c1b-4d7e-9a61-0d5a41c15701}"
# value references of the test FMU
VR_X, VR_K, VR_X0, VR_U, VR_NSTEPS, VR_RESOURCE = range(6)


def build_dahlquist_fmu(out_dir: Path, extra_flags: Sequence[str] = ()) -> Path:
    """Build the test FMU as an unzipped FMU folder ``out_dir/dahlquist`` and return its path."""
    fmu_dir = Path(out_dir) / DAHLQUIST_ID
    (fmu_dir / "binaries" / "linux64").mkdir(parents=True, exist_ok=True)
    (fmu_dir / "resources").mkdir(exist_ok=True)
    shutil.copyfile(DAHLQUIST_MODEL_DESCRIPTION, fmu_dir / "modelDescription.xml")
    so = fmu_dir / "binaries" / "linux64" / f"{DAHLQUIST_ID}.so"
    cmd = ["gcc", "-O2", "-g", "-Wall", "-Wextra", *extra_flags, "-shared", "-fPIC",
           f"-I{fmi2_headers_dir()}", *map(str, DAHLQUIST_SOURCES), "-o", str(so), "-lm"]
    proc = subprocess.run(cmd, capture_output=True, text=True, env=CLEAN_ENV)
    if proc.returncode != 0:
        raise RuntimeError(f"building the test FMU failed:\n{' '.join(cmd)}\n{proc.stderr}")
    return fmu_dir


INIT = """\
instantiate dq
set_real 1={k!r} 2={x0!r}
setup 0
enter_init
exit_init
"""


def init(k=2.0, x0=1.5) -> str:
    return INIT.format(k=float(k), x0=float(x0))
