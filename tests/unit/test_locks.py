"""run/locks.py: one lock convention for the golden writes and the middleware build. The holder
writes ``<lock>.pid`` (its pid, then its info) while it holds the lock; a waiter past
``notice_after`` runs the rest of its wait inside the ``waiting`` callback, given the holder; a
wait that times out names the holder. (A holder stopped with SIGSTOP: tests/middleware/test_no_silent_hang.py.)"""

from __future__ import annotations

import contextlib
import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from pytest_rmw_introspect.errors import LockTimeout
from pytest_rmw_introspect.run import locks

HOLD = textwrap.dedent("""
    import sys, time
    from pathlib import Path
    from pytest_rmw_introspect.run import locks
    with locks.held(Path(sys.argv[1]), 5, info=sys.argv[2]):
        print("holding", flush=True)
        time.sleep(float(sys.argv[3]))
""")


def _held_elsewhere(lock: Path, info: str, seconds: float) -> subprocess.Popen[str]:
    holder = subprocess.Popen([sys.executable, "-c", HOLD, str(lock), info, str(seconds)], stdout=subprocess.PIPE, text=True)
    assert holder.stdout is not None and holder.stdout.readline() == "holding\n"
    return holder


def test_the_holder_writes_its_pid_and_info_while_it_holds_the_lock(tmp_path):
    lock = tmp_path / "a.lock"
    with locks.held(lock, 1.0, info="run-7"):
        assert locks.holder_file(lock).read_text() == f"{os.getpid()} run-7\n"
        assert locks.holder(lock) == locks.Holder(os.getpid(), "run-7")
    assert not locks.holder_file(lock).exists()
    with locks.held(lock, 1.0):
        assert locks.holder_file(lock).read_text() == f"{os.getpid()}\n"
        assert locks.holder(lock) == locks.Holder(os.getpid(), "")


def test_a_holder_that_wrote_nothing_readable_is_said_so(tmp_path):
    lock = tmp_path / "a.lock"
    assert locks.holder(lock) == locks.Holder(None) and locks.holder_of(lock) == "a process that did not write its pid"
    locks.holder_file(lock).write_text("not-a-pid\n")
    assert locks.holder(lock).pid is None


def test_a_wait_past_the_notice_runs_inside_the_callback_given_the_holder(tmp_path):
    lock = tmp_path / "a.lock"
    events: list[object] = []

    @contextlib.contextmanager
    def waiting(holder: locks.Holder):
        events.append(holder)
        yield
        events.append("ended")

    holder = _held_elsewhere(lock, "run-9", 1.5)
    try:
        with locks.held(lock, 30, waiting=waiting, notice_after=0.2):
            events.append("held")
    finally:
        holder.wait(30)
    assert events == [locks.Holder(holder.pid, "run-9"), "ended", "held"]


def test_a_lock_free_within_the_notice_never_calls_the_callback(tmp_path):
    with locks.held(tmp_path / "a.lock", 1.0, waiting=lambda holder: pytest.fail(f"told of {holder}")):
        pass


def test_a_wait_that_times_out_names_the_holder_and_ends_the_callback_without_its_end(tmp_path):
    lock = tmp_path / "a.lock"
    events: list[str] = []

    @contextlib.contextmanager
    def waiting(holder: locks.Holder):
        events.append("waiting")
        yield
        events.append("ended")

    holder = _held_elsewhere(lock, "-", 10)
    try:
        began = time.monotonic()
        with pytest.raises(LockTimeout) as caught:
            with locks.held(lock, 0.6, waiting=waiting, notice_after=0.2):
                pytest.fail("took a held lock")
        took = time.monotonic() - began
    finally:
        holder.kill()
        holder.wait(10)
    assert events == ["waiting"]
    assert caught.value.pid == holder.pid and f"pid {holder.pid}, " in str(caught.value)
    assert 0.6 <= took < 5  # the whole wait is bounded by the timeout, the notice included
