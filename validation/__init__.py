"""Independent checks: the slider-crank built natively in exudyn, comparison metrics,
the paper-figure reproduction.  Installed as ``wearjoint.validation``."""
