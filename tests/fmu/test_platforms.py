"""One FMU for linux64, win64 and aarch64-linux (docs/reference/fmu.md §5, "Platforms").

All three binaries come from the same kernels' IR (only the target triple and data layout
differ).  Each is driven by the C host built for its own platform (tests/c_host, portable C):
linux64 natively, win64 under wine, aarch64-linux under qemu-aarch64, through the same worn
slider-crank trace in FMI 2.0 Co-Simulation and Model Exchange and FMI 3.0 Co-Simulation.
References: linux64 (itself equal to the in-process joint, test_native_fmu.py).  aarch64 must
give the same bits (no fused multiply-add anywhere); win64 differs in the last bits of sin, cos
and atan2 (MinGW's msvcrt-based libm), so it is held to 1e-9 of each output's range; the contact
angle to 1e-8 of its range: where the worn groove conforms to the pin the nearest point of the
fitted profile is ill-conditioned (docs/reference/fmu.md §5, Platforms: measured 4.7e-9 of 2 pi).

Tests of a platform skip, naming what to install, where its cross compiler or emulator is
missing (.ci/install-cross-toolchains installs them).
"""
from __future__ import annotations

import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy import extract, read_model_description, supported_platforms  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402
from fmi_host import (  # noqa: E402
    CLEAN_ENV, build_c_host, build_fmi3_host, platform_or_skip, profile_command, profile_values,
    run_c_host, start_script, trace_command, trace_rows, value_lines, write_trace_file,
)
from kinematic_trace import orbiting_pin_trace, slider_crank_trace  # noqa: E402
from test_directional_derivatives import (  # noqa: E402
    INPUT_NAMES, OUTPUT_NAMES, STATES, TOLERANCE, normalised_error,
)
from test_directional_derivatives import STEP as DIFFERENCE_STEP  # noqa: E402

from wearjoint import JointParameters, paper_joint  # noqa: E402
from wearjoint.fmu import platforms  # noqa: E402
from wearjoint.fmu import variables as fv  # noqa: E402
from wearjoint.fmu.model_description import fmi3_value_references  # noqa: E402

CROSS = ("win64", "aarch64-linux")
JOINT = paper_joint(wear_factor=10.0)      # micrometres of wear within the trace
N_POINTS = JOINT.n_points
ROWS, STEP = 2000, 1e-4                    # 0.2 s of the slider-crank: ten onsets, nine separations
WIN64_TOLERANCE = 1e-9                     # of each output's range over the trace, and of the deepest wear
WIN64_ANGLE_TOLERANCE = 1e-8               # the contact angle's, of its range (module docstring)
CASES = {"fmi2-cs": (2, False), "fmi2-me": (2, True), "fmi3-cs": (3, False)}


# ------------------------------------------------------------------ fixtures
@pytest.fixture(scope="module")
def fmus(shared_build, tmp_path_factory):
    """The FMI 2.0 and 3.0 FMUs as built by default (every installed platform), unzipped."""
    built = {}
    for version in (2, 3):
        path = shared_build(backend="native", fmi_version=version)
        md = read_model_description(str(path))
        vr = fv.value_references(md) if version == 2 else fmi3_value_references()
        built[version] = {"path": path, "token": md.guid, "vr": vr,
                          "dir": Path(extract(str(path), unzipdir=str(tmp_path_factory.mktemp(f"multi{version}_x"))))}
    return built


@pytest.fixture(scope="module")
def hosts(tmp_path_factory):
    """hosts(version, platform): the C host of that FMI version built for that platform (cached)."""
    cache = {}

    def get(version: int, platform: str) -> Path:
        if (version, platform) not in cache:
            out = tmp_path_factory.mktemp(f"host{version}_{platform}")
            build = build_c_host if version == 2 else build_fmi3_host
            cache[version, platform] = build(out, extra_flags=["-Werror"], platform=platform)
        return cache[version, platform]
    return get


@pytest.fixture(scope="module")
def trace():
    return slider_crank_trace(JOINT, ROWS, STEP)


@pytest.fixture(scope="module")
def trace_file(trace, tmp_path_factory):
    return write_trace_file(tmp_path_factory.mktemp("platform_trace") / "trace.txt", trace)


def carries(fmus, platform: str) -> None:
    platform_or_skip(platform)
    names = zipfile.ZipFile(fmus[2]["path"]).namelist()
    assert platforms.PLATFORMS[platform].binary_arcname(2) in names, f"{platform} was not built: {names[:5]}"


def run_on(hosts, fmu: dict, version: int, platform: str, script: str) -> str:
    code, out, err = run_c_host(hosts(version, platform), fmu["dir"], fv.MODEL_NAME, fmu["token"], script,
                                platform=platform)
    assert code == 0, f"{platform}: {out[-1500:]}{err[-3000:]}"
    return out


def worn_trace(hosts, fmus, case: str, platform: str, trace_file, also_read: tuple = ()) -> tuple[np.ndarray, np.ndarray]:
    """The outputs at every row (then those named in ``also_read``) and the final worn profile of ``case`` on
    ``platform``."""
    version, me = CASES[case]
    vr = fmus[version]["vr"]
    out = run_on(hosts, fmus[version], version, platform,
                 start_script(version, vr, JOINT, "instantiate_me" if me else "instantiate")
                 + trace_command(vr, trace_file, me, also_read=also_read) + profile_command(version, vr, N_POINTS)
                 + "free\n")
    return np.array(trace_rows(out), float), profile_values(out, version, vr, N_POINTS)


def assert_within_win64_tolerance(rows, profile, reference_rows, reference_profile, span_rows=None) -> None:
    """Each output within WIN64_TOLERANCE of its range over ``span_rows`` (default the reference
    rows; of its size where it is constant)."""
    span = np.ptp(reference_rows if span_rows is None else span_rows, axis=0)
    span = np.where(span > 0.0, span, np.max(np.abs(reference_rows), axis=0))
    worst = np.max(np.abs(rows - reference_rows), axis=0)
    tolerance = np.full(span.shape, WIN64_TOLERANCE)
    tolerance[1 + [v.name for v in fv.SCALAR_OUTPUTS].index("contact_angle")] = WIN64_ANGLE_TOLERANCE
    assert np.all(worst <= tolerance * span), (worst / np.maximum(span, 1e-300)).max()
    assert np.max(np.abs(profile - reference_profile)) <= WIN64_TOLERANCE * reference_profile.max()


# ------------------------------------------------------------------ what the FMU carries
def test_one_build_carries_a_binary_per_platform_and_validates(fmus):
    for platform in CROSS:
        carries(fmus, platform)
    for version, folders in ((2, ("linux64", "win64", "aarch64-linux")),
                             (3, ("x86_64-linux", "x86_64-windows", "aarch64-linux"))):
        names = zipfile.ZipFile(fmus[version]["path"]).namelist()
        binaries = sorted(n for n in names if n.startswith("binaries/"))
        assert binaries == sorted(f"binaries/{f}/{fv.MODEL_NAME}.{'dll' if 'win' in f else 'so'}" for f in folders)
        assert {"linux64", "win64"} <= set(supported_platforms(str(fmus[version]["path"])))
        assert validate_fmu(str(fmus[version]["path"])) == []


def _exports_and_imports(platform: str, binary: Path) -> tuple[set, set]:
    """(exported symbols, needed libraries) read with the platform's binutils."""
    if platform == "win64":
        dump = subprocess.run(["x86_64-w64-mingw32-objdump", "-p", str(binary)], capture_output=True, text=True,
                              check=True).stdout
        return set(re.findall(r"\]\s+(fmi\w+)", dump)), set(re.findall(r"DLL Name: (\S+)", dump))
    prefix = "aarch64-linux-gnu-" if platform == "aarch64-linux" else ""
    defined = subprocess.run([f"{prefix}nm", "-D", "--defined-only", str(binary)], capture_output=True, text=True,
                             check=True).stdout.split()[2::3]
    dynamic = subprocess.run([f"{prefix}readelf", "-d", str(binary)], capture_output=True, text=True,
                             check=True).stdout
    return set(defined), set(re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", dynamic))


@pytest.mark.parametrize("version", [2, 3])
@pytest.mark.parametrize("platform, runtime", [("win64", {"KERNEL32.dll", "msvcrt.dll"}),
                                               ("aarch64-linux", {"libc.so.6", "libm.so.6"})])
def test_each_binary_needs_the_c_runtime_only_and_exports_exactly_the_fmi_functions(fmus, version, platform,
                                                                                     runtime):
    carries(fmus, platform)
    folder = fmus[version]["dir"] / "binaries"
    reference_exports, _ = _exports_and_imports("linux64", folder / platforms.PLATFORMS["linux64"].folder(version)
                                                / f"{fv.MODEL_NAME}.so")
    target = platforms.PLATFORMS[platform]
    exports, needed = _exports_and_imports(platform, folder / target.folder(version) / f"{fv.MODEL_NAME}{target.extension}")
    assert needed <= runtime, needed
    assert exports == reference_exports and all(name.startswith(f"fmi{version}") for name in exports)
    assert {f"fmi{version}Instantiate" if version == 2 else "fmi3InstantiateCoSimulation",
            f"fmi{version}DoStep"} <= exports


# fused multiply-add instructions: aarch64 f[n]madd/f[n]msub/fmla/fmls, x86-64 vfmadd/vfmsub/vfnmadd
FMA = re.compile(r"\s(f(n)?m(add|sub)|fml[as]|vf(n)?m(add|sub)\w*)\s")


@pytest.mark.parametrize("platform", ["linux64", "win64", "aarch64-linux"])
def test_no_binary_fuses_a_multiply_and_an_add(fmus, platform):
    if platform != "linux64":
        carries(fmus, platform)
    target = platforms.PLATFORMS[platform]
    objdump = {"win64": "x86_64-w64-mingw32-objdump", "aarch64-linux": "aarch64-linux-gnu-objdump"}.get(platform,
                                                                                                      "objdump")
    binary = fmus[2]["dir"] / "binaries" / target.folder(2) / f"{fv.MODEL_NAME}{target.extension}"
    code = subprocess.run([objdump, "-d", str(binary)], capture_output=True, text=True, check=True).stdout
    assert code.count("\n") > 1000          # the kernels are in there
    assert not FMA.findall(code), FMA.findall(code)[:5]


# ------------------------------------------------------------------ the same trace everywhere
@pytest.mark.parametrize("wear_factor", [10.0, 1000.0])
def test_a_pin_driven_round_a_fast_wearing_bushing_gives_linux64s_numbers_on_win64(fmus, hosts, wear_factor,
                                                                                   tmp_path):
    """The default (Hunt-Crossley) damping does not amplify win64's last-bit differences of sin/cos/atan2:
    4000 steps of 5 us, the pin bouncing gently in and out of a bushing that wears micrometres, within 1e-9
    of each output's range (measured 2.2e-11 at wear factor 1000; the Lankarani-Nikravesh damping with its
    1 mm/s floor 1.6e-9, which fails)."""
    carries(fmus, "win64")
    joint = JointParameters(wear_factor=wear_factor)
    path = write_trace_file(tmp_path / "orbit.txt", orbiting_pin_trace(joint, 4000, 5e-6))
    vr = fmus[2]["vr"]
    script = start_script(2, vr, joint) + trace_command(vr, path) + profile_command(2, vr, joint.n_points) + "free\n"
    (rows, profile), (reference_rows, reference_profile) = (
        (np.array(trace_rows(out), float), profile_values(out, 2, vr, joint.n_points))
        for out in (run_on(hosts, fmus[2], 2, platform, script) for platform in ("win64", "linux64")))
    contact = reference_rows[:, 1 + [v.name for v in fv.SCALAR_OUTPUTS].index("contact")]
    assert np.count_nonzero(np.diff(contact) > 0.5) >= 10 and reference_profile.max() > 1e-6   # onsets and wear
    assert_within_win64_tolerance(rows, profile, reference_rows, reference_profile)


# every case on win64 (its own compiler and C runtime); aarch64's FMI 2.0 co-simulation by default, the others slow
@pytest.mark.parametrize("platform,case", [(platform, case) if platform == "win64" or case == "fmi2-cs" else
                                           pytest.param(platform, case, marks=pytest.mark.slow)
                                           for platform in CROSS for case in CASES])
def test_the_worn_trace_gives_linux64s_numbers(fmus, hosts, trace_file, case, platform):
    """aarch64: the same bits as linux64; win64: within 1e-9 of each output's range and of the deepest wear."""
    carries(fmus, platform)
    reference_rows, reference_profile = worn_trace(hosts, fmus, case, "linux64", trace_file)
    rows, profile = worn_trace(hosts, fmus, case, platform, trace_file)
    contact = reference_rows[:, 1 + [v.name for v in fv.SCALAR_OUTPUTS].index("contact")]
    assert rows.shape == reference_rows.shape == (ROWS, 1 + len(fv.SCALAR_OUTPUTS))
    assert np.count_nonzero(np.diff(contact) > 0.5) >= 5 and reference_profile.max() > 1e-6   # impacts and wear
    if platform == "aarch64-linux":
        assert np.array_equal(rows, reference_rows) and np.array_equal(profile, reference_profile)
    else:
        assert_within_win64_tolerance(rows, profile, reference_rows, reference_profile)


@pytest.mark.parametrize("platform", CROSS)
def test_a_linearising_hosts_worn_trace_gives_linux64s_numbers(fmus, hosts, trace_file, platform):
    """docs/reference/model.md §3.11 on each binary: the worn trace read as a linearising master reads it (after
    each row's outputs the normal force's 12 published derivatives), so that each doStep in contact wears with
    the linear normal force's mean instead of its held value: aarch64 the same bits as linux64, win64 within 1e-9
    of each output's range; on linux64 that profile is not the held trace's (the rule ran)."""
    carries(fmus, platform)
    derivatives = tuple(fv.derivative_name("normal_force", v.name) for v in fv.INPUTS)
    reference_rows, reference_profile = worn_trace(hosts, fmus, "fmi2-cs", "linux64", trace_file, derivatives)
    held_profile = worn_trace(hosts, fmus, "fmi2-cs", "linux64", trace_file)[1]
    rows, profile = worn_trace(hosts, fmus, "fmi2-cs", platform, trace_file, derivatives)
    assert rows.shape == reference_rows.shape == (ROWS, 1 + len(fv.SCALAR_OUTPUTS) + len(derivatives))
    assert np.max(np.abs(reference_profile - held_profile)) > 1e-3 * reference_profile.max() > 1e-9
    if platform == "aarch64-linux":
        assert np.array_equal(rows, reference_rows) and np.array_equal(profile, reference_profile)
    else:
        assert_within_win64_tolerance(rows, profile, reference_rows, reference_profile)


def test_a_state_serialised_on_one_platform_continues_on_another(fmus, hosts, trace, trace_file, tmp_path):
    """A state serialised half-way on linux64 continues on aarch64 bit for bit and on win64 within
    tolerance; win64's and aarch64's serialised states restore on linux64 (fixed little-endian layout)."""
    for platform in CROSS:
        carries(fmus, platform)
    vr = fmus[2]["vr"]
    first = write_trace_file(tmp_path / "first.txt", trace[:ROWS // 2])
    later = write_trace_file(tmp_path / "later.txt", trace[ROWS // 2:])
    start = start_script(2, vr, JOINT)
    tail = trace_command(vr, later) + profile_command(2, vr, N_POINTS) + "free\n"

    def continued(platform, state) -> tuple[np.ndarray, np.ndarray]:
        out = run_on(hosts, fmus[2], 2, platform, start + f"deserialize 0 {state}\nset_state 0\n" + tail)
        return np.array(trace_rows(out), float), profile_values(out, 2, vr, N_POINTS)

    states = {}
    for platform in ("linux64", *CROSS):
        states[platform] = tmp_path / f"{platform}.state"
        run_on(hosts, fmus[2], 2, platform, start + trace_command(vr, first) + f"get_state 0\nserialize 0 {states[platform]}\n")
    assert states["aarch64-linux"].read_bytes() == states["linux64"].read_bytes()
    reference = continued("linux64", states["linux64"])
    assert reference[1].max() > 0.0
    on_aarch64 = continued("aarch64-linux", states["linux64"])
    assert np.array_equal(on_aarch64[0], reference[0]) and np.array_equal(on_aarch64[1], reference[1])
    whole_trace = worn_trace(hosts, fmus, "fmi2-cs", "linux64", trace_file)[0]
    assert_within_win64_tolerance(*continued("win64", states["linux64"]), *reference, whole_trace)
    assert_within_win64_tolerance(*continued("linux64", states["win64"]), *reference, whole_trace)


@pytest.mark.parametrize("platform", CROSS)
def test_sources_relink_the_platforms_binary(fmus, hosts, platform, tmp_path):
    """``sh sources/build.sh PLATFORM`` relinks a binary that answers like the shipped one."""
    carries(fmus, platform)
    shutil.copytree(fmus[2]["dir"], tmp_path / "fmu")
    sources, target = tmp_path / "fmu" / "sources", platforms.PLATFORMS[platform]
    done = subprocess.run(["sh", str(sources / "build.sh"), platform], capture_output=True, text=True, env=CLEAN_ENV)
    assert done.returncode == 0, done.stderr
    relinked = sources / f"{fv.MODEL_NAME}{target.extension}"
    shipped = tmp_path / "fmu" / "binaries" / platform / relinked.name
    vr = fmus[2]["vr"]
    # the pin centre 0.11 mm from the bushing centre: 10 um into the bushing
    touching = {"pin_omega": -15.7, "bushing_x": JOINT.pin_offset_m[0] - JOINT.bushing_offset_m[0] - 0.00011,
                "bushing_vy": 0.2}
    script = (start_script(2, vr, JOINT) + "set_real " + " ".join(f"{vr[k]}={v!r}" for k, v in touching.items())
              + "\nget_real " + " ".join(str(vr[v.name]) for v in fv.SCALAR_OUTPUTS) + "\n")
    copy = {**fmus[2], "dir": tmp_path / "fmu"}
    before = value_lines(run_on(hosts, copy, 2, platform, script))
    relinked.replace(shipped)
    after = value_lines(run_on(hosts, copy, 2, platform, script))
    assert after == before and any(float(line.split()[2]) > 100.0 for line in before)   # a normal force
    done = subprocess.run(["sh", str(sources / "build.sh"), "sparc"], capture_output=True, text=True, env=CLEAN_ENV)
    assert done.returncode == 2 and "unknown platform 'sparc'" in done.stderr


@pytest.mark.parametrize("case", list(CASES))
@pytest.mark.parametrize("platform", ["linux64", *CROSS])
def test_directional_derivatives_equal_central_differences_on_each_platform(fmus, hosts, case, platform, tmp_path):
    """fmi*GetDirectionalDerivative through the platform's C host, unit seeds at the contact states of
    test_directional_derivatives.py (worn and unworn, set as FMU states), against the central differences of
    the same binary's outputs."""
    if platform != "linux64":
        carries(fmus, platform)
    version, me = CASES[case]
    vr = fmus[version]["vr"]
    set_real, get_real = ("set_real", "get_real") if version == 2 else ("set_float64", "get_float64")
    inputs, outputs = [vr[n] for n in INPUT_NAMES], ",".join(str(vr[n]) for n in OUTPUT_NAMES)
    script = start_script(version, vr, STATES[0].params, "instantiate_me" if me else "instantiate")
    for k, state in enumerate(STATES):
        (tmp_path / f"{k}.state").write_bytes(state.fmu_state())
        x = [float(value) for value in state.inputs()]
        script += f"deserialize {k} {tmp_path / f'{k}.state'}\nset_state {k}\n"
        script += f"{set_real} " + " ".join(f"{v}={value!r}" for v, value in zip(inputs, x)) + "\n"
        script += "".join(f"directional_derivative {outputs} {','.join(map(str, inputs))} "
                          f"{','.join(str(float(value)) for value in seed)}\n" for seed in np.eye(12))
        for m in range(12):
            for sign in (1.0, -1.0):
                script += (f"{set_real} {inputs[m]}={x[m] + sign * float(DIFFERENCE_STEP[m])!r}\n"
                           f"{get_real} {outputs.replace(',', ' ')}\n")
            script += f"{set_real} {inputs[m]}={x[m]!r}\n"
    out = run_on(hosts, fmus[version], version, platform, script + "free\n").splitlines()
    sensitivities = np.array([float(line.split()[2]) for line in out if line.startswith("sensitivity ")])
    values = np.array([float(line.split()[2]) for line in out if line.startswith(("real ", "float64 "))])
    n = len(OUTPUT_NAMES)
    for k in range(len(STATES)):
        derivatives = sensitivities[k * 12 * n:(k + 1) * 12 * n].reshape(12, n).T
        plus_minus = values[k * 24 * n:(k + 1) * 24 * n].reshape(12, 2, n)
        differences = ((plus_minus[:, 0] - plus_minus[:, 1]) / (2.0 * DIFFERENCE_STEP[:, None])).T
        assert normalised_error(derivatives, differences) <= TOLERANCE, (platform, STATES[k].name)


# ------------------------------------------------------------------ choosing the platforms
def _build_fmu_cli(*argv) -> int:
    """``wearjoint build-fmu ARGV``'s exit status (the program's own path: its errors, one line each)."""
    from wearjoint.cli import main

    return main(["build-fmu", *argv])


def test_a_platform_without_its_toolchain_is_named_with_the_package_to_install(tmp_path, monkeypatch, capsys):
    hidden = {"x86_64-w64-mingw32-gcc", "aarch64-linux-gnu-gcc"}
    real_which = shutil.which
    monkeypatch.setattr(platforms.shutil, "which", lambda name, *a, **k: None if name in hidden else
                        real_which(name, *a, **k))
    assert _build_fmu_cli("--out", str(tmp_path / "a"), "--platforms", "linux64,win64") == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "win64" in err[0] and "gcc-mingw-w64-x86-64" in err[0]
    assert not (tmp_path / "a").exists()
    # automatic: linux64 alone, and why the others were skipped
    assert _build_fmu_cli("--out", str(tmp_path / "b"), "--n-points", "64") == 0
    err = capsys.readouterr().err
    assert "built: linux64" in err
    assert re.search(r"skipped win64: .*gcc-mingw-w64-x86-64", err)
    assert re.search(r"skipped aarch64-linux: .*gcc-aarch64-linux-gnu", err)
    names = zipfile.ZipFile(tmp_path / "b" / f"{fv.MODEL_NAME}.fmu").namelist()
    assert [n for n in names if n.startswith("binaries/")] == [f"binaries/linux64/{fv.MODEL_NAME}.so"]


@pytest.mark.parametrize("argv, message", [
    (["--platforms", "sparc"], "--platforms='sparc' (platforms) is invalid ('sparc' is no platform): allowed auto or a "
                               "comma-separated list of linux64"),
    (["--platforms", ","], "--platforms=',' (platforms) is invalid"),
    (["--platforms", "win64", "--backend", "pythonfmu"], "the pythonfmu backend builds linux64 only"),
    (["--platforms", "aarch64-darwin"], "aarch64-darwin is built only on a machine of that platform (this one is linux64)"),
])
def test_bad_platform_choices_are_refused_in_one_line(tmp_path, capsys, argv, message):
    assert _build_fmu_cli("--out", str(tmp_path), *argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0], err
    assert not any(tmp_path.iterdir())


def test_fmi3_names_are_accepted_for_platforms():
    assert platforms.parse_platforms("x86_64-linux,x86_64-windows,aarch64-linux,win64") == \
        ("linux64", "win64", "aarch64-linux")
    assert platforms.parse_platforms("auto") is None
    assert platforms.PLATFORMS["aarch64-linux"].folder(2) == "aarch64-linux"    # FMI 2.0.4 section 2.3
    assert platforms.PLATFORMS["win64"].binary_arcname(3) == f"binaries/x86_64-windows/{fv.MODEL_NAME}.dll"


def test_the_readme_c_tool_recipe_runs_on_linux64_and_under_wine(fmus, tmp_path):
    """README "Using the FMU from a C tool", as written: the linux64 host and the Windows host (wine)
    load their own platform's binary of the same FMU and print the same answers."""
    carries(fmus, "win64")
    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text()
    section = readme[readme.index("### Using the FMU from a C tool"):]
    recipe = section[section.index("```bash\n") + 8:section.index("```\n", section.index("```bash\n") + 8)]
    (tmp_path / "build").mkdir()
    shutil.copy(fmus[2]["path"], tmp_path / "build" / f"{fv.MODEL_NAME}.fmu")
    (tmp_path / "tests").symlink_to(Path(__file__).resolve().parents[1])
    from fmi_host import wine_environment
    env = {**wine_environment(), "PATH": f"{Path(shutil.which('python')).parent}:/usr/bin:/bin"}
    done = subprocess.run(["bash", "-e", "-c", recipe], capture_output=True, text=True, cwd=tmp_path, env=env,
                          timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    runs = done.stdout.split("instantiate ok\n")[1:]
    assert len(runs) == 2, done.stdout

    def value(run, name):
        return float(re.search(rf"^real {fmus[2]['vr'][name]} (\S+)$", run, flags=re.M).group(1))

    # the bushing body 0.11 mm off the pin: the pin in contact, 0.11 mm - c deep (the check had left it centred)
    for run in runs:
        assert value(run, "contact") == 1.0
        assert abs(value(run, "penetration") - (0.11e-3 - (JOINT.bushing_radius_m - JOINT.pin_radius_m))) < 1e-15
    force = [value(run, "pin_force_x") for run in runs]             # pushed towards -x; win64 within 1e-9
    assert force[0] < -1000.0 and abs(force[1] - force[0]) <= 1e-9 * abs(force[0])
