"""``wearjoint report DIR``: (re)write the results folder's report.html (:mod:`wearjoint.report`)."""
from __future__ import annotations

import sys

from ..checks import path as path_argument
from ..report import write_report


def add_arguments(p) -> None:
    p.add_argument("folder", type=path_argument, help="a results folder (summary.json or sweep_summary.json, PNGs)")


def run(args) -> int:
    """Exit status 0, or 2 with one line naming the folder or its summary file when there is none or it is not a
    JSON object."""
    if not args.folder.is_dir():
        print(f"wearjoint report: error: FOLDER={str(args.folder)!r} is invalid: "
              f"{'it is a file' if args.folder.exists() else 'no such folder'}; allowed a results folder "
              "(summary.json or sweep_summary.json, PNGs)", file=sys.stderr)
        return 2
    try:
        page = write_report(args.folder)
    except (FileNotFoundError, ValueError) as exc:
        print(f"wearjoint report: error: {exc}", file=sys.stderr)
        return 2
    print(f"report in {page}")
    return 0


__all__ = ["add_arguments", "run"]
