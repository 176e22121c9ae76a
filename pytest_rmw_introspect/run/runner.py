"""Run a target on the recording middleware and read its capture.

The runner starts what ``resolution.resolve`` made of the target (``ResolvedTarget``: command line,
environment, working directory, warm or cold start) and asks the target module nothing else.
The process gets the middleware's activation environment (``ros_env.activation_env``), a
capture file of its own (``RMW_INTROSPECT_OUTPUT`` in a fresh temporary directory, so
captures never collide, not even under pytest-xdist), ``RMW_INTROSPECT_EXIT=1`` (the
middleware ends the process with status 0 as soon as its interfaces settled) and
``RMW_INTROSPECT_SETTLE_MS`` from the target's ``settle`` and ``RMW_INTROSPECT_HORIZON_MS``
from its ``horizon`` (virtual time: after the first settle the middleware advances the node's
clock through every timed wait, up to that age, then settles again), ``RMW_INTROSPECT_LIFECYCLE``
from its ``lifecycle`` and ``RMW_INTROSPECT_PARAMETERS`` from its ``read_parameters`` (after the
first settle the middleware reads every node's parameters and drives lifecycle nodes).

A lifecycle node whose transition failed (its callback returned FAILURE or ERROR, or raised)
is a :class:`~pytest_rmw_introspect.errors.LifecycleTransitionFailed`: the capture would show
the node in a state the target did not ask for. ``RMW_INTROSPECT_STIMULI`` comes from its
``stimuli`` when it has any (a stimulus that matches nothing, is not taken or answered, or
after which the process fails is a :class:`~pytest_rmw_introspect.errors.StimulusFailed`).

What counts as a capture:

* the process settled (and the middleware ended it): the normal case;
* it settled once and then ended by itself with any status, or crashed (a timeout that
  expired at once in virtual time, say): what it had created until then, with the exit
  reported as information (``Capture.notes()``);
* it ended by itself with status 0 before it ever settled: what was alive just before its
  own final teardown (``Capture.ended_by_itself``).

Every ROS process the target starts runs on the middleware too (it inherits the environment):
each writes a capture file of its own (``capture.<pid>.json``). The capture is the target's own
process; the others are reported (``Capture.other_processes``). A target that creates no node
itself but starts exactly one ROS process (a wrapper script) is captured from that process,
with a note.

The runner waits up to the target's ``timeout``. A process still running then is stopped
with SIGINT, SIGTERM and finally SIGKILL (short grace periods, to its whole process group),
and whatever capture the middleware wrote so far (it writes progress snapshots) is attached
to the :class:`~pytest_rmw_introspect.errors.TargetTimeout`. A non-zero exit is a
:class:`~pytest_rmw_introspect.errors.TargetExited` with the tail of the process's stderr; a
process that created no node is :class:`~pytest_rmw_introspect.errors.NoNodeCreated`.
"""

from __future__ import annotations

import atexit
import contextlib
import importlib
import os
import queue
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

from ..errors import (
    Cancelled,
    CaptureFormatError,
    ExecutableNotFound,
    LifecycleTransitionFailed,
    NoNodeCreated,
    NotEnded,
    StimulusFailed,
    TargetError,
    TargetExited,
    TargetNotStopped,
    TargetTimeout,
    WarmStartFailed,
)
from ..model import tally
from . import failure_hints, process, progress, ros_env
from .deadline import Watchdog
from .resolution import resolve

if TYPE_CHECKING:
    from ..model.capture import Capture, OtherProcess
    from .resolution import ResolvedTarget
    from .target import TargetSpec
    from .warm.client import WarmChild

# Imported when first needed, not here: the capture model (its dataclasses cost ~30 ms to create)
# while the first target starts, so the two overlap (_import_capture_model_meanwhile), and the warm
# start machinery (``warm``) only when a target may start warm: ``rmw-introspect capture`` starts
# its one target cold without it.

#: where a capture run's files go: ``<tempdir>/rmw_introspect_<runner pid>_<random>/``
_WORKDIR_PREFIX = "rmw_introspect_"
#: a working directory left by a runner that was killed is removed by the next run after this long
_STALE_AFTER_S = 600.0
#: a runner sweeps stale working directories at its first capture and then at most this often
_SWEEP_EVERY_S = 60.0
_last_sweep = -_SWEEP_EVERY_S
_CAPTURE_MODEL = f"{__name__.rsplit('.', 2)[0]}.model.capture"


def stop(proc: process.Handle, sigint_grace: float | None = None,
         sigterm_grace: float | None = None) -> int:
    """Stop a target process: SIGINT, SIGTERM, SIGKILL to its group (``process.stop``)."""
    return process.stop(proc, sigint_grace, sigterm_grace)


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def sweep_stale_workdirs(tempdir: Path | None = None, *, now: float | None = None) -> list[Path]:
    """Remove working directories of runners that are gone (killed with SIGKILL, say) and
    older than ten minutes; returns what was removed."""
    base = Path(tempdir or tempfile.gettempdir())
    now = time.time() if now is None else now
    removed: list[Path] = []
    try:
        candidates = list(base.glob(f"{_WORKDIR_PREFIX}*_*"))
    except OSError:
        return removed
    for path in candidates:
        owner = path.name[len(_WORKDIR_PREFIX):].split("_", 1)[0]
        try:
            if not owner.isdigit() or _pid_alive(int(owner)) or now - path.stat().st_mtime < _STALE_AFTER_S:
                continue
        except OSError:
            continue
        shutil.rmtree(path, ignore_errors=True)
        removed.append(path)
    return removed


#: capture working directories handed to the remover thread (``_remove_later``); None stops it
_removals: queue.SimpleQueue[Path | None] = queue.SimpleQueue()
_remover: threading.Thread | None = None
_remover_lock = threading.Lock()


def _remove_later(workdir: Path) -> None:
    """Remove a capture's working directory in a thread of its own instead of before the capture
    is returned: deleting a directory and the files in it waits for the file system (~7 ms on this
    project's ext4, mounted with ``discard``; 12 ms per capture under load), time in which nothing
    is computed. What is still queued when the interpreter exits is removed then
    (``flush_removals``, registered with atexit); a runner killed first leaves it to
    ``sweep_stale_workdirs``."""
    global _remover
    _removals.put(workdir)
    with _remover_lock:
        if _remover is None or not _remover.is_alive():  # none yet, or forked without it
            _remover = threading.Thread(target=_remove_queued, name="rmw-introspect cleanup", daemon=True)
            _remover.start()


def _remove_queued() -> None:
    while (workdir := _removals.get()) is not None:
        shutil.rmtree(workdir, ignore_errors=True)


@atexit.register
def flush_removals() -> None:
    """Remove every capture working directory still waiting for the remover thread; returns
    when they are gone."""
    with _remover_lock:
        remover = _remover
    if remover is not None and remover.is_alive():
        _removals.put(None)
        remover.join()
    while True:  # what was queued after the stop (or with no thread alive: a forked process)
        try:
            workdir = _removals.get_nowait()
        except queue.Empty:
            return
        if workdir is not None:
            shutil.rmtree(workdir, ignore_errors=True)


def _try_load(path: Path, include_infrastructure: bool) -> Capture | None:
    from ..model.capture import Capture

    if not path.exists():
        return None
    try:
        return Capture.load(path, include_infrastructure=include_infrastructure)
    except CaptureFormatError:
        return None


@dataclass
class _Started:
    proc: process.Handle
    stdout: IO[bytes]
    stderr: IO[bytes]
    note: str | None  # why it started cold
    #: a warm child's command line as a cold start's /proc/self/cmdline would read
    cmdline: list[str] | None = None
    #: ``proc`` when it was forked by a warm start server
    warm_child: WarmChild | None = None

    @property
    def how(self) -> str:
        """``warm`` or ``cold`` (``Capture.started``)."""
        return "cold" if self.warm_child is None else "warm"


def _server_cwd(target: ResolvedTarget) -> str:
    """The working directory a warm start server for ``target`` runs in."""
    return str(target.cwd) if target.cwd is not None else os.getcwd()


#: seconds a capture waits quietly for a warm start server that is still starting
_QUIET_WAIT = 1.0


def _warm_server(warm: Any, env: dict[str, str], cwd: str, python: str | None, wait: float) -> Any:
    """The ready warm start server for a target, or why there is none. A wait longer than
    ``_QUIET_WAIT`` is said on the terminal (in the thread the user waits in: a capture started
    ahead runs in one of its own, beside a running test)."""
    if wait <= _QUIET_WAIT or threading.current_thread() is not threading.main_thread():
        return warm.POOL.server(env, cwd, python, wait=wait)
    server = warm.POOL.server(env, cwd, python, wait=_QUIET_WAIT)
    if server != warm.STILL_STARTING:
        return server
    told = progress.say_once("warm-server", "the warm start server (one Python process that imports rclpy once, so "
                             f"that captures start in milliseconds) is still starting; waiting up to {wait:.0f} s for it "
                             "before starting the target cold")
    began = time.monotonic()
    server = warm.POOL.server(env, cwd, python, wait=wait - _QUIET_WAIT)
    if told:
        waited = progress.seconds(_QUIET_WAIT + time.monotonic() - began)
        progress.say(f"the warm start server is ready after {waited}" if isinstance(server, warm.WarmServer)
                     else f"no warm start server after {waited} ({server}): the target starts cold")
    return server


def _start(target: ResolvedTarget, python: str | None, warm_wait: float | None) -> _Started:
    """Start the target: forked from a warm start server when it can be (``target.warm``), else a
    new process (``warm_wait``: default ``warm.DEFAULT_WAIT``)."""
    note = target.cold_because
    argv, env = list(target.argv), dict(target.env)
    if target.warm is not None:
        from .warm import client as warm

        if warm_wait is None:
            warm_wait = warm.DEFAULT_WAIT
        cwd = _server_cwd(target)
        server = _warm_server(warm, env, cwd, python, warm_wait)
        if isinstance(server, warm.WarmServer):
            try:
                child = server.spawn(target.warm, env=env, cwd=cwd)
                return _tallied(_Started(child, child.stdout, child.stderr, None, list(target.warm.orig_argv), child))
            except WarmStartFailed as exc:
                note = str(exc)
        else:
            note = server
    try:
        proc = process.start(argv, env=env, cwd=target.cwd)
    except OSError as exc:
        raise ExecutableNotFound(
            f"Cannot start the target {target.name}: {exc.strerror or exc} ({argv[0]}).",
            target=target.name,
            searched=[argv[0]],
        ) from None
    assert proc.stdout is not None and proc.stderr is not None
    return _tallied(_Started(proc, proc.stdout, proc.stderr, note))


def _tallied(start: _Started) -> _Started:
    """``start``, counted for the test suite's cost report (``model.tally``: nothing unless
    ``RMW_INTROSPECT_TALLY`` is set; issue 48)."""
    tally.note("start", start.how)
    return start


@dataclass
class _Ended:
    returncode: int
    timed_out: bool
    stdout: str
    stderr: str


def _import_capture_model_meanwhile() -> None:
    """Import the capture model (~30 ms of dataclass creation, needed once the target ends) while
    the target starts, in a thread of its own. Not in this thread: a SIGINT or SIGTERM
    (KeyboardInterrupt, the CLI's Terminated) raised in the middle of an import can come out as
    another error (a RuntimeError from a dataclass field's ``__set_name__``), which would skip
    the clean stop of the target and of the command. The first use waits for the import."""
    if _CAPTURE_MODEL not in sys.modules:
        threading.Thread(target=importlib.import_module, args=(_CAPTURE_MODEL,),
                         name="rmw-introspect import", daemon=True).start()


#: seconds between two looks at a capture's ``cancel`` event while its target runs
_CANCEL_POLL_S = 0.1


def _wait_for(proc: process.Handle, timeout: float, cancel: threading.Event | None) -> int:
    """``proc.wait(timeout)``, raising :class:`Cancelled` soon after ``cancel`` is set. A capture
    in another thread (a system's processes, captured in parallel) is not reached by the
    KeyboardInterrupt of the main thread, which sets the event instead."""
    if cancel is None:
        return proc.wait(timeout)
    deadline = time.monotonic() + timeout
    while True:
        if cancel.is_set():
            raise Cancelled()
        remaining = deadline - time.monotonic()
        try:
            return proc.wait(max(0.0, min(remaining, _CANCEL_POLL_S)))
        except subprocess.TimeoutExpired:
            if remaining <= _CANCEL_POLL_S:
                raise


def _wait(start: _Started, timeout: float, cancel: threading.Event | None = None,
          watchdog: Watchdog | None = None, describe: str = "") -> _Ended:
    """Wait for the target (stopping it after ``timeout``, or at once when ``cancel`` is set),
    then kill what is left of its group. ``watchdog``: told the target's pid and each wait;
    ``describe``: the target, for the error of one that cannot be stopped."""
    proc = start.proc
    stopping = contextlib.nullcontext() if watchdog is None else watchdog.waiting(
        f"the target (pid {proc.pid}) to stop: SIGINT, SIGTERM, then SIGKILL to its process group")
    if watchdog is not None:
        watchdog.pid = proc.pid
    stdout_tail, stderr_tail = process.OutputTail.read_together(start.stdout, start.stderr)
    timed_out = False
    try:
        with contextlib.nullcontext() if watchdog is None else watchdog.waiting(
                f"the target (pid {proc.pid}, started {start.how}) to settle or end within its timeout"):
            returncode = _wait_for(proc, timeout, cancel)
    except subprocess.TimeoutExpired:
        timed_out = True
        with stopping:
            try:
                returncode = stop(proc)
            except NotEnded as exc:
                if start.warm_child is not None:
                    start.warm_child.server_stopped_answering()
                raise TargetNotStopped(describe or f"pid {proc.pid}", exc.pid, exc.waited, exc.state, exc.reaper) from None
    except BaseException:  # KeyboardInterrupt (or SIGTERM, see cli), Cancelled: do not leave it behind
        with stopping, contextlib.suppress(NotEnded):  # the interruption is what to report
            stop(proc, 0.5, 0.5)
        raise
    finally:
        process.reap_group(proc)
        if start.warm_child is not None:
            start.warm_child.release()
        stdout_tail.finish()
        stderr_tail.finish()
    return _Ended(returncode, timed_out, stdout_tail.text(), stderr_tail.text())


def run(
    spec: TargetSpec,
    *,
    library: str | Path | None = None,
    ros: ros_env.RosEnvironment | None = None,
    include_infrastructure: bool = False,
    keep_files: bool | None = None,
    python: str | None = None,
    warm_wait: float | None = None,
    cold_note: str | None = None,
    cancel: threading.Event | None = None,
) -> Capture:
    """Run ``spec`` on the middleware and return its capture (raises a TargetError subclass).

    ``library``: the middleware library (default: ``middleware.ensure_library``); ``ros``: the
    ROS environment (default: ``ros_env.detect()``); ``keep_files``: keep the temporary
    capture and stderr files (default: the ``RMW_INTROSPECT_KEEP_FILES`` variable);
    ``warm_wait``: seconds to wait for a warm start server that is still starting before the
    target is started cold instead (default ``warm.DEFAULT_WAIT``); ``cold_note``: start it cold,
    for this reason (``Capture.start_note``), without looking for a warm start server.

    The walk of a capture, one step each: :meth:`_Run.begin` (a working directory, the target
    resolved, a deadline), :meth:`_Run.run_target` (started warm or cold, waited for, once more
    cold if its warm start server died under it), :meth:`_Run.read_capture` (the capture file
    read and the ending classified), :meth:`_Run.judge` (what the middleware drove: lifecycle
    transitions, stimuli), then the warm start server told the types the target used.
    """
    if keep_files is None:
        keep_files = os.environ.get("RMW_INTROSPECT_KEEP_FILES", "") not in ("", "0", "false")
    walk = _Run.begin(spec, library=library, ros=ros, python=python, cold_note=cold_note,
                      include_infrastructure=include_infrastructure, keep_files=keep_files)
    try:
        start, ended = walk.run_target(warm_wait, cancel)
        try:
            captured = walk.judge(walk.read_capture(start, ended), start, ended)
        except TargetError as exc:
            exc.started = start.how  # the error of a target that ran says how it was started
            raise
        if cold_note is None:  # a run that never starts warm has no server to tell
            _learn(captured, walk.target, python)
        return captured
    finally:
        walk.end()


@dataclass
class _Run:
    """One capture on its way (:func:`run`'s steps): the resolved target, its working directory
    (the capture files, kept or removed at the end) and the deadline behind every wait."""

    target: ResolvedTarget
    workdir: Path
    python: str | None
    include_infrastructure: bool
    keep_files: bool
    #: the last resort behind every bounded wait: status 2 with every stack (run/deadline.py)
    watchdog: Watchdog
    #: ``time.monotonic()`` before the target started: the capture's wall time counts from it
    began: float
    #: seconds from starting the target to its end (``RunFacts.wall_time``; set once it ended)
    wall_time: float | None = None

    @classmethod
    def begin(cls, spec: TargetSpec, *, library: str | Path | None, ros: ros_env.RosEnvironment | None, python: str | None,
              cold_note: str | None, include_infrastructure: bool, keep_files: bool) -> _Run:
        """A working directory of its own (stale ones of killed runners swept now and then) and
        the target resolved into it (``resolution.resolve``), with its deadline not yet started."""
        global _last_sweep
        if time.monotonic() - _last_sweep > _SWEEP_EVERY_S:  # a listing of the temporary directory: not per capture
            _last_sweep = time.monotonic()
            sweep_stale_workdirs()
        workdir = Path(tempfile.mkdtemp(prefix=f"{_WORKDIR_PREFIX}{os.getpid()}_"))
        try:
            target = resolve(spec, workdir=workdir, library=library, ros=ros, python=python, cold_note=cold_note)
        except BaseException:
            shutil.rmtree(workdir, ignore_errors=True)
            raise
        began = time.monotonic()
        return cls(target, workdir, python, include_infrastructure, keep_files, cls._deadline(target, workdir), began)

    @staticmethod
    def _deadline(target: ResolvedTarget, workdir: Path) -> Watchdog:
        return Watchdog.for_target(target.name, target.timeout,
                                   on_expiry=lambda: shutil.rmtree(workdir, ignore_errors=True))

    def run_target(self, warm_wait: float | None, cancel: threading.Event | None) -> tuple[_Started, _Ended]:
        """Start the target (forked warm, or cold) and wait for it to settle or end; a target whose
        warm start server died under it (it died with it) runs once more, cold."""
        if cancel is not None and cancel.is_set():
            raise Cancelled()
        self.watchdog.start()
        with self.watchdog.waiting("the target to start (or a warm start server to fork it)"):
            start = _start(self.target, self.python, warm_wait)
        _import_capture_model_meanwhile()
        ended = _wait(start, self.target.timeout, cancel, self.watchdog, self.target.name)
        if start.warm_child is not None and start.warm_child.server_lost:
            for leftover in self.workdir.iterdir():  # its capture files, and its log directory
                if leftover.is_dir():
                    shutil.rmtree(leftover, ignore_errors=True)
                else:
                    leftover.unlink()
            self.watchdog.cancel()  # a second run: a deadline of its own
            self.watchdog = self._deadline(self.target, self.workdir).start()
            lost = ("the warm start server stopped answering during the capture" if start.warm_child.server_silent
                    else "the warm start server ended during the capture")
            with self.watchdog.waiting(f"the target to start cold ({lost})"):
                start = _start(self.target.started_cold(lost), self.python, warm_wait)
            ended = _wait(start, self.target.timeout, cancel, self.watchdog, self.target.name)
        self.watchdog.now("its capture files to be read (the target has ended)")
        self.wall_time = time.monotonic() - self.began
        if self.keep_files:
            (self.workdir / "stderr.txt").write_text(ended.stderr, encoding="utf-8")
            (self.workdir / "stdout.txt").write_text(ended.stdout, encoding="utf-8")
        return start, ended

    def read_capture(self, start: _Started, ended: _Ended) -> Capture:
        """The target's capture with the runner's facts, or the error its ending is: it did not
        settle in time, failed before its final settle (or crashed), or created no node."""
        from ..model.capture import Capture

        target, stderr, argv = self.target, ended.stderr, list(self.target.shown_argv)
        output, others, from_child = _outputs(target.output, start.proc.pid, self.include_infrastructure)
        loaded = self._failed_ending(output, start, ended)
        if loaded is None:
            if not output.exists():
                raise NoNodeCreated(target.name, stderr, None, argv,
                                    detail="it exited with status 0 and wrote no capture: it never initialised "
                                    "ROS 2, or it did not run on the recording middleware",
                                    hint=_no_node_hint(target), language=_language(target))
            loaded = Capture.load(output, include_infrastructure=self.include_infrastructure)
        if not loaded.raw_nodes:
            raise NoNodeCreated(target.name, stderr, _mark(loaded, start), argv, hint=_no_node_hint(target),
                                language=_language(target))
        captured = _with_facts(loaded, start, returncode=ended.returncode, stderr=stderr,
                               wall_time=self.wall_time, command=target.argv,
                               other_processes=tuple(others), from_child=from_child,
                               ros_distribution=target.ros_distribution, keep_path=self.keep_files)
        captured.make_values_portable(ros_env.package_shares(target.prefixes), home=_home(target))
        return captured

    def _failed_ending(self, output: Path, start: _Started, ended: _Ended) -> Capture | None:
        """Raise the error of a target that did not settle in time, crashed, or ended with a
        non-zero status before it settled; else the capture a non-zero ending left (None: the
        target ended with status 0, its capture is still to read)."""
        from ..model.capture_diagnoses import diagnose_unsettled, stimulus_problems

        target, returncode, stderr, argv = self.target, ended.returncode, ended.stderr, list(self.target.shown_argv)
        if ended.timed_out:
            partial = _mark(_try_load(output, self.include_infrastructure), start)
            raise TargetTimeout(target.name, target.timeout, partial, stderr, argv,
                                diagnosis=diagnose_unsettled(partial))
        if returncode == 0:
            return None
        loaded = _try_load(output, self.include_infrastructure)
        crashed = crash_evidence(returncode, stderr)
        if crashed and target.stimuli and loaded is not None and loaded.settled_once:
            # a crash on a stimulus: the stimulus report says which one it was
            problems = stimulus_problems(loaded, returncode)
            if problems:
                raise StimulusFailed(target.name, problems, _mark(loaded, start), stderr, argv)
        if loaded is None or not loaded.settled_once or crashed:
            raise TargetExited(target.name, returncode, stderr, _mark(loaded, start), argv,
                               hint=failure_hints.exit_hint(stderr), crashed=crashed)
        return loaded

    def judge(self, captured: Capture, start: _Started, ended: _Ended) -> Capture:
        """``captured``, unless what the middleware drove went wrong: a lifecycle transition that
        failed (the node is not in the state asked for), a stimulus that failed."""
        from ..model.capture_diagnoses import stimulus_problems

        target, argv = self.target, list(self.target.shown_argv)
        failures = captured.failed_transitions()
        if failures:
            raise LifecycleTransitionFailed(target.name, failures, wanted=target.lifecycle, partial=captured,
                                            stderr_tail=ended.stderr, argv=argv)
        if target.stimuli:
            problems = stimulus_problems(captured, ended.returncode)
            if problems:
                raise StimulusFailed(target.name, problems, captured, ended.stderr, argv)
        return captured

    def end(self) -> None:
        """The deadline cancelled; the working directory removed (in a thread of its own) unless kept."""
        self.watchdog.cancel()
        if not self.keep_files:
            _remove_later(self.workdir)


#: signals that end a program because it failed (not because something stopped it)
_CRASH_SIGNALS = frozenset({signal.SIGSEGV, signal.SIGABRT, signal.SIGBUS, signal.SIGFPE, signal.SIGILL})
_CRASH_MARKS = ("Traceback (most recent call last):", "terminate called after throwing")


def crash_evidence(returncode: int, stderr: str) -> bool:
    """A non-zero end that is a crash: a fatal signal, or an uncaught exception on stderr (a
    Python traceback, C++'s ``terminate called after throwing``). A plain ``exit(1)`` after the
    interfaces settled is not (a program that gave up when a timeout expired at once in virtual
    time): it stays a capture with a note."""
    if returncode < 0 and -returncode in _CRASH_SIGNALS:
        return True
    return any(mark in stderr for mark in _CRASH_MARKS)


def _home(target: ResolvedTarget) -> str | None:
    """The home directory the target ran with (its environment's HOME)."""
    return dict(target.env).get("HOME") or os.environ.get("HOME")


def _language(target: ResolvedTarget) -> str | None:
    """What the program of ``target`` is, for :class:`NoNodeCreated`: "python" (a module or
    script target, a Python interpreter, a script whose ``#!`` line names one), "compiled" (an
    ELF executable) or None (not known)."""
    if target.module is not None or not target.argv:
        return "python" if target.module is not None else None
    program = target.argv[0]
    if os.path.basename(program).startswith("python"):
        return "python"
    found = program if os.sep in program else shutil.which(program, path=target.env.get("PATH"))
    try:
        with open(found or program, "rb") as f:
            head = f.read(128)
    except OSError:
        return None
    if head.startswith(b"\x7fELF"):
        return "compiled"
    first_line = head.split(b"\n", 1)[0]
    return "python" if first_line.startswith(b"#!") and b"python" in first_line else None


def _no_node_hint(target: ResolvedTarget) -> str | None:
    """Why a target that created no node may not have run its node (a subprocess: only then)."""
    return failure_hints.no_node_hint(target.module, target.argv[0], target.own_env, target.cwd)


def _with_facts(loaded: Capture, start: _Started, *, keep_path: bool = True, **facts: Any) -> Capture:
    """``loaded`` with the runner's facts: how the target was started, and ``facts``. A warm
    child's command line (``/proc/self/cmdline``, which the middleware reads for ``argv``) is the
    server's: the capture gets the one a cold start would have had."""
    from ..model.capture import RunFacts

    return loaded.with_facts(RunFacts(started=start.how, start_note=start.note, **facts),
                             argv=start.cmdline, keep_path=keep_path)


def _mark(loaded: Capture | None, start: _Started) -> Capture | None:
    """A partial capture (of a target that failed) with how the target was started."""
    return None if loaded is None else _with_facts(loaded, start)


def _learn(captured: Capture, target: ResolvedTarget, python: str | None) -> None:
    """Tell the warm start server for targets like this one which message types they use."""
    type_names = sorted({e.type for e in captured.raw_endpoints if e.type})
    if not type_names:
        return
    from .warm import client as warm

    warm.POOL.learn(dict(target.env), _server_cwd(target), type_names, python)


def _describe_process(path: Path, include_infrastructure: bool) -> OtherProcess:
    from ..model.capture import OtherProcess

    pid_text = path.name.split(".")[1] if path.name.count(".") >= 2 else ""
    other = _try_load(path, include_infrastructure)
    if other is None:
        return OtherProcess(pid=int(pid_text) if pid_text.isdigit() else None, argv=[], node_names=[])
    names = sorted({n.fqn for n in other.raw_nodes})
    return OtherProcess(pid=other.pid, argv=list(other.argv), node_names=names)


def _outputs(pattern: Path, pid: int, include_infrastructure: bool) -> tuple[Path, list[OtherProcess], OtherProcess | None]:
    """The target's capture file (``pattern``: with ``<pid>`` for the process id), the other ROS
    processes it started, and (when the target itself wrote nothing but exactly one child did)
    that child, whose file becomes the capture."""
    own = pattern.with_name(pattern.name.replace("<pid>", str(pid)))
    # written atomically by the middleware (<file>.tmp.<pid>, then a rename): skip temporaries
    others = sorted(p for p in pattern.parent.glob(pattern.name.replace("<pid>", "*"))
                    if p != own and not p.name.endswith(".json.tmp") and ".tmp." not in p.name)
    if own.exists() or len(others) != 1:
        return own, [_describe_process(p, include_infrastructure) for p in others], None
    return others[0], [], _describe_process(others[0], include_infrastructure)
