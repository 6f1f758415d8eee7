"""The wear study's configuration from `wearjoint wear-study`'s parsed options: the sweeps' target's
(:func:`wearjoint.targets.wear_study_config`, which the sweeps and the sensitivity study call too) with the
command line's note."""
from __future__ import annotations

from ..studies.wear_study import WearStudyConfig
from ..targets import parse_float_list, parse_int_list, wear_study_config
from .options import model_notes


def config_from_args(args) -> WearStudyConfig:
    config = wear_study_config(vars(args))
    model_notes(config.joint, config.mechanism, args)
    return config


__all__ = ["config_from_args", "parse_int_list", "parse_float_list"]
