"""Ahead-of-time builds that run at once share the cores: each running build leaves a marker in the user's cache,
so that a build's compile notice gives the time the builds running together take.

A change to the kernels rebuilds the joint FMU's and the master's (a cold `cosim`): the FMU in a second process, the
master in the first, each in two processes of its own.  Their notices gave each its reference alone (18 s, 13 s)
where they took 35 s and 29 s side by side (with the markers, 37 s and 30 s); the sum of the references, 32 s, is
within 16 % of each.
"""
from __future__ import annotations

import contextlib
import os
from pathlib import Path

from ..processes import process_alive
from .user_cache import user_cache_dir


def _folder() -> Path:
    return user_cache_dir() / "building"


@contextlib.contextmanager
def running(key: str):
    """Marks the ahead-of-time build ``key`` (:data:`.notice.AHEAD_OF_TIME`) running in this process while the block
    runs (nothing where the cache cannot be written)."""
    marker = _folder() / f"{key}.{os.getpid()}"
    try:
        marker.parent.mkdir(parents=True, exist_ok=True)
        marker.touch()
    except OSError:
        marker = None
    try:
        yield
    finally:
        if marker is not None:
            marker.unlink(missing_ok=True)


def others(key: str) -> list[str]:
    """The keys of the ahead-of-time builds running now besides this process's ``key``: markers of live processes
    (a dead one's marker, a build that was killed, is removed).  None off POSIX, where a process's life is not
    tested (:func:`~wearjoint.processes.process_alive`)."""
    if os.name != "posix":
        return []
    try:
        markers = sorted(_folder().iterdir())
    except OSError:
        return []
    found = []
    for marker in markers:
        build, _, pid = marker.name.rpartition(".")
        if not pid.isdigit() or (build == key and int(pid) == os.getpid()):
            continue
        if process_alive(int(pid)):
            found.append(build)
        else:
            marker.unlink(missing_ok=True)
    return found
