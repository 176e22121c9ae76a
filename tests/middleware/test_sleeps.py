"""The process's sleeps on virtual time (issue 24; docs/design.md, "Sleeps"): the preloaded
middleware defines the C library's nanosleep, clock_nanosleep, usleep and sleep (src/sleep.cpp).
In the warp a sleep jumps virtual time by its duration and returns at once, like a wait with a
timeout; a thread that used ROS since the last change and sleeps is in its loop and proves the
process idle. Everything else - no session, bad arguments, other clocks, signals - behaves as the
C library does."""

from __future__ import annotations

import json
import signal
import subprocess
import time

import rmwi_helpers as h

HORIZON = {"RMW_INTROSPECT_HORIZON_MS": "10000", "RMW_INTROSPECT_SETTLE_MS": "100"}


def _publishers(capture: dict) -> dict[str, dict]:
    return {e["name"]: e for e in capture["endpoints"] if e["kind"] == "publisher"}


def test_a_python_sleep_loop_is_stepped_and_what_it_creates_later_is_captured(run):
    """sleep_then_create.py: publish; time.sleep(0.5), and after 6 sleeps a second publisher.
    Before, the loop settled by its publishes and the warp had nothing to jump: the publisher
    created after 3 s of sleeps was not in the capture."""
    result = run(h.python_node("sleep_then_create.py"), env=HORIZON, timeout=30)
    h.assert_settled_process(result)
    publishers = _publishers(result.capture)
    assert "/after_sleeps" in publishers, sorted(publishers)
    assert publishers["/after_sleeps"]["created_virtual_ms"] >= 3000
    assert publishers["/after_sleeps"]["created_real_ms"] < 3000  # jumped, not slept
    assert result.capture["settled_by"] == "sleep"
    vt = result.capture["time"]
    assert vt["horizon_reached"] is True and vt["jumps"] >= 15, vt


def test_with_sleeps_on_the_real_clock_the_same_loop_loses_what_it_creates_later(run):
    result = run(h.python_node("sleep_then_create.py"),
                 env={**HORIZON, "RMW_INTROSPECT_SLEEPS": "0"}, timeout=30)
    h.assert_settled_process(result)
    assert "/after_sleeps" not in _publishers(result.capture)
    assert result.capture["time"]["jumps"] == 0


def test_an_rcl_c_node_sleeping_with_nanosleep_and_usleep_is_stepped(run, c_node):
    """rmwi_c_timer_node sleep: publish, then nanosleep or usleep 0.1 s by turns, and after the
    30th sleep a second publisher: C's sleeps are stepped like Python's."""
    result = run([c_node.parent / "rmwi_c_timer_node", "sleep"], env=HORIZON, timeout=30)
    h.assert_settled_process(result)
    publishers = _publishers(result.capture)
    assert {"/c/looped", "/c/after_sleeps"} <= set(publishers), sorted(publishers)
    assert publishers["/c/after_sleeps"]["created_virtual_ms"] >= 3000
    assert result.capture["settled_by"] == "sleep"
    assert result.capture["time"]["jumps"] >= 30


def test_a_signal_ends_a_sleep_of_the_middleware_like_one_of_the_c_library(middleware_library, tmp_path):
    """interrupted_sleep.py sleeps 60 s after its publish: the capture settles on that sleep (past
    the horizon, it sleeps for real), and SIGINT still ends it at once (EINTR: Python raises
    KeyboardInterrupt; the script prints "interrupted" and exits 0)."""
    capture = tmp_path / "capture.json"
    proc = h.spawn(middleware_library, h.python_node("interrupted_sleep.py"), capture,
                   env={**HORIZON, "RMW_INTROSPECT_EXIT": "0"})
    try:
        settled = h.wait_for(lambda: h.read_capture_if(capture, state="settled"), timeout=30)
        assert settled["settled_by"] == "sleep"
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=10)
    finally:
        h.stop(proc)
    assert "interrupted" in out, (out, err)
    assert proc.returncode == 0, (proc.returncode, err)


def test_outside_the_warp_and_with_bad_arguments_the_sleeps_are_the_c_librarys(run):
    """Before rclpy.init (no session) and after it (before any warp): NULL, out-of-range and
    negative requests fail as the C library's do, another clock and time.sleep sleep for real."""
    result = run(h.python_node("sleep_arguments.py"), env=HORIZON, exit_on_settle=False, timeout=30)
    assert result.returncode == 0, result
    seen = json.loads(result.stdout.strip().splitlines()[-1])
    einval, efault = 22, 14
    for when in ("before", "after"):
        s = seen[when]
        assert s["nanosleep_null"] == [-1, efault], (when, s)
        assert s["nanosleep_bad_nsec"] == [-1, einval], (when, s)
        assert s["nanosleep_negative"] == [-1, einval], (when, s)
        assert s["clock_nanosleep_bad_clock"] == einval, (when, s)
        assert s["clock_nanosleep_null"] == efault, (when, s)
        assert s["clock_nanosleep_past"] == 0 and s["usleep"] == 0 and s["sleep_zero"] == 0, (when, s)
        assert s["clock_nanosleep_boottime"] == 0 and s["boottime_slept"] >= 0.05, (when, s)
        assert s["usleep_slept"] >= 0.05 and s["time_sleep_slept"] >= 0.05, (when, s)


def test_a_process_that_never_starts_ros_sleeps_for_real(middleware_library):
    """The library is preloaded into every process of a target (shells, `sleep`, helpers): with no
    session its sleeps go straight to the C library."""
    env = h.ros_environment({"LD_PRELOAD": str(middleware_library), **HORIZON})
    t0 = time.monotonic()
    done = subprocess.run(["sleep", "0.2"], env=env, timeout=10)
    assert done.returncode == 0 and time.monotonic() - t0 >= 0.2


def test_a_child_forked_in_the_warp_sleeps_for_real(run):
    result = run(h.python_node("fork_sleep.py"), env=HORIZON, exit_on_settle=False, timeout=30)
    assert result.returncode == 0, result
    assert result.capture is not None and result.capture["time"]["jumps"] >= 1  # forked in the warp
    slept = float(result.stdout.split("child slept")[1].split()[0])
    assert slept >= 0.2, result.stdout
