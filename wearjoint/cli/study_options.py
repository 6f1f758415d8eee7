"""The wear study's configuration from `wearjoint wear-study`'s options (also read by the sweeps and the
sensitivity study, which run wear studies as cases: here, apart from the command, so that they do not
import the command that imports them)."""
from __future__ import annotations

from ..parameters import ParameterError
from ..studies.cycle_jump import DEFAULT_JUMP_TOLERANCE
from ..studies.wear_study import DEFAULT_WEAR_FACTOR, WearStudyConfig
from .options import model_from_args


def parse_int_list(name: str, text: str) -> tuple:
    """'1000,2000' -> (1000, 2000); a clear ParameterError for anything else."""
    values = []
    for item in str(text).split(","):
        item = item.strip()
        try:
            values.append(int(item))
        except ValueError:
            raise ParameterError(f"{name}: {item!r} is not an integer (expected e.g. 1000,2000)") from None
    return tuple(values)


def parse_float_list(name: str, text: str) -> tuple:
    values = []
    for item in str(text).split(","):
        try:
            values.append(float(item))
        except ValueError:
            raise ParameterError(f"{name}: {item.strip()!r} is not a number (expected e.g. 1,10,50)") from None
    return tuple(values)


def config_from_args(args) -> WearStudyConfig:
    joint, mechanism = model_from_args(args)
    revolutions = parse_int_list("--revolutions", args.revolutions)
    if len(revolutions) != 1:
        raise ParameterError("--revolutions takes one integer")
    revolutions = revolutions[0]
    if args.snapshots is not None:
        snapshots = parse_int_list("--snapshots", args.snapshots)
    else:
        snapshots = tuple(sorted({max(1, revolutions * q // 4) for q in (1, 2, 3, 4)}))
    jump_tolerance = args.cycle_jump_tolerance
    if jump_tolerance is None and args.wear_factor is None and not args.no_cycle_jump:
        jump_tolerance = DEFAULT_JUMP_TOLERANCE
    if args.wear_factor is None and not args.no_wear:
        joint = joint.replace(wear_factor=DEFAULT_WEAR_FACTOR)
    return WearStudyConfig(joint=joint, mechanism=mechanism, revolutions=revolutions, snapshots=snapshots,
                           jump_tolerance=jump_tolerance, jump_block_revolutions=args.cycle_jump_block,
                           engine=args.engine,
                           integrator=args.integrator, max_step_s=args.max_step,
                           **({"rtol": args.rtol} if getattr(args, "rtol", None) is not None else {}),
                           checkpoint_every_revolutions=args.checkpoint_every,
                           impact_threshold_m_s2=args.impact_threshold_m_s2, fmu_backend=args.fmu_backend)
