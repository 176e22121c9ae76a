"""The target's process: started in its own process group, tied to the runner's life, its
output kept as a bounded tail, stopped with escalating signals.

* The child gets the parent-death signal SIGKILL (``prctl(PR_SET_PDEATHSIG)``): when the runner
  dies (SIGKILL, a CI job cancelled, an xdist worker killed), a hung target dies with it instead
  of being reparented to init. util-linux's ``setpriv --pdeathsig`` arms it and execs the target
  (same process, same pid) when it is there: the target then starts with vfork and exec, ~0.3 ms,
  where a Python ``preexec_fn`` (the fallback) makes subprocess fork and run Python in the child,
  8-13 ms for a small runner and more for a large one. The fallback also ends a child whose
  runner died before the signal was armed; setpriv leaves that window (the ~1 ms between the
  vfork and its prctl) open.
* stdout and stderr are read by one thread into :class:`OutputTail` buffers of a fixed size: a
  target logging in a loop cannot fill the disk (only the tail is ever shown).
* :func:`stop`: SIGINT, SIGTERM, then SIGKILL to the whole group, with short grace periods. A
  target starts with SIGINT and SIGQUIT at their default action (:data:`DEFAULT_IN_TARGETS`),
  also when the runner ignores them.
* :class:`Process` (what :func:`start` returns) waits with a timeout by being woken the moment the
  target ends (a pidfd), where ``subprocess.Popen.wait(timeout)`` polls with sleeps growing to
  50 ms: a cold capture of a short-lived target ended up to 50 ms after its target did.
"""

from __future__ import annotations

import ctypes
import functools
import os
import select
import selectors
import shutil
import signal
import subprocess
import threading
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import IO, Protocol

from ..errors import NotEnded

#: seconds granted after SIGINT and after SIGTERM before the next, harder signal
SIGINT_GRACE = 2.0
SIGTERM_GRACE = 1.0
#: seconds a process may take to end after SIGKILL: at once, unless it is in uninterruptible sleep
#: (state D) or nobody reaps it (a warm start server that stopped answering); then NotEnded
KILL_WAIT = 5.0
#: bytes of stdout and of stderr kept (the end of each)
TAIL_BYTES = 16_384
_PR_SET_PDEATHSIG = 1
_SIG_DFL = 0
#: the signals every target starts with at their default action: a runner started with `cmd &`
#: by a non-interactive shell (as CI scripts do) ignores SIGINT and SIGQUIT, and an ignored
#: signal is inherited, so each stop (SIGINT first) waited out its grace period (issue 50, N30)
DEFAULT_IN_TARGETS = (signal.SIGINT, signal.SIGQUIT)


def _load_libc() -> ctypes.CDLL | None:
    # glibc's name, else the C library the interpreter itself is linked with (ctypes.util's
    # find_library would cost ~15 ms of imports and an `ldconfig -p` at every start)
    for name in ("libc.so.6", None):
        try:
            return ctypes.CDLL(name, use_errno=True)
        except OSError:
            continue
    return None


_LIBC = _load_libc()


def die_with_parent(parent: int) -> None:
    """Arm the parent-death signal SIGKILL in this process, or end it at once if ``parent`` (the
    process that forked it) is already gone. Runs in a child between fork and exec."""
    if _LIBC is not None:
        _LIBC.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    if os.getppid() != parent:  # the runner died before the signal was armed
        os._exit(1)


class Handle(Protocol):
    """A started target as :func:`stop` and :func:`reap_group` use it: a ``subprocess.Popen`` (cold
    start) or a ``warm.WarmChild`` (forked by a warm start server). ``pid`` is also the id of the
    target's process group."""

    pid: int

    @property
    def returncode(self) -> int | None: ...

    def poll(self) -> int | None: ...

    def wait(self, timeout: float | None = None) -> int: ...

    def send_signal(self, sig: int) -> None: ...


class OutputTail:
    """The last ``limit`` bytes a pipe delivered, read by a daemon thread until EOF (its own, or
    one shared with other pipes: :func:`read_tails`)."""

    def __init__(self, pipe: IO[bytes], limit: int = TAIL_BYTES, *, start: bool = True) -> None:
        self._pipe = pipe
        self._limit = limit
        self._data = bytearray()
        self._total = 0
        self._lock = threading.Lock()
        self._thread: threading.Thread | None = None
        if start:
            self._thread = threading.Thread(target=self._drain, name="rmw-introspect-output", daemon=True)
            self._thread.start()

    def _feed(self, chunk: bytes) -> None:
        with self._lock:
            self._total += len(chunk)
            self._data += chunk
            if len(self._data) > 2 * self._limit:
                del self._data[: len(self._data) - self._limit]

    def _drain(self) -> None:
        fd = self._pipe.fileno()
        try:
            while True:
                chunk = os.read(fd, 65536)
                if not chunk:
                    break
                self._feed(chunk)
        except OSError:
            pass
        finally:
            self._pipe.close()

    def finish(self, timeout: float = 1.0) -> None:
        """Wait (briefly) for EOF: a daemonised grandchild may hold the pipe open for ever."""
        if self._thread is not None:
            self._thread.join(timeout)

    @property
    def total_bytes(self) -> int:
        return self._total

    def text(self) -> str:
        with self._lock:
            data = bytes(self._data[-self._limit:])
        return data.decode("utf-8", errors="replace")

    @classmethod
    def read_together(cls, *pipes: IO[bytes], limit: int = TAIL_BYTES) -> list[OutputTail]:
        """Tails of several pipes (a target's stdout and stderr) read by one daemon thread."""
        tails = [cls(pipe, limit, start=False) for pipe in pipes]
        thread = threading.Thread(target=cls._drain_all, args=(tails,), name="rmw-introspect-output", daemon=True)
        for tail in tails:
            tail._thread = thread
        thread.start()
        return tails

    @staticmethod
    def _drain_all(tails: list[OutputTail]) -> None:
        with selectors.DefaultSelector() as selector:
            for tail in tails:
                selector.register(tail._pipe.fileno(), selectors.EVENT_READ, tail)
            try:
                while selector.get_map():
                    for key, _events in selector.select():
                        try:
                            chunk = os.read(key.fd, 65536)
                        except OSError:
                            chunk = b""
                        if chunk:
                            key.data._feed(chunk)
                        else:
                            selector.unregister(key.fd)
                            key.data._pipe.close()
            finally:
                for key in list(selector.get_map().values()):
                    key.data._pipe.close()


class Process(subprocess.Popen[bytes]):
    """A ``subprocess.Popen`` whose ``wait(timeout)`` returns when the process ends."""

    def wait(self, timeout: float | None = None) -> int:
        if timeout is not None and self.returncode is None and not wait_for_exit(self.pid, timeout):
            raise subprocess.TimeoutExpired(self.args, timeout)
        return super().wait(timeout)  # ended (or not known to be): reaps it, or polls as before


def wait_for_exit(pid: int, timeout: float) -> bool:
    """Wait up to ``timeout`` seconds for the child ``pid`` to end, without reaping it. False when it
    is still running then; True when it ended, or when this cannot be known (no pidfd: an older
    kernel or Python, or the pid was reaped already), so the caller's own wait decides."""
    try:
        fd = os.pidfd_open(pid)
    except (AttributeError, OSError):
        return True
    try:
        poller = select.poll()  # not select.select: a long session's descriptors pass FD_SETSIZE
        poller.register(fd, select.POLLIN)
        return bool(poller.poll(max(0.0, timeout) * 1000))
    finally:
        os.close(fd)


@functools.lru_cache(maxsize=1)
def death_signal_wrapper() -> tuple[str, ...] | None:
    """The command that arms SIGKILL as the parent-death signal and execs the rest of its command
    line (util-linux's ``setpriv``, 2.33 or later), or None where there is none."""
    setpriv = shutil.which("setpriv")
    if setpriv is None:
        return None
    try:
        usage = subprocess.run([setpriv, "--help"], capture_output=True, text=True, timeout=10).stdout
    except (OSError, subprocess.SubprocessError):
        return None
    return (setpriv, "--pdeathsig", "KILL", "--") if "--pdeathsig" in usage else None


def _found(program: str, env: Mapping[str, str]) -> bool:
    """``program`` is an executable file exec finds: an absolute path, or a name on ``PATH``. Any
    other program starts without the wrapper, so that one that cannot start is still an OSError
    of ``start`` (the wrapper itself would start, then fail to exec it)."""
    if os.sep in program:
        return os.path.isabs(program) and os.path.isfile(program) and os.access(program, os.X_OK)
    # relative PATH entries are left out: the child resolves them in its own working directory
    path = os.pathsep.join(d for d in env.get("PATH", os.defpath).split(os.pathsep) if os.path.isabs(d))
    return shutil.which(program, path=path) is not None


def ignored_stop_signals() -> tuple[int, ...]:
    """The signals of :data:`DEFAULT_IN_TARGETS` this process ignores (an ignored signal stays
    ignored across fork and exec)."""
    return tuple(sig for sig in DEFAULT_IN_TARGETS if signal.getsignal(sig) == signal.SIG_IGN)


def _restore_and_die_with_parent(parent: int, ignored: Sequence[int]) -> None:
    """In the child, between fork and exec: ``ignored`` back to their default action (libc's
    signal(): the child may be forked from any thread, where Python's signal.signal refuses),
    then :func:`die_with_parent`."""
    if _LIBC is not None:
        for sig in ignored:
            _LIBC.signal(sig, ctypes.c_void_p(_SIG_DFL))
    die_with_parent(parent)


def start(argv: Sequence[str], *, env: Mapping[str, str], cwd: Path | None) -> Process:
    """Start ``argv`` in a new session (its own process group), stdin closed, output piped, with
    SIGKILL as its parent-death signal and SIGINT and SIGQUIT at their default action even when
    this process ignores them. Raises OSError when it cannot be started."""
    ignored = ignored_stop_signals()
    # setpriv cannot reset a signal: a runner that ignores one starts the target the slower way
    wrapper = death_signal_wrapper() if argv and not ignored and _found(argv[0], env) else None
    return Process(
        [*wrapper, *argv] if wrapper else list(argv),
        env=dict(env),
        cwd=str(cwd) if cwd else None,
        stdin=subprocess.DEVNULL,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        start_new_session=True,
        preexec_fn=None if wrapper else functools.partial(_restore_and_die_with_parent, os.getpid(), ignored),
    )


def _signal_group(proc: Handle, sig: int) -> None:
    try:
        os.killpg(proc.pid, sig)
    except (ProcessLookupError, PermissionError):
        try:
            proc.send_signal(sig)
        except ProcessLookupError:
            pass


def process_state(pid: int) -> str:
    """``pid``'s state as people read it: ``S (sleeping) in do_epoll_wait``, ``T (stopped)``, ``gone``."""
    names = {"R": "running", "S": "sleeping", "D": "uninterruptible sleep", "T": "stopped",
             "t": "stopped by a tracer", "Z": "zombie", "X": "dead", "I": "idle"}
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return "gone"
    state = stat[stat.rfind(")") + 2:].split(" ", 1)[0]
    text = f"{state} ({names.get(state, 'unknown')})"
    try:
        wchan = Path(f"/proc/{pid}/wchan").read_text().strip()
    except OSError:
        wchan = ""
    return f"{text} in {wchan}" if wchan and wchan != "0" else text


def _reaper(pid: int) -> str:
    """Who should reap ``pid``: its parent, with that parent's state."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
        parent = int(next(line.split()[1] for line in status.splitlines() if line.startswith("PPid:")))
    except (OSError, StopIteration, ValueError, IndexError):
        return "its parent is unknown"
    if parent == os.getpid():
        return "its parent is this runner"
    return f"its parent (pid {parent}, a warm start server when started warm) is {process_state(parent)}"


def stop(proc: Handle, sigint_grace: float | None = None,
         sigterm_grace: float | None = None) -> int:
    """Stop ``proc`` (started by :func:`start`): SIGINT, SIGTERM, SIGKILL to its group, after
    the grace periods given (default: ``SIGINT_GRACE``, ``SIGTERM_GRACE`` as they are now).
    Raises :class:`NotEnded` when it has not ended KILL_WAIT seconds after SIGKILL."""
    graces = (SIGINT_GRACE if sigint_grace is None else sigint_grace,
              SIGTERM_GRACE if sigterm_grace is None else sigterm_grace)
    for sig, grace in zip((signal.SIGINT, signal.SIGTERM), graces, strict=True):
        if proc.poll() is not None:
            break
        _signal_group(proc, sig)
        try:
            proc.wait(grace)
        except subprocess.TimeoutExpired:
            continue
    if proc.poll() is None:
        _signal_group(proc, signal.SIGKILL)
    try:
        return proc.wait(KILL_WAIT)
    except subprocess.TimeoutExpired:
        raise NotEnded(proc.pid, KILL_WAIT, process_state(proc.pid), _reaper(proc.pid)) from None


def reap_group(proc: Handle) -> None:
    """Kill what the target left behind in its own process group (its children). Children that
    started a session of their own (daemons, ``setsid``) are out of reach: see docs/known-limits.md."""
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass
