"""The runner's watchdog (run/deadline.py): what its message says, and its slack."""

from __future__ import annotations

import os

from pytest_rmw_introspect.run import deadline, process


def test_the_message_names_the_innermost_wait_and_the_target_state():
    dog = deadline.Watchdog.for_target("the talker", 20.0)
    assert dog.seconds == 20.0 + deadline.slack()
    assert "while waiting for nothing yet (setting up)" in dog.message()
    with dog.waiting("the target to start"):
        with dog.waiting("the warm start server's answer"):
            assert "while waiting for the warm start server's answer" in dog.message()
        assert "while waiting for the target to start" in dog.message()
    assert "The target: not started." in dog.message()
    dog.pid = os.getpid()
    assert f"The target: pid {os.getpid()}, R (running)" in dog.message()
    dog.now("its capture files to be read")
    message = dog.message()
    assert "passed its deadline (20 s timeout + 30 s" in message and "while waiting for its capture files" in message
    assert message.endswith("Every thread's stack:")


def test_the_slack_comes_from_the_environment_and_bad_values_keep_the_default(monkeypatch):
    monkeypatch.setenv(deadline.SLACK_ENV, "2.5")
    assert deadline.slack() == 2.5
    for bad in ("", "soon", "-1"):
        monkeypatch.setenv(deadline.SLACK_ENV, bad)
        assert deadline.slack() == deadline.SLACK_S


def test_process_state_reads_proc():
    assert process.process_state(os.getpid()).startswith("R (running)")
    assert process.process_state(2**22 + 12345) == "gone"
