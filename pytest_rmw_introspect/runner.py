"""Run a target on the recording middleware and read its capture.

The process gets the middleware's activation environment (``ros_env.activation_env``), a
capture file of its own (``RMW_INTROSPECT_OUTPUT`` in a fresh temporary directory, so
captures never collide, not even under pytest-xdist), ``RMW_INTROSPECT_EXIT=1`` (the
middleware ends the process with status 0 as soon as its interfaces settled) and
``RMW_INTROSPECT_SETTLE_MS`` from the target's ``settle`` and ``RMW_INTROSPECT_HORIZON_MS``
from its ``horizon`` (virtual time: after the first settle the middleware advances the node's
clock through every timed wait, up to that age, then settles again).

What counts as a capture:

* the process settled (and the middleware ended it): the normal case;
* it settled once and then ended by itself with any status, or crashed (a timeout that
  expired at once in virtual time, say): what it had created until then, with the exit
  reported as information (``Capture.notes()``);
* it ended by itself with status 0 before it ever settled: what was alive just before its
  own final teardown (``Capture.ended_by_itself``).

The runner waits up to the target's ``timeout``. A process still running then is stopped
with SIGINT, SIGTERM and finally SIGKILL (short grace periods, to its whole process group),
and whatever capture the middleware wrote so far (it writes progress snapshots) is attached
to the :class:`~pytest_rmw_introspect.errors.TargetTimeout`. A non-zero exit is a
:class:`~pytest_rmw_introspect.errors.TargetExited` with the tail of the process's stderr; a
process that created no node is :class:`~pytest_rmw_introspect.errors.NoNodeCreated`.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import tempfile
import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from .capture_model import Capture
from .errors import (
    CaptureFormatError,
    ExecutableNotFound,
    NoNodeCreated,
    TargetExited,
    TargetTimeout,
)
from .target import TargetSpec, build_argv

#: seconds granted after SIGINT and after SIGTERM before the next, harder signal
SIGINT_GRACE = 2.0
SIGTERM_GRACE = 1.0
_STDERR_TAIL_BYTES = 16_384


def _read_tail(path: Path, limit: int = _STDERR_TAIL_BYTES) -> str:
    try:
        with path.open("rb") as f:
            f.seek(0, os.SEEK_END)
            size = f.tell()
            f.seek(max(0, size - limit))
            return f.read().decode("utf-8", errors="replace")
    except OSError:
        return ""


def _signal_group(proc: subprocess.Popen, sig: int) -> None:
    try:
        os.killpg(proc.pid, sig)
    except (ProcessLookupError, PermissionError):
        try:
            proc.send_signal(sig)
        except ProcessLookupError:
            pass


def stop(proc: subprocess.Popen, sigint_grace: float = SIGINT_GRACE, sigterm_grace: float = SIGTERM_GRACE) -> int:
    """Stop ``proc`` (started with ``start_new_session=True``): SIGINT, SIGTERM, SIGKILL."""
    for sig, grace in ((signal.SIGINT, sigint_grace), (signal.SIGTERM, sigterm_grace)):
        if proc.poll() is not None:
            break
        _signal_group(proc, sig)
        try:
            proc.wait(grace)
        except subprocess.TimeoutExpired:
            continue
    if proc.poll() is None:
        _signal_group(proc, signal.SIGKILL)
        proc.wait()
    return proc.returncode


def _reap_group(proc: subprocess.Popen) -> None:
    """Kill what the target left behind in its own process group (its children)."""
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def _try_load(path: Path, include_infrastructure: bool) -> Capture | None:
    if not path.exists():
        return None
    try:
        return Capture.load(path, include_infrastructure=include_infrastructure)
    except CaptureFormatError:
        return None


def environment(
    spec: TargetSpec,
    library: Path,
    ros: Any,
    output: Path,
    base: Mapping[str, str] | None = None,
) -> dict[str, str]:
    """The complete environment of the target process."""
    from . import ros_env

    env = dict(os.environ if base is None else base)
    env.update(ros_env.activation_env(library, ros, base=env))
    env.update(spec.env)
    env["RMW_INTROSPECT_OUTPUT"] = str(output)
    env["RMW_INTROSPECT_FORMAT"] = "json"
    env["RMW_INTROSPECT_EXIT"] = "1"
    env["RMW_INTROSPECT_AUTO_EXPORT"] = "1"
    env["RMW_INTROSPECT_SETTLE_MS"] = str(max(0, round(spec.effective_settle() * 1000)))
    env["RMW_INTROSPECT_HORIZON_MS"] = str(max(0, round(spec.effective_horizon() * 1000)))
    env.setdefault("PYTHONUNBUFFERED", "1")
    return env


def run(
    spec: TargetSpec,
    *,
    library: str | Path | None = None,
    ros: Any = None,
    include_infrastructure: bool = False,
    keep_files: bool | None = None,
    python: str | None = None,
) -> Capture:
    """Run ``spec`` on the middleware and return its capture (raises a TargetError subclass).

    ``library``: the middleware library (default: ``middleware.ensure_library``); ``ros``: the
    ROS environment (default: ``ros_env.detect()``); ``keep_files``: keep the temporary
    capture and stderr files (default: the ``RMW_INTROSPECT_KEEP_FILES`` variable).
    """
    from . import middleware, ros_env

    spec.validate()
    ros = ros or ros_env.detect()
    if library is None:
        library = middleware.ensure_library(ros)
    # like `ros2 run`: AMENT_PREFIX_PATH as it is now, then the prefixes of the detected install
    prefixes = ros_env.ament_prefixes(tuple(getattr(ros, "ament_prefixes", ())))
    argv = build_argv(spec, prefixes, python=python)
    if keep_files is None:
        keep_files = os.environ.get("RMW_INTROSPECT_KEEP_FILES", "") not in ("", "0", "false")

    workdir = Path(tempfile.mkdtemp(prefix="rmw_introspect_"))
    output = workdir / "capture.json"
    stderr_path = workdir / "stderr.txt"
    stdout_path = workdir / "stdout.txt"
    env = environment(spec, Path(library), ros, output)
    describe = spec.describe()
    timeout = spec.effective_timeout()
    cwd = spec.cwd
    if cwd is not None and not cwd.is_dir():
        raise ExecutableNotFound(f"Working directory {cwd} of target {describe} does not exist.", target=describe)

    started = time.monotonic()
    try:
        with stderr_path.open("wb") as err, stdout_path.open("wb") as out:
            try:
                proc = subprocess.Popen(
                    argv,
                    env=env,
                    cwd=str(cwd) if cwd else None,
                    stdin=subprocess.DEVNULL,
                    stdout=out,
                    stderr=err,
                    start_new_session=True,
                )
            except OSError as exc:
                raise ExecutableNotFound(
                    f"Cannot start the target {describe}: {exc.strerror or exc} ({argv[0]}).",
                    target=describe,
                    searched=[argv[0]],
                ) from None
            timed_out = False
            try:
                returncode = proc.wait(timeout)
            except subprocess.TimeoutExpired:
                timed_out = True
                returncode = stop(proc)
            except BaseException:  # KeyboardInterrupt while waiting: do not leave it behind
                stop(proc, 0.5, 0.5)
                raise
            finally:
                _reap_group(proc)
        wall = time.monotonic() - started
        stderr = _read_tail(stderr_path)

        if timed_out:
            raise TargetTimeout(describe, timeout, _try_load(output, include_infrastructure), stderr, argv)
        captured = _try_load(output, include_infrastructure) if returncode != 0 else None
        if returncode != 0 and (captured is None or not captured.settled_once):
            raise TargetExited(describe, returncode, stderr, captured, argv)
        if captured is None:
            if not output.exists():
                raise NoNodeCreated(
                    describe,
                    stderr,
                    None,
                    argv,
                    detail="it exited with status 0 and wrote no capture: it never initialised ROS 2, "
                    "or it did not run on the recording middleware",
                )
            captured = Capture.load(output, include_infrastructure=include_infrastructure)
        if not captured.raw_nodes:
            raise NoNodeCreated(describe, stderr, captured, argv)
        captured.returncode = returncode
        captured.stderr = stderr
        captured.wall_time = wall
        captured.command = argv
        captured.path = output if keep_files else None
        return captured
    finally:
        if not keep_files:
            shutil.rmtree(workdir, ignore_errors=True)


def capture(
    target: TargetSpec | Mapping[str, Any] | None = None,
    *,
    include_infrastructure: bool = False,
    library: str | Path | None = None,
    ros: Any = None,
    base_dir: str | Path | None = None,
    keep_files: bool | None = None,
    **options: Any,
) -> Capture:
    """Capture the interfaces of a target: the library function behind ``pytest_rmw_introspect.capture``.

    Give the target as keyword arguments (the keys of :mod:`pytest_rmw_introspect.target`:
    ``package``/``executable``, ``command``, ``script``, ``module``, ``arguments``,
    ``namespace``, ``node_name``, ``remappings``, ``parameters``, ``params_file``, ``env``,
    ``cwd``, ``settle``, ``timeout``), as a mapping, or as a :class:`TargetSpec`; keyword
    arguments override the mapping. Relative paths are relative to ``base_dir`` (default:
    the current directory).

    >>> cap = capture(script="talker.py", namespace="/robot1")   # doctest: +SKIP
    >>> cap["/robot1/talker"].publishers[0].name                 # doctest: +SKIP
    '/robot1/chatter'

    Raises :class:`~pytest_rmw_introspect.errors.SetupError` when ROS 2 or the middleware is
    missing and a :class:`~pytest_rmw_introspect.errors.TargetError` when the target fails.
    """
    base = Path(base_dir) if base_dir is not None else Path.cwd()
    if isinstance(target, TargetSpec):
        spec = target
    else:
        spec = TargetSpec.from_mapping(target or {}, base_dir=base, source="capture()")
    if options:
        spec = spec.merged(options, base_dir=base, source="capture()")
    return run(spec, library=library, ros=ros, include_infrastructure=include_infrastructure, keep_files=keep_files)
