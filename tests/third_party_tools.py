"""Where the tests find the third-party tools they run when present (each test skips, naming the variable,
where its tool is missing): fmusim, the Reference-FMUs' importer ($FMUSIM, default the build
../shared/tools/fmusim makes), and OpenModelica's OMSimulator ($OMSIMULATOR_HOME, else ../shared/tools/omsimulator
beside this clone's folder, else the OMSimulator on PATH)."""
from __future__ import annotations

import os
import shutil
from pathlib import Path

FMUSIM = os.environ.get("FMUSIM", "/tmp/fmusim-build/build-fmusim/fmusim")


def _omsimulator_home() -> Path:
    if os.environ.get("OMSIMULATOR_HOME"):
        return Path(os.environ["OMSIMULATOR_HOME"])
    shared = Path(__file__).resolve().parents[2] / "shared/tools/omsimulator"
    on_path = shutil.which("OMSimulator")
    return Path(on_path).resolve().parents[1] if on_path and not shared.is_dir() else shared


OMSIMULATOR_HOME = _omsimulator_home()
OMSIMULATOR_CLI = OMSIMULATOR_HOME / "bin/OMSimulator"
OMSIMULATOR_PYTHON = OMSIMULATOR_HOME / "lib/x86_64-linux-gnu"     # its Python package, libOMSimulator.so beside it
OMSIMULATOR_MISSING = (f"no OMSimulator build at {OMSIMULATOR_HOME} (set $OMSIMULATOR_HOME; README in "
                       "../shared/tools/omsimulator)")
