"""File locks that say who holds them: the golden-write locks and the middleware's build lock.

A lock is an ``flock`` (filelock): the kernel releases it when its holder dies, so a holder that
was killed never blocks anyone. A holder that is alive but stopped (SIGSTOP, a suspended shell
job) or hung holds it for ever: every wait for a lock therefore has a timeout, and the holder
writes its pid beside the lock (``<lock>.pid``: the pid, then the holder's extra info, such as
the run a middleware builder belongs to) so that a waiter can name it: in a wait that times out
(:class:`LockTimeout`), and in what a ``waiting`` callback says while it waits.
"""

from __future__ import annotations

import contextlib
import os
import time
from collections.abc import Callable, Iterator
from contextlib import AbstractContextManager
from dataclasses import dataclass
from pathlib import Path

from ..errors import LockTimeout
from .process import process_state

#: seconds on a lock before a ``waiting`` callback is told who holds it
NOTICE_AFTER = 1.0


@dataclass(frozen=True)
class Holder:
    """The process that holds (or last took) a lock, from its ``<lock>.pid`` file."""

    pid: int | None  #: None: the file is missing or unreadable
    info: str = ""  #: what the holder wrote after its pid ("" when nothing)

    def __str__(self) -> str:
        """For people: ``pid 123, T (stopped)``."""
        if self.pid is None:
            return "a process that did not write its pid"
        return f"pid {self.pid}, {process_state(self.pid)}"


def holder_file(path: Path) -> Path:
    """Where the holder of the lock at ``path`` writes its pid and info."""
    return path.with_name(path.name + ".pid")


def holder(path: Path) -> Holder:
    """The process that holds (or last took) the lock at ``path``."""
    try:
        pid, _, info = holder_file(path).read_text(encoding="ascii").strip().partition(" ")
        return Holder(int(pid), info.strip())
    except (OSError, ValueError, UnicodeDecodeError):
        return Holder(None)


def holder_of(path: Path) -> str:
    """The process that last took the lock at ``path``: ``pid 123, T (stopped)``."""
    return str(holder(path))


@contextlib.contextmanager
def held(path: Path, timeout: float, *, info: str = "",
         waiting: Callable[[Holder], AbstractContextManager[object]] | None = None,
         notice_after: float = NOTICE_AFTER) -> Iterator[None]:
    """Hold the lock at ``path``, waiting at most ``timeout`` seconds (else LockTimeout, naming
    the holder). While it is held, ``<lock>.pid`` says ``<pid> <info>``.

    ``waiting``: when the lock is not free within ``notice_after`` seconds, the rest of the wait
    runs inside ``waiting(holder)`` (a context manager: say that and whom it waits for on entry,
    that the wait ended on a normal exit; the LockTimeout passes through it)."""
    from filelock import FileLock, Timeout

    lock = FileLock(str(path))
    try:
        if waiting is None:
            lock.acquire(timeout=timeout)
        else:
            began = time.monotonic()
            try:
                lock.acquire(timeout=min(notice_after, timeout))
            except Timeout:
                with waiting(holder(path)):
                    lock.acquire(timeout=max(0.0, timeout - (time.monotonic() - began)))
    except Timeout:
        found = holder(path)
        raise LockTimeout(path, timeout, str(found), found.pid) from None
    pid_file = holder_file(path)
    try:
        with contextlib.suppress(OSError):
            pid_file.write_text(f"{os.getpid()} {info}".rstrip() + "\n")
        yield
    finally:
        with contextlib.suppress(OSError):
            pid_file.unlink(missing_ok=True)
        lock.release()
