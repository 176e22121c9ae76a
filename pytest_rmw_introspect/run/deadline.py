"""The runner's overall deadline: no capture waits silently, whatever it waits for.

Every blocking wait of a capture has a bound of its own (the target's ``timeout``, the stop
graces, the warm start server's answers, the build and golden-write locks: docs/troubleshooting.md,
"A capture that hangs"). This is the last resort behind them, for a wait nobody bounded: a
:class:`Watchdog` armed for the target's ``timeout`` plus :data:`SLACK_S` that, when it expires,
writes what the capture was waiting for, the target's state (``/proc/<pid>/stat``: running,
sleeping, stopped, in uninterruptible sleep, and where in the kernel) and every thread's stack
(``faulthandler``) to stderr, kills the target's process group and ends the process with status 2.
A capture that hangs is a bug of this package: the output is what its report needs.

The runner names each wait as it enters it (:meth:`Watchdog.waiting`), so the message says
"waiting for the warm start server to report its child's end", not just "timed out".
"""

from __future__ import annotations

import contextlib
import faulthandler
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator

from .process import process_state

#: seconds a capture may run beyond its target's ``timeout`` before the watchdog ends the process:
#: stopping the target (SIGINT, SIGTERM and SIGKILL graces: 3 s), reading its capture, a warm start
#: server's answers (each bounded by a few seconds) fit in it many times over
SLACK_S = 30.0
#: the environment variable that overrides SLACK_S (seconds; the tests provoke the watchdog with it)
SLACK_ENV = "RMW_INTROSPECT_RUNNER_SLACK_S"
#: the exit status of a process whose capture passed its deadline (a failure of the tool, as a
#: user error is: docs/cli.md)
EXIT_STATUS = 2


def slack() -> float:
    """The slack in force (:data:`SLACK_ENV`, else :data:`SLACK_S`)."""
    try:
        value = float(os.environ.get(SLACK_ENV, ""))
    except ValueError:
        return SLACK_S
    return value if value >= 0 else SLACK_S


class Watchdog:
    """Ends the process (status 2, with every thread's stack) if the capture of ``target`` is not
    done ``seconds`` after :meth:`start`. ``on_expiry`` runs first (kill the target's group)."""

    def __init__(self, target: str, seconds: float, *, timeout: float,
                 on_expiry: Callable[[], None] | None = None) -> None:
        self.target = target
        self.seconds = seconds
        self.timeout = timeout
        self.pid: int | None = None  # the target's, once started
        self._on_expiry = on_expiry
        self._waiting_for = "nothing yet (setting up)"
        self._since = time.monotonic()
        self._timer: threading.Timer | None = None

    @classmethod
    def for_target(cls, target: str, timeout: float, on_expiry: Callable[[], None] | None = None) -> Watchdog:
        """A watchdog for a target with ``timeout``: ``timeout`` + :func:`slack` seconds."""
        return cls(target, timeout + slack(), timeout=timeout, on_expiry=on_expiry)

    def start(self) -> Watchdog:
        self._timer = threading.Timer(self.seconds, self.expire)
        self._timer.name = "rmw-introspect watchdog"
        self._timer.daemon = True
        self._timer.start()
        return self

    def cancel(self) -> None:
        if self._timer is not None:
            self._timer.cancel()

    def now(self, what: str) -> None:
        """Name what the capture does from now on."""
        self._waiting_for, self._since = what, time.monotonic()

    @contextlib.contextmanager
    def waiting(self, what: str) -> Iterator[None]:
        """Name the wait the capture enters (restored when it leaves)."""
        before, since = self._waiting_for, self._since
        self._waiting_for, self._since = what, time.monotonic()
        try:
            yield
        finally:
            self._waiting_for, self._since = before, since

    def message(self) -> str:
        waited = time.monotonic() - self._since
        target_state = "not started" if self.pid is None else f"pid {self.pid}, {process_state(self.pid)}"
        return (f"rmw-introspect: error: the capture of {self.target} passed its deadline ({self.timeout:g} s "
                f"timeout + {self.seconds - self.timeout:g} s, {SLACK_ENV}) while waiting for "
                f"{self._waiting_for} (for {waited:.1f} s). The target: {target_state}. This is a bug of "
                "pytest-rmw-introspect, not of your node: please report it with this message and the stacks "
                "below (docs/troubleshooting.md, \"A capture that hangs\"). Every thread's stack:")

    def expire(self) -> None:
        """Write what was waited for and every stack, kill the target's group, exit 2. The stacks
        come first: once the target is killed the runner's threads move on, and the dump would
        show where they went instead of where they waited."""
        text = self.message()
        try:
            try:  # file descriptor 2 itself: under pytest, sys.stderr is a capture buffer
                with contextlib.suppress(Exception):
                    sys.stderr.flush()
                os.write(2, (text + "\n").encode())
                faulthandler.dump_traceback(file=2, all_threads=True)
            finally:
                if self.pid is not None:
                    with contextlib.suppress(OSError):
                        os.killpg(self.pid, signal.SIGKILL)
                if self._on_expiry is not None:
                    with contextlib.suppress(Exception):
                        self._on_expiry()
        finally:
            os._exit(EXIT_STATUS)
