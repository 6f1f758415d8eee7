"""The SliderCrank FMU's test helpers, shared by tests/fmu/test_slider_crank_fmu.py (the model) and
tests/fmu/test_slider_crank_fmu_hosts.py (C hosts, states, platforms): the built FMUs, an initialised
Co-Simulation instance, the traces' smooth loads and the C hosts' trace command."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
from fmi_host import write_trace_file

from wearjoint.fmu import slider_crank as sc
from wearjoint.fmu import variables as fv
from wearjoint.slider_crank import SliderCrank

MECHANISM = SliderCrank()
INPUT_VRS = [sc.VALUE_REFERENCES[v.name] for v in sc.LOAD_INPUTS]   # the loads and the slider's (load_coupling 0)
STATE_VRS = [sc.VALUE_REFERENCES[v.name] for v in sc.STATES]
OUTPUTS = [v.name for v in sc.VARIABLES if v.causality == fv.OUTPUT]
OUTPUT_VRS = [sc.VALUE_REFERENCES[name] for name in OUTPUTS]
WIN64_TOLERANCE = 1e-9   # of each output's range (MinGW's sin/cos differ from glibc's in the last bit)


def slider_crank_fmus(shared_build, tmp_path_factory) -> dict:
    """SliderCrank.fmu, FMI 2.0 and 3.0, as built by default (every installed platform), unzipped."""
    built = {}
    for version in (2, 3):
        path = shared_build(fmi_version=version, model="slider-crank")
        md = read_model_description(str(path))
        built[version] = {"path": path, "md": md, "token": md.guid,
                          "dir": Path(extract(str(path), unzipdir=str(tmp_path_factory.mktemp(f"sc{version}_x"))))}
    return built


def initialised(kind, fmu, parameters=None, name="sc"):
    """An initialised FMI 2.0 instance (``kind``: fmpy's FMU2Slave or FMU2Model) of the SliderCrank FMU ``fmu`` with
    ``parameters``."""
    instance = kind(guid=fmu["token"], unzipDirectory=str(fmu["dir"]), modelIdentifier=sc.MODEL_IDENTIFIER,
                    instanceName=name)
    instance.instantiate()
    instance.setupExperiment(startTime=0.0)
    instance.enterInitializationMode()
    for key, value in (parameters or {}).items():
        instance.setReal([sc.VALUE_REFERENCES[key]], [value])
    instance.exitInitializationMode()
    return instance


def initialised_slave(fmu, parameters=None, name="sc"):
    """An initialised FMI 2.0 Co-Simulation instance of the SliderCrank FMU ``fmu`` with ``parameters``."""
    return initialised(FMU2Slave, fmu, parameters, name)


def smooth_loads(t):
    """Loads of the order of the ideal joint's (N, N m), smooth in t, and a load on the slider: the inputs of the
    traces."""
    return np.array([40 * math.sin(31 * t), -25 + 10 * math.cos(17 * t), 0.3 * math.sin(13 * t),
                     -40 * math.sin(31 * t), 25 - 10 * math.cos(17 * t), -0.2 * math.cos(11 * t),
                     5 * math.sin(7 * t)])


def trace_command(tmp_path, n: int, h: float = 1e-3, start: float = 0.0) -> str:
    """The C hosts' ``trace`` command over ``n`` steps of ``h`` [s] from ``start`` [s] (the FMU's time: a step from
    another is refused) under the smooth loads (file in tmp_path)."""
    times = [start + i * h for i in range(n)]
    path = write_trace_file(tmp_path / f"loads_{start:g}.txt", [[t, h, *smooth_loads(t)] for t in times])
    return f"trace {path} {len(INPUT_VRS)} {','.join(map(str, INPUT_VRS))} {','.join(map(str, OUTPUT_VRS))}\n"


def start_script(version: int, parameters: dict, interface: str = "instantiate") -> str:
    """A C host script that instantiates and initialises the FMU with ``parameters``."""
    setter = "set_real" if version == 2 else "set_float64"
    values = " ".join(f"{sc.VALUE_REFERENCES[k]}={v!r}" for k, v in parameters.items())
    return (f"{interface} sc\n{'setup 0' + chr(10) if version == 2 else ''}enter_init\n"
            + (f"{setter} {values}\n" if values else "") + "exit_init\n")
