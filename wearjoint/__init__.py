"""wearjoint: a planar revolute clearance joint whose bushing wears.

Importing the package loads numpy and numba only; the FMI, exudyn and plotting
layers are imported by the modules that need them.
"""
from ._compile import cache

cache.install()

# kernels load only after numba's cache locator is installed
from .joint import ClearanceJoint, ContactResult, JointState, StateError  # noqa: E402
from .parameters import (  # noqa: E402
    JointParameters, ParameterError, SliderCrankParameters, contact_stiffness, effective_modulus,
    paper_joint,
)

__version__ = "0.1.0"

__all__ = ["ClearanceJoint", "ContactResult", "JointState", "JointParameters", "ParameterError",
           "SliderCrankParameters", "StateError", "contact_stiffness", "effective_modulus", "paper_joint"]
