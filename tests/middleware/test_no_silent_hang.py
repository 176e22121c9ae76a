"""No silent hang (issue 39): every wait a capture can be stuck in is bounded, each provoked here
for real: a target stopped with SIGSTOP, a warm start server stopped before or during a capture,
a daemon that keeps the target's output pipes open, a build or golden-write lock held by a
stopped process; and a capture that passes its overall deadline ends with status 2, what it was
waiting for and every thread's stack (run/deadline.py)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
import warm_helpers as w
from rmwi_processes import alive, wait_gone

from pytest_rmw_introspect.check import golden
from pytest_rmw_introspect.errors import GoldenWriteError, LockTimeout, NoNodeCreated, TargetTimeout
from pytest_rmw_introspect.run import deadline, locks, runner
from pytest_rmw_introspect.run.target import TargetSpec
from pytest_rmw_introspect.run.warm import client as warm

TALKER = str(w.NODES / "talker.py")
#: what any capture below may take beyond its target's timeout (the issue's bound)
MARGIN_S = 5.0


def _timed(fn, *args, **kwargs):
    started = time.monotonic()
    try:
        return fn(*args, **kwargs), time.monotonic() - started
    except Exception as exc:  # noqa: BLE001  # the test inspects it
        return exc, time.monotonic() - started


def _stopped_holder(tmp_path: Path, lock: Path) -> subprocess.Popen[bytes]:
    """A process that takes ``lock`` (as the tool does, writing its pid) and stops itself."""
    ready = tmp_path / "holder.ready"
    code = textwrap.dedent(f"""
        import os, signal
        from pathlib import Path
        from pytest_rmw_introspect.run import locks
        with locks.held(Path({str(lock)!r}), 5):
            Path({str(ready)!r}).write_text("1")
            os.kill(os.getpid(), signal.SIGSTOP)
    """)
    holder = subprocess.Popen([sys.executable, "-c", code])
    deadline_at = time.monotonic() + 30
    while not ready.exists():
        assert time.monotonic() < deadline_at and holder.poll() is None, "the lock holder did not start"
        time.sleep(0.05)
    while "T (stopped)" not in locks.holder_of(lock):
        assert time.monotonic() < deadline_at
        time.sleep(0.02)
    return holder


def _end(proc: subprocess.Popen[bytes]) -> None:
    proc.kill()
    proc.wait(10)


# ---------------------------------------------------------------------------- the target


def test_a_target_stopped_with_sigstop_is_ended_within_its_timeout():
    # SIGINT and SIGTERM stay pending on a stopped process: only SIGKILL ends it
    code = "import os, signal; os.kill(os.getpid(), signal.SIGSTOP)"
    spec = TargetSpec.from_mapping({"command": [sys.executable, "-c", code], "timeout": 2})
    error, took = _timed(runner.run, spec, cold_note="test")
    assert isinstance(error, TargetTimeout), error
    assert took < 2 + MARGIN_S


# ---------------------------------------------------------------------------- warm start servers


def test_a_stopped_warm_server_is_given_up_and_the_target_started_cold(monkeypatch):
    monkeypatch.setattr(warm, "SPAWN_TIMEOUT", 2.0)
    env = {"LC_RMWI_TEST": "stopped before the capture"}  # a server of this test's own
    server = w.server_for({"env": env})
    os.kill(server.pid, signal.SIGSTOP)
    try:
        cap, took = _timed(runner.run, TargetSpec.from_mapping({"script": TALKER, "env": env, "timeout": 20}),
                           warm_wait=60.0)
        assert not isinstance(cap, Exception), cap
        assert cap.started == "cold"
        assert f"the warm start server (pid {server.pid}, T (stopped)" in cap.start_note
        assert "did not answer a request to start a target within 2 s" in cap.start_note
        assert took < 20 + MARGIN_S
        # the pool let go of it (and killed it): the next capture gets a new server
        assert w.server_for({"env": env}) is not server
        assert wait_gone([server.pid], 10.0) == []
    finally:
        if alive(server.pid):
            os.kill(server.pid, signal.SIGKILL)


def test_a_warm_server_stopped_during_a_capture_is_not_waited_for():
    env = {"LC_RMWI_TEST": "stopped during the capture"}
    server = w.server_for({"env": env})
    # the target stops its parent when that parent is the warm start server (never a cold start's runner)
    stopper = textwrap.dedent(f"""
        import os, runpy, signal
        parent = os.getppid()
        if parent == {server.pid}:
            os.kill(parent, signal.SIGSTOP)
        runpy.run_path({TALKER!r}, run_name="__main__")
    """)
    script = Path(os.environ.get("TMPDIR", "/tmp")) / f"rmwi_stops_server_{os.getpid()}.py"
    script.write_text(stopper)
    try:
        cap, took = _timed(runner.run, TargetSpec.from_mapping({"script": str(script), "env": env, "timeout": 20}),
                           warm_wait=60.0)
        assert not isinstance(cap, Exception), cap
        assert (cap.started, cap.start_note) == ("cold", "the warm start server stopped answering during the capture")
        assert cap.node_names == ["/talker"]
        assert took < 20 + MARGIN_S
        assert w.server_for({"env": env}) is not server
        assert wait_gone([server.pid], 10.0) == []
    finally:
        script.unlink(missing_ok=True)
        if alive(server.pid):
            os.kill(server.pid, signal.SIGKILL)


def test_a_daemon_that_keeps_the_output_pipes_open_is_not_waited_for(tmp_path):
    # The target starts a process in a session of its own (out of reach of the group kill) that
    # inherits its stdout and stderr and sleeps: the pipes the runner reads never reach end of
    # file. The runner must not wait for them.
    pid_file = tmp_path / "daemon.pid"
    code = textwrap.dedent(f"""
        import subprocess
        daemon = subprocess.Popen(["setsid", "sleep", "60"])
        open({str(pid_file)!r}, "w").write(str(daemon.pid))
    """)
    spec = TargetSpec.from_mapping({"command": [sys.executable, "-c", code], "timeout": 10})
    error, took = _timed(runner.run, spec, cold_note="test")
    daemon = int(pid_file.read_text())
    try:
        assert isinstance(error, NoNodeCreated), error  # it exited with status 0 and created no node
        assert alive(daemon)  # the pipes were still open when the runner returned
        assert took < 10 + MARGIN_S
    finally:
        os.kill(daemon, signal.SIGKILL)


# ---------------------------------------------------------------------------- locks


def test_a_build_lock_held_by_a_stopped_process_names_it(tmp_path):
    lock = tmp_path / "jazzy-0123.lock"
    holder = _stopped_holder(tmp_path, lock)
    try:
        error, took = _timed(lambda: locks.held(lock, 1.0).__enter__())
        assert isinstance(error, LockTimeout), error
        assert str(error.holder).startswith(f"pid {holder.pid}, T (stopped)")
        assert took < 1 + MARGIN_S
    finally:
        _end(holder)
    # a holder that is gone (killed) never blocks: the kernel released its lock
    with locks.held(lock, 1.0):
        pass


def test_the_middleware_build_lock_held_by_a_stopped_builder_fails_with_its_pid(tmp_path, monkeypatch):
    """The real build lock of run/middleware.py: a builder that stopped (its `<lock>.pid` file names it)
    makes a waiting process fail after BUILD_LOCK_TIMEOUT, naming the builder and its state."""
    from pytest_rmw_introspect.errors import SetupError
    from pytest_rmw_introspect.run import middleware, ros_env

    dest = tmp_path / "jazzy-0123"
    lock = tmp_path / "jazzy-0123.lock"
    ready = tmp_path / "builder.ready"
    code = textwrap.dedent(f"""
        import os, signal
        from pathlib import Path
        from filelock import FileLock
        with FileLock({str(lock)!r}):
            Path({str(tmp_path / "jazzy-0123.lock.pid")!r}).write_text(f"{{os.getpid()}} -\\n")
            Path({str(ready)!r}).write_text("1")
            os.kill(os.getpid(), signal.SIGSTOP)
    """)
    holder = subprocess.Popen([sys.executable, "-c", code])
    try:
        deadline_at = time.monotonic() + 30
        while not ready.exists():
            assert time.monotonic() < deadline_at and holder.poll() is None, "the builder did not start"
            time.sleep(0.05)
        monkeypatch.setattr(middleware, "BUILD_LOCK_TIMEOUT", 1.0)
        monkeypatch.setattr(middleware, "WAIT_NOTICE_AFTER", 0.1)
        ros = ros_env.RosEnvironment(ros_env.WHEELS, tmp_path, "jazzy")
        error, took = _timed(lambda: middleware._build_lock(lock, dest, ros).__enter__())
        assert isinstance(error, SetupError), error
        assert f"Another process (pid {holder.pid}, T (stopped)" in str(error) and "kill <pid>" in str(error)
        assert took < 1.1 + MARGIN_S
    finally:
        _end(holder)


def test_a_golden_lock_held_by_a_stopped_process_fails_the_write_with_its_pid(tmp_path):
    contract = tmp_path / "talker.interfaces.yaml"
    holder = _stopped_holder(tmp_path, golden.lock_path(contract))
    try:
        error, took = _timed(golden.write_text, contract, "nodes: {}\n", timeout=1.0)
        assert isinstance(error, GoldenWriteError), error
        assert f"pid {holder.pid}, T (stopped)" in str(error) and "kill <pid>" in str(error)
        assert took < 1 + MARGIN_S
        assert not contract.exists()
    finally:
        _end(holder)


# ---------------------------------------------------------------------------- the overall deadline


def test_a_capture_past_its_deadline_exits_2_with_every_stack(cli_env, tmp_path):
    # A target that ignores SIGINT and SIGTERM keeps the runner in its stop for 3 s: with no slack
    # beyond its 2 s timeout, the watchdog ends the command then, saying what it waited for.
    code = ("import signal, time; signal.signal(signal.SIGINT, signal.SIG_IGN); "
            "signal.signal(signal.SIGTERM, signal.SIG_IGN); time.sleep(60)")
    started = time.monotonic()
    proc = subprocess.run(
        [sys.executable, "-m", "pytest_rmw_introspect", "capture", "--timeout", "2", "--", sys.executable, "-c", code],
        cwd=tmp_path, env={**cli_env, deadline.SLACK_ENV: "1"}, capture_output=True, text=True, timeout=60)
    took = time.monotonic() - started
    assert proc.returncode == deadline.EXIT_STATUS, proc.stderr
    assert "passed its deadline (2 s timeout + 1 s" in proc.stderr
    assert "while waiting for the target (pid " in proc.stderr and "to stop: SIGINT, SIGTERM" in proc.stderr
    assert "Every thread's stack:" in proc.stderr
    assert "most recent call first" in proc.stderr and "in stop" in proc.stderr  # faulthandler's dump
    assert took < 2 + MARGIN_S + 5  # the interpreter's start on a loaded machine
    pid = int(proc.stderr.split("The target: pid ", 1)[1].split(",", 1)[0])
    assert wait_gone([pid], 5.0) == []  # the watchdog killed its group


@pytest.fixture
def cli_env(middleware_library):
    env = {k: v for k, v in os.environ.items() if k not in ("CI", "PYTEST_ADDOPTS")}
    env["RMW_INTROSPECT_LIBRARY"] = str(middleware_library)
    return env
