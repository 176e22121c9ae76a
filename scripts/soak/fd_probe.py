"""A pytest plugin of the soak (scripts/soak/soak.py): counts this process's open file descriptors
after its first test item and at the end of its session, into ``$SOAK_FD_DIR/<worker>.json``."""

from __future__ import annotations

import json
import os
from pathlib import Path

_first: int | None = None


def _open_fds() -> int:
    return len(os.listdir("/proc/self/fd")) - 1  # the listing's own descriptor


def pytest_runtest_logfinish(nodeid: str, location: object) -> None:
    global _first
    if _first is None:
        _first = _open_fds()


def pytest_sessionfinish(session: object, exitstatus: int) -> None:
    directory = os.environ.get("SOAK_FD_DIR")
    worker = os.environ.get("PYTEST_XDIST_WORKER")
    if not directory or worker is None or _first is None:  # the controller runs no item
        return
    Path(directory, f"{worker}.json").write_text(json.dumps({"worker": worker, "first": _first, "end": _open_fds()}))
