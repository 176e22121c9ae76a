"""What the user is told while something slow runs before the first result (a middleware build,
a wait on another process's build, a warm start server starting, a system capture of many
processes): one line when it starts (what, why, where its log is), progress lines while it
lasts, one line when it ends.

The run layer only says the lines; the front end decides where they go (:func:`set_sink`): the
command line prints them to stderr (the default), the pytest plugin writes them on the terminal
past its output capture. Nothing here waits or sleeps: a step that finishes quickly says its two
lines and that is all; a :class:`LateStep` (work that is often quick and sometimes not) says
nothing unless it lasts.
"""

from __future__ import annotations

import os
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager

PREFIX = "rmw-introspect: "

Sink = Callable[[str], None]


def _stderr(line: str) -> None:
    try:
        sys.stderr.write(PREFIX + line + "\n")
        sys.stderr.flush()
    except (OSError, ValueError):  # a closed stderr (a daemonised caller): nobody to tell
        pass


_sink: Sink = _stderr
#: the run this process is one worker of (pytest-xdist's test run id), or None: see :func:`say_once`
_scope: str | None = None


def set_sink(sink: Sink | None) -> Sink:
    """Send the lines to ``sink`` (None: back to stderr); returns the sink it replaces."""
    global _sink
    previous = _sink
    _sink = sink or _stderr
    return previous


def say(line: str) -> None:
    """Tell the user ``line`` (one line, no prefix: the sink adds what its front end needs)."""
    _sink(line)


def set_scope(scope: str | None) -> None:
    """This process is one of several workers of one run (``scope`` names the run): a line said
    with :func:`say_once` is said by one of them only."""
    global _scope
    _scope = scope


def scope() -> str | None:
    """The run this process is a worker of (:func:`set_scope`), or None."""
    return _scope


def say_once(key: str, line: str) -> bool:
    """Say ``line`` unless another worker of this run said the line of ``key`` already (workers
    of one pytest-xdist run wait for the same build: the user is told once). True if said."""
    if _scope is not None:
        mark = os.path.join(tempfile.gettempdir(), f"rmw-introspect-said-{_scope}-{key}")
        try:
            os.close(os.open(mark, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o600))
        except FileExistsError:
            return False
        except OSError:
            pass  # cannot mark it: saying it twice is better than not at all
    say(line)
    return True


def seconds(elapsed: float) -> str:
    """``elapsed`` as people read it: ``0.4 s``, ``12 s``."""
    return f"{elapsed:.1f} s" if elapsed < 10 else f"{elapsed:.0f} s"


@contextmanager
def step(start: str, done: str, failed: str) -> Iterator[Callable[[], float]]:
    """Say ``start`` now and, when the block ends, ``done`` (``{time}`` in it: the time it took)
    or, when it raised, ``failed`` and the time. The block gets a function that returns the
    seconds so far (for its progress lines)."""
    began = time.monotonic()

    def elapsed() -> float:
        return time.monotonic() - began

    say(start)
    try:
        yield elapsed
    except BaseException:
        say(f"{failed} after {seconds(elapsed())}")
        raise
    say(done.format(time=seconds(elapsed())))


class Throttle:
    """Lets a progress line through at most every ``every`` seconds (the first after ``every``)."""

    def __init__(self, every: float) -> None:
        self.every = every
        self._next = time.monotonic() + every

    def due(self) -> bool:
        now = time.monotonic()
        if now < self._next:
            return False
        self._next = now + self.every
        return True


class LateStep:
    """A step said only if it lasts: its start line at the first :meth:`tick` ``after`` seconds
    or more after it began, then a progress line at most every ``every`` seconds, and its end line
    (:meth:`end`) only if the start was said. The owner calls :meth:`tick` while it waits (its
    waits bounded by :meth:`wait_for`) and :meth:`end` when the work ended or failed."""

    def __init__(self, start: str, done: str, failed: str, *, after: float, every: float) -> None:
        self.start, self.done, self.failed = start, done, failed
        self.began = time.monotonic()
        self.after, self.every = after, every
        self.said = False
        self._throttle = Throttle(every)

    def elapsed(self) -> float:
        return time.monotonic() - self.began

    def wait_for(self) -> float:
        """How long the owner may wait before its next :meth:`tick` (the start line's moment)."""
        return max(0.05, self.after - self.elapsed() if not self.said else self.every)

    def tick(self, progress_line: str) -> None:
        """Say the start line once the step has lasted ``after`` seconds; after that, every
        ``every`` seconds, ``progress_line`` (how far the work got now)."""
        if not self.said:
            if self.elapsed() >= self.after:
                self.said = True
                say(self.start)
            return
        if self._throttle.due():
            say(progress_line)

    def end(self, *, ok: bool) -> None:
        if not self.said:
            return
        if ok:
            say(self.done.format(time=seconds(self.elapsed())))
        else:
            say(f"{self.failed} after {seconds(self.elapsed())}")
