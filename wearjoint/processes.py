"""Whether another process still runs: the sweep's orphaned case folders and the ahead-of-time builds' markers
(:mod:`wearjoint._compile.concurrent_builds`) are told apart from live ones by their process's id."""
from __future__ import annotations

import os


def process_alive(pid: int) -> bool:
    """Whether process ``pid`` exists (POSIX: signal 0 tests it and sends nothing; elsewhere it is taken as alive)."""
    if os.name != "posix":
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:                                  # another user's process
        return True
    return True
