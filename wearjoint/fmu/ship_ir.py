"""Write the kernel IR the package ships (``wearjoint/fmu/shipped_ir/``) anew, after a change to the kernels.

``python -m wearjoint.fmu.ship_ir [MODEL ...]`` compiles each model's IR with an empty numba cache
(:func:`wearjoint.fmu.kernel_ir.write_shipped_ir`; every model of :data:`build_native.MODELS` and the
co-simulation master, :data:`SHIPPED`, by default); ``--check`` only says which archives are stale (exit status 1 if any).
"""
from __future__ import annotations

import argparse

from ..cosim.native_master import MASTER
from .build_native import MODELS
from .kernel_ir import kernel_digest, shipped_key, write_shipped_ir

SHIPPED = {**MODELS, MASTER.name: MASTER}   # the native FMUs' kernels and the co-simulation master's


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m wearjoint.fmu.ship_ir", description=__doc__.splitlines()[0])
    parser.add_argument("models", nargs="*", metavar="MODEL", help=f"of {', '.join(SHIPPED)} (default: all)")
    parser.add_argument("--check", action="store_true", help="write nothing; exit 1 if an archive is stale")
    args = parser.parse_args(argv)
    unknown = [name for name in args.models if name not in SHIPPED]
    if unknown:
        parser.error(f"MODEL={unknown[0]!r} is invalid: allowed one of {', '.join(SHIPPED)}")
    stale = 0
    for name in args.models or SHIPPED:
        spec = SHIPPED[name]
        current = shipped_key(spec).get("digest") == kernel_digest(spec)
        if args.check:
            print(f"{name}: {'current' if current else 'stale'}")
            stale += not current
        else:
            print(f"{name}: {write_shipped_ir(spec)}")
    return 1 if stale else 0


if __name__ == "__main__":
    raise SystemExit(main())
