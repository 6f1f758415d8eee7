"""wearjoint: a planar revolute clearance joint whose bushing wears.

Importing the package loads numpy and numba only; the FMI, exudyn and plotting
layers are imported by the modules that need them.
"""
from .joint import ClearanceJoint, ContactResult, JointState
from .parameters import (
    JointParameters, ParameterError, SliderCrankParameters, contact_stiffness, effective_modulus,
    paper_joint,
)

__version__ = "0.1.0"

__all__ = ["ClearanceJoint", "ContactResult", "JointState", "JointParameters", "ParameterError",
           "SliderCrankParameters", "contact_stiffness", "effective_modulus", "paper_joint"]
