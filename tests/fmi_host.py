"""Helpers to build and run the C FMI hosts ``tests/c_host/fmi2_host.c`` (FMI 2.0) and
``tests/c_host/fmi3_host.c`` (FMI 3.0), both on ``host_common.c`` (see the README there): the proof
that an FMU works from C with no Python on the host."""
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
HOST_SOURCE = C_HOST_DIR / "fmi2_host.c"
FMI3_HOST_SOURCE = C_HOST_DIR / "fmi3_host.c"
COMMON_SOURCE = C_HOST_DIR / "host_common.c"     # the script machinery both hosts share

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


def _build_host(source: Path, headers: Path | None, out_dir: Path, extra_flags: Sequence[str]) -> Path:
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    exe = out_dir / source.stem
    cmd = ["gcc", "-O2", "-g", "-Wall", "-Wextra", *extra_flags, f"-I{headers}", str(source),
           str(COMMON_SOURCE), "-o", str(exe), "-ldl"]
    proc = subprocess.run(cmd, capture_output=True, text=True, env=CLEAN_ENV)
    if proc.returncode != 0:
        raise RuntimeError(f"building the C host failed:\n{' '.join(cmd)}\n{proc.stderr}")
    return exe


def build_c_host(out_dir: Path, extra_flags: Sequence[str] = ()) -> Path:
    """Compile the FMI 2.0 host into ``out_dir/fmi2_host`` and return its path.

    ``gcc -O2 -g -Wall -Wextra -I<fmi2 headers> fmi2_host.c host_common.c -o fmi2_host -ldl``
    (one process, one core).  Raises ``RuntimeError`` with gcc's output if the compilation fails.
    """
    return _build_host(HOST_SOURCE, fmi2_headers_dir(), out_dir, extra_flags)


def build_fmi3_host(out_dir: Path, extra_flags: Sequence[str] = ()) -> Path:
    """Compile the FMI 3.0 host into ``out_dir/fmi3_host`` and return its path (as
    :func:`build_c_host`, with ``fmi3_host.c``).  Run it with :func:`run_c_host`, the
    instantiationToken in place of the GUID."""
    return _build_host(FMI3_HOST_SOURCE, fmi3_headers_dir(), out_dir, extra_flags)


def run_c_host(host: Path, fmu_dir: Path, model_identifier: str, guid: str, script: Script, *,
               host_args: Sequence[str] = (), valgrind: bool = False,
               timeout: float = 600.0) -> tuple[int, str, str]:
    """Run a C host (either) on an unzipped FMU with a clean environment; return (returncode, stdout, stderr).

    ``script`` is the script text (``str``), a sequence of lines, or a path (``os.PathLike``) to an
    existing script file.  Text is written to a temporary file that is removed afterwards.
    The environment is only ``PATH=/usr/bin:/bin``: no PYTHONPATH, LD_LIBRARY_PATH or LD_PRELOAD.
    ``valgrind=True`` runs under ``valgrind --leak-check=full --error-exitcode=3`` (valgrind's
    report is at the end of stderr).  ``host_args`` go before the positional arguments
    (e.g. ``["--no-unload"]``).
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
    cmd = [*(VALGRIND_ARGS if valgrind else ()), str(host), *host_args, str(fmu_dir),
           model_identifier, guid, script_path]
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, env=dict(CLEAN_ENV),
                              timeout=timeout)
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
