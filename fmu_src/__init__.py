"""Source of the ClearanceWearJoint FMU (pythonfmu slave); installed as ``wearjoint.fmu_src``."""
