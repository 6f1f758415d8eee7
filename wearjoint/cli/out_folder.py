"""The results folder a command writes (``--out``), checked before the command runs: a run that would finish and
then fail to write its results, or write them over another command's, is refused first with one line."""
from __future__ import annotations

import json
import shlex
from pathlib import Path

from ..checks import ParameterError

# the commands that write a results folder, and those that write their files into any folder (--out)
RESULT_COMMANDS = ("simulate", "cosim", "validate", "wear-study", "calibrate", "cosim-study", "sweep", "sensitivity",
                   "contact-law")
FILE_COMMANDS = ("build-fmu", "export-ssp")
# the folders a command writes into although another command's results are there: calibrate's, into the study it fits
SHARED_FOLDERS = {"calibrate": ("wear-study",)}
# a command's results without a summary recording its command line (written by the command itself, or a run stopped
# before its summary): the files that mark them, the first found (a sensitivity run's sweep.json beside its samples)
MARKER_FILES = {"cosim_study.json": "cosim-study", "contact_law.json": "contact-law", "calibration.json": "calibrate",
                "wear_study_checkpoint.pkl": "wear-study", "samples.csv": "sensitivity", "sweep.json": "sweep"}


def _refuse(out, allowed: str, option: str | None) -> None:
    raise ParameterError(f"{option or 'parameter out'}={str(out)!r} is invalid: allowed {allowed}")


def results_commands(folder: Path) -> tuple[str, ...]:
    """The wearjoint commands whose results ``folder`` may hold: its summary's ``command_line``'s, else that of the
    first marker file of MARKER_FILES (a sweep.json of the ``wear-study`` it sweeps: a ``wear-study --seeds``
    ensemble's too), else none."""
    from ..report import SUMMARY_FILES

    for name in SUMMARY_FILES:
        try:
            words = shlex.split(json.loads((folder / name).read_text()).get("command_line") or "")
        except (OSError, ValueError, AttributeError):
            continue
        if len(words) >= 2 and words[0] == "wearjoint":
            return (words[1],)
    command = next((command for name, command in MARKER_FILES.items() if (folder / name).exists()), None)
    if command != "sweep":
        return () if command is None else (command,)
    try:
        swept = json.loads((folder / "sweep.json").read_text()).get("command")
    except (OSError, ValueError, AttributeError):
        swept = None
    return ("sweep", "wear-study") if swept == "wear-study" else ("sweep",)


def prepare_out_folder(command: str, out, option: str | None = None) -> list[Path]:
    """Make the output folder ``out`` of ``command`` (its missing parents too) and return the folders made, after
    checking that it is a folder that can be made and, for a command of RESULT_COMMANDS, that it holds no other
    command's results (a command writes over its own earlier results).  ParameterError (``--out``; ``option``:
    named so, where the message cannot be traced to the option) otherwise, nothing made."""
    folder = Path(out)
    if folder.exists() and not folder.is_dir():
        _refuse(out, "a folder (made if missing): it is a file", option)
    if folder.is_dir() and command in RESULT_COMMANDS:
        owners = results_commands(folder)
        if owners and not set(owners) & {command, *SHARED_FOLDERS.get(command, ())}:
            _refuse(out, f"an empty folder or one of `wearjoint {command}`'s results: it holds the results of "
                         f"`wearjoint {owners[0]}` (choose another --out)", option)
    if folder.is_dir():
        return []
    missing = []
    parent = folder
    while not parent.exists():
        missing.append(parent)
        parent = parent.parent
    if not parent.is_dir():
        _refuse(out, f"a folder that can be made: {str(parent)!r} is a file", option)
    for path in reversed(missing):
        try:
            path.mkdir()
        except OSError as exc:
            remove_empty_folders(missing[missing.index(path) + 1:])
            _refuse(out, f"a folder that can be made: {exc.strerror or exc} ({str(path)!r})", option)
    return missing


def remove_empty_folders(folders: list[Path]) -> None:
    """Remove the folders :func:`prepare_out_folder` made (innermost first) that are still empty: a run refused
    before writing leaves nothing behind."""
    for path in folders:
        try:
            path.rmdir()
        except OSError:
            return


__all__ = ["FILE_COMMANDS", "RESULT_COMMANDS", "prepare_out_folder", "remove_empty_folders", "results_commands"]
