"""What of a wear study (:mod:`wearjoint.studies.wear_study`) survives a kill or a divergence.

* **Checkpoints** (``wear_study_checkpoint.pkl``): the study's state pickled, then its CRC-32C, written
  atomically (tmp + rename).  ``--resume`` reads the last one; it may change the study's *numerical*
  settings (:data:`NUMERICAL`: integrator, max step, DOPRI's rtol, the cycle-jump tolerance and block, the
  checkpoint interval; the command takes the checkpoint's where its options leave them out) but not its *physical* ones (mechanism, joint, wear law and factor, horizon and snapshots,
  engine), which it refuses in one line naming the parameter, the checkpointed and the given value.
  ``numerical_settings`` in the checkpoint and summary.json says which settings covered which revolutions.
* **Snapshots as they are reached**: ``profile_revR.csv`` (the profile) and ``snapshots.json`` (every
  snapshot's summary entry so far, the study's status and its numerical settings), each written atomically
  (the Fig. 8 samples of each snapshot are in the checkpoint).
* **A diverged study** ends with :class:`StudyDiverged`, whose one-line message names the revolution and
  time reached, the last good checkpoint and what to try (:func:`diverged_message`).
"""
from __future__ import annotations

import json
import os
import pickle
import re
from pathlib import Path

import numpy as np

from wearjoint.core import state_format
from wearjoint.joint import ClearanceJoint, StateError
from wearjoint.mechanism_parameters import same_setting
from wearjoint.parameters import ParameterError
from wearjoint.results import write_json_atomic
from wearjoint.checks import RunDiverged
from wearjoint.simulate import SimulationOptions

CHECKPOINT_NAME = "wear_study_checkpoint.pkl"
CHECKPOINT_FORMAT = 3                   # the pickle, then its CRC-32C (uint32, little-endian); 3: + numerical_settings
READABLE_FORMATS = (2, 3)               # 2: as 3 without numerical_settings (one segment: its own settings)
SNAPSHOTS_NAME = "snapshots.json"
ARRAY_KEYS = ("wear_depth_m", "time_s", "slider_a_m_s2", "samples")   # snapshot arrays (not in the JSON files)
# the settings a resumed study may change: how the answer is computed, not what is computed
NUMERICAL = ("integrator", "max_step_s", "rtol", "jump_tolerance", "jump_block_revolutions",
             "checkpoint_every_revolutions")
SEGMENT_KEYS = ("integrator", "max_step_s", "rtol", "jump_tolerance", "jump_block_revolutions")   # per segment
DERIVED = ("revolutions_per_simulated_revolution",)
# what a resumed study may change freely: what its summary states of the answer, not the answer
STATED = ("life_depth_m",)
OPTIONS = {"revolutions": "--revolutions", "snapshots": "--snapshots", "engine": "--engine",
           "integrator": "--integrator", "max_step_s": "--max-step", "rtol": "--rtol",
           "jump_tolerance": "--cycle-jump-tolerance",
           "jump_block_revolutions": "--cycle-jump-block", "checkpoint_every_revolutions": "--checkpoint-every",
           "impact_threshold_m_s2": "--impact-threshold-m-s2", "fmu_backend": "--fmu-backend",
           "life_depth_m": "--life-depth-m"}


class StudyDiverged(RunDiverged):
    """A wear study that diverged: its outputs for what finished are written (``summary``: summary.json's
    content, ``"status": "diverged"``); the message is :func:`diverged_message`'s."""

    def __init__(self, message: str, summary: dict):
        super().__init__(message)
        self.summary = summary


def option_name(key: str, group: str | None = None) -> str:
    """A study setting as the command line writes it, with its API name: ``--max-step (max_step_s)``."""
    option = "--" + key.replace("_", "-") if group else OPTIONS.get(key)
    api = f"{group}.{key}" if group else key
    return f"{option} ({api})" if option else api


# ----------------------------------------------------------------------------- checkpoints
def crc32c(data: bytes) -> int:
    return int(state_format.crc32c(np.frombuffer(data, dtype=np.uint8), len(data)))


def _replace_atomic(path: Path, write) -> None:
    """``write(file)`` into path + '.tmp' (binary), flushed and synced, then renamed over ``path``."""
    tmp = path.with_name(path.name + ".tmp")
    with open(tmp, "wb") as f:
        write(f)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def write_checkpoint_atomic(path: Path, state: dict) -> None:
    """The study's state pickled, then the CRC-32C of the pickle (the state format's checksum)."""
    data = pickle.dumps(state, protocol=pickle.HIGHEST_PROTOCOL)
    _replace_atomic(path, lambda f: f.write(data + crc32c(data).to_bytes(4, "little")))


def read_checkpoint(path: Path) -> dict:
    """The state in the checkpoint at ``path`` (checksum and format checked, not the settings)."""
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise ParameterError(f"cannot read checkpoint {path}: {exc}") from None
    stored, computed = int.from_bytes(data[-4:], "little"), crc32c(data[:-4])
    if len(data) < 4 or stored != computed:
        raise StateError(f"checkpoint {path}: its CRC-32C is 0x{stored:08x}, its {max(len(data) - 4, 0)} bytes "
                         f"give 0x{computed:08x}: the file is corrupted or not a wear-study checkpoint")
    try:
        state = pickle.loads(data[:-4])
    except (pickle.UnpicklingError, EOFError, ValueError, TypeError, AttributeError) as exc:
        raise ParameterError(f"cannot read checkpoint {path}: {exc}") from None
    found = state.get("format") if isinstance(state, dict) else None
    if found not in READABLE_FORMATS:
        raise ParameterError(f"checkpoint {path} has format {found!r}, this version reads "
                             f"{', '.join(map(str, READABLE_FORMATS))}")
    if "numerical_settings" not in state:       # format 2: its own settings covered what it did (DOPRI at 1e-6)
        state["config"].setdefault("rtol", SimulationOptions.rtol)
        state["numerical_settings"] = [segment(state["config"], 0.0, checkpoint_revolution(state))]
        state["format"] = CHECKPOINT_FORMAT
    return state


def load_checkpoint(path: Path, config) -> tuple[dict, list]:
    """(state, the numerical settings ``config`` changes, by name) of the checkpoint at ``path``, to continue with
    ``config``; ParameterError naming the failed check (checksum, format, a physical setting changed, a
    wear profile out of range).  The engine's state is checked when the engine restores it."""
    state = read_checkpoint(path)
    changed = settings_changes(state["config"], config.to_dict(), path)
    probe = ClearanceJoint(config.joint)
    for s in state["snapshots"]:
        try:
            probe.set_wear_profile(s["wear_depth_m"])
        except StateError as exc:
            raise StateError(f"checkpoint {path}: snapshot {s['revolution']} wear_depth_m: {exc}") from None
    return state, changed


def quartile_snapshots(revolutions: int) -> tuple:
    """The snapshots of a study of ``revolutions`` whose ``--snapshots`` was left out: its quarters."""
    return tuple(sorted({max(1, revolutions * q // 4) for q in (1, 2, 3, 4)}))


def _following(old: dict, new: dict) -> tuple:
    """The joint's fields that follow each study's mechanism (its offsets and effective mass, left to it in both):
    a change of the mechanism names the mechanism's option, not these."""
    from ..mechanism_parameters import SliderCrankParameters

    try:
        derived = [SliderCrankParameters.from_dict(settings["mechanism"]).joint_defaults() for settings in (old, new)]
    except (KeyError, TypeError, ValueError):
        return ()
    return tuple(k for k in derived[1] if all(json.loads(json.dumps(d[k])) == settings.get("joint", {}).get(k)
                                             for d, settings in zip(derived, (old, new))))


def settings_changes(old: dict, new: dict, path: Path) -> list:
    """The numerical settings (:data:`NUMERICAL`) that differ between the checkpointed study's settings
    ``old`` and ``new`` (their names); ParameterError for any other difference (the first named, with both
    values).  The FMU backend of a monolithic study is no setting of it."""
    physical, numerical = [], []
    for key in sorted(new, key=lambda k: ("mechanism", "joint").index(k) if k in ("mechanism", "joint") else 2):
        value = new[key]            # the mechanism first: the joint's offsets follow its lengths
        if key in DERIVED or key in STATED or (key == "fmu_backend" and new.get("engine") != "cosim"):
            continue
        if key in ("joint", "mechanism"):
            before = old.get(key, {})
            follow = _following(old, new) if key == "joint" else ()
            physical += [(option_name(k, key), before.get(k), v) for k, v in value.items()
                         if not same_setting(k, before.get(k), v) and k not in follow]
        elif old.get(key) != value:
            if (key == "snapshots" and old.get("revolutions") != new["revolutions"]
                    and value == list(quartile_snapshots(new["revolutions"]))):
                continue                                # the quarters of a changed --revolutions: named there
            if key == "jump_tolerance" and (old.get(key) is None) != (value is None):    # the route itself
                physical.append((option_name(key) + " (None: the wear-factor route)", old.get(key), value))
            else:
                (numerical if key in NUMERICAL else physical).append((option_name(key), old.get(key), value, key))
    if physical:
        name, before, given = physical[0][:3]
        more = f" (also changed: {', '.join(p[0] for p in physical[1:])})" if len(physical) > 1 else ""
        allowed = ", ".join(OPTIONS[k] for k in NUMERICAL)
        raise ParameterError(f"cannot resume the study checkpointed in {path.parent}: parameter {name} is "
                             f"{_show(before)} in its checkpoint, {_show(given)} given{more}; a resumed study may "
                             f"change only its numerical settings ({allowed}): use the same value or another --out")
    if numerical and new.get("engine") == "cosim":
        raise ParameterError(f"cannot resume the study checkpointed in {path.parent} with other numerical settings "
                             f"({', '.join(n[0] for n in numerical)}) through --engine cosim: its FMU state holds "
                             "the step; use the checkpointed settings")
    return [n[3] for n in numerical]


def _show(value) -> str:
    return repr(tuple(value)) if isinstance(value, list) else repr(value)


# ----------------------------------------------------------------------------- which settings covered what
def segment(config_dict: dict, first: float, last: float) -> dict:
    return {"from_revolution": first, "to_revolution": last, **{k: config_dict.get(k) for k in SEGMENT_KEYS}}


def checkpoint_revolution(state: dict) -> float:
    """The crank revolution a study's state has reached at its last checkpoint."""
    if "jump" in state:
        return float(state["jump"]["revolution"])
    return float(state["last_checkpoint_revolution"] * state["config"]["revolutions_per_simulated_revolution"])


def continue_segments(state: dict, config_dict: dict) -> None:
    """Open a new segment of numerical settings where the state stands if ``config_dict``'s differ from the
    last segment's (a resume with other settings); the first segment for a new state."""
    segments = state.setdefault("numerical_settings", [])
    here = checkpoint_revolution(state) if segments else 0.0
    if not segments or any(segments[-1][k] != config_dict.get(k) for k in SEGMENT_KEYS):
        if segments:
            segments[-1]["to_revolution"] = here
        segments.append(segment(config_dict, here, here))


def extend_segment(state: dict, revolution: float) -> None:
    state["numerical_settings"][-1]["to_revolution"] = float(revolution)


# ----------------------------------------------------------------------------- snapshots as they are reached
def snapshot_entry(snapshot: dict) -> dict:
    """A snapshot's summary entry (without its arrays)."""
    return {k: v for k, v in snapshot.items() if k not in ARRAY_KEYS}


def write_profile_csv(path: Path, phi_deg: np.ndarray, depth: np.ndarray) -> None:
    _replace_atomic(path, lambda f: np.savetxt(f, np.column_stack([phi_deg, depth]), delimiter=",",
                                               header="phi_deg,wear_depth_m", comments="", fmt="%.17g"))


def write_snapshot(out: Path, phi_deg: np.ndarray, snapshot: dict) -> None:
    """One snapshot's profile file: profile_revR.csv."""
    write_profile_csv(out / f"profile_rev{snapshot['revolution']}.csv", phi_deg, snapshot["wear_depth_m"])


def write_snapshot_index(out: Path, config, state: dict, status: str, **extra) -> None:
    """snapshots.json: the status ("running", "finished", "diverged"), every snapshot's entry so far and
    the numerical settings of each stretch of revolutions."""
    index = {"status": status, "revolutions": config.revolutions, "snapshots_planned": list(config.snapshots),
             "snapshots": [snapshot_entry(s) for s in state["snapshots"]],
             "numerical_settings": state.get("numerical_settings", []), "checkpoint": CHECKPOINT_NAME, **extra}
    write_json_atomic(out / SNAPSHOTS_NAME, index)


# ----------------------------------------------------------------------------- divergence
def divergence_reason(message: str) -> str:
    """The reason of :func:`wearjoint.runner.divergence`'s message (the whole message otherwise)."""
    found = re.match(r"the run diverged by t = [^:]+: (.*?); nothing after this is physical", message)
    return found.group(1) if found else re.sub(r" \(lower [^)]*\)$", "", message)   # (the advice: said after)


def diverged_message(config, out: Path, reached_revolution: float, reached_time_s: float, reason: str,
                     last_good: float | None) -> str:
    """One line: where the study diverged, why, its last good checkpoint, what is written and what to try."""
    checkpoint = (f"the last good checkpoint is at revolution {last_good:.6g} ({out / CHECKPOINT_NAME})"
                  if last_good is not None else "no checkpoint was reached")
    worn = "wore through" in reason
    if worn:
        advice = "a resume cannot help: lower --wear-coefficient-m2-N" + (
            ", --wear-factor" if config.jump_tolerance is None and config.joint.wear_factor > 1 else "") + \
            " or --revolutions"
    else:
        smaller = f"--max-step {config.max_step_s / 2:.3g}"
        what = (f"--integrator dopri or {smaller}" if config.integrator == "rk4" else smaller)
        advice = (f"continue from it with --resume and {what}" if last_good is not None else
                  f"run it again with {what}") + (" (or a new study with a smaller --wear-factor)"
                                                   if config.jump_tolerance is None and config.joint.wear_factor > 1
                                                   else "")
    return (f"the wear study {'stopped' if worn else 'diverged'} at revolution {reached_revolution:.6g} of "
            f"{config.revolutions} (simulated time {reached_time_s:.6g} s, {config.integrator} at max step "
            f"{config.max_step_s:.3g} s): {reason}; {checkpoint}; the snapshots reached and summary.json "
            f"(\"status\": \"{'worn through' if worn else 'diverged'}\") are written in {out}; {advice}")


__all__ = ["CHECKPOINT_NAME", "CHECKPOINT_FORMAT", "SNAPSHOTS_NAME", "NUMERICAL", "StudyDiverged", "crc32c",
           "write_checkpoint_atomic", "read_checkpoint", "load_checkpoint", "settings_changes",
           "continue_segments", "extend_segment", "checkpoint_revolution", "write_snapshot", "write_snapshot_index",
           "write_profile_csv", "snapshot_entry", "divergence_reason", "diverged_message"]
