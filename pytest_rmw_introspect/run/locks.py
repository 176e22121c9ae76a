"""File locks that say who holds them: the golden-write locks. (The middleware's build lock,
``run/middleware._build_lock``, is its own: its holder also writes the run it belongs to, so that
xdist workers of one run say a wait once; it bounds its wait the same way.)

A lock is an ``flock`` (filelock): the kernel releases it when its holder dies, so a holder that
was killed never blocks anyone. A holder that is alive but stopped (SIGSTOP, a suspended shell
job) or hung holds it for ever: every wait for a lock therefore has a timeout, and the holder
writes its pid beside the lock (``<lock>.pid``) so that a wait that times out can name it and
its state.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator
from pathlib import Path

from .process import process_state


class LockTimeout(Exception):
    """The lock was not free within the timeout; ``holder``: who holds it, for people."""

    def __init__(self, path: Path, timeout: float, holder: str) -> None:
        self.path, self.timeout, self.holder = path, timeout, holder
        super().__init__(f"{path} was held for over {timeout:g} s by {holder}")


def holder_of(path: Path) -> str:
    """The process that last took the lock at ``path``: ``pid 123, T (stopped)``."""
    try:
        pid = int(path.with_name(path.name + ".pid").read_text().strip())
    except (OSError, ValueError):
        return "a process that did not write its pid"
    return f"pid {pid}, {process_state(pid)}"


@contextlib.contextmanager
def held(path: Path, timeout: float) -> Iterator[None]:
    """Hold the lock at ``path``, waiting at most ``timeout`` seconds (LockTimeout)."""
    from filelock import FileLock, Timeout

    try:
        lock = FileLock(str(path), timeout=timeout)
        lock.acquire()
    except Timeout:
        raise LockTimeout(path, timeout, holder_of(path)) from None
    try:
        with contextlib.suppress(OSError):
            path.with_name(path.name + ".pid").write_text(f"{os.getpid()}\n")
        yield
    finally:
        lock.release()
