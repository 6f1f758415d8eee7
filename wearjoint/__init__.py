"""wearjoint: a planar revolute clearance joint whose bushing wears.

Importing the package loads nothing heavy: the names below are imported on first use (PEP 562), and
numba only with the kernels (:mod:`wearjoint.core.jit` installs the package's cache locator first).  The
command line starts its figure worker before any of them loads.
"""
import importlib

__version__ = "0.1.0"

# public name -> the module defining it
_EXPORTS = {
    "ClearanceJoint": "joint", "ContactResult": "joint", "JointState": "joint", "StateError": "joint",
    "JointParameters": "parameters", "ParameterError": "parameters", "SliderCrankParameters": "parameters",
    "contact_stiffness": "parameters", "effective_modulus": "parameters", "paper_joint": "parameters",
}
__all__ = list(_EXPORTS)


def __getattr__(name: str):
    if name not in _EXPORTS:
        raise AttributeError(f"module 'wearjoint' has no attribute {name!r}")
    value = getattr(importlib.import_module("." + _EXPORTS[name], __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
