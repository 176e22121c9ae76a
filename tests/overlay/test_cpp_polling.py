"""rclcpp programs that do not block in their executor the usual way (issue 24 item 6), built from
tests/overlay/cpp_polling over the overlay and captured with the default options (10 s horizon):
an action client driven by `while (!done) spin_some(node)` whose goal is never answered, a node
whose timers all cancel themselves (spun by rclcpp::spin and by a MultiThreadedExecutor), a
`publish; sleep_for(10ms); spin_some` loop (its sleeps stepped by the warp) and a 2 Hz WallRate
loop. Each is captured with every entity it creates, and the notes say what the program did when
the horizon was not observed.
How long each takes against a plain capture is measured in bench/ (bench_cpp_polling.py), never
asserted here."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from overlay_support import REPO, cmake_build

CLI = [sys.executable, "-m", "pytest_rmw_introspect"]
SOURCES = REPO / "tests" / "overlay" / "cpp_polling"

# the first test of a session may build the programs (a few minutes on 2 cores)
pytestmark = pytest.mark.timeout(1800)


@pytest.fixture(scope="module")
def programs(overlay) -> Path:
    return cmake_build(overlay, SOURCES, "cpp_polling") / "install" / "lib" / "rmwi_cpp_polling"


def capture(overlay, command: list[str], options: tuple[str, ...] = ()) -> tuple[dict, list[str]]:
    """The raw capture of ``command`` (default options but ``options``) and the notes the CLI printed."""
    out = subprocess.run([*CLI, "capture", "--raw", "--format", "json", *options, "--", *command], env=overlay.env(),
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    notes = [line.removeprefix("note: ") for line in out.stderr.splitlines() if line.startswith("note: ")]
    return json.loads(out.stdout), notes


def own_endpoints(doc: dict, fqn: str) -> set[tuple[str, str, str]]:
    """(kind, name, type) of the node's endpoints alive at the end, without rclcpp's own."""
    infrastructure = ("/rosout", "/parameter_events", f"{fqn}/get_", f"{fqn}/set_parameters", f"{fqn}/describe_",
                      f"{fqn}/list_parameters")
    return {(e["kind"], e["name"], e["type"]) for e in doc["endpoints"]
            if e["node"] == fqn and not e["destroyed"] and not e["name"].startswith(infrastructure)}


def horizon_note(notes: list[str]) -> str:
    (note,) = [n for n in notes if n.startswith("virtual time stopped")]
    assert "never waited with a timeout" in note and "very fast timer" not in note
    return note


def test_an_action_client_polled_by_spin_some_until_an_answer_that_never_comes(overlay, programs):
    doc, notes = capture(overlay, [str(programs / "action_poller")])
    assert doc["state"] == "settled" and [n["fqn"] for n in doc["nodes"]] == ["/action_poller"]
    action = "test_msgs/action/Fibonacci"
    assert own_endpoints(doc, "/action_poller") == {
        ("publisher", "/poller_status", "std_msgs/msg/String"),
        ("client", "/fibonacci/_action/send_goal", f"{action}_SendGoal"),
        ("client", "/fibonacci/_action/cancel_goal", "action_msgs/srv/CancelGoal"),
        ("client", "/fibonacci/_action/get_result", f"{action}_GetResult"),
        ("subscription", "/fibonacci/_action/feedback", f"{action}_FeedbackMessage"),
        ("subscription", "/fibonacci/_action/status", "action_msgs/msg/GoalStatusArray"),
    }
    assert doc["probe"]["state"] == "done" and doc["probe"]["unanswered"] == 0  # spin_some answers the probes
    vt = doc["time"]
    assert vt["warp_stalled"] and not vt["warp_budget_exhausted"] and vt["jumps"] == 0
    assert vt["warp_polls"] > 0
    note = horizon_note(notes)
    assert "without pausing" in note and "busy loop at full CPU" in note, note


def test_the_spin_some_action_client_is_proven_idle_by_its_polls(overlay, programs):
    """Its spin_some polls find nothing (docs/design.md, "Detected quiescence", idle pollers): the
    settle is detected, not waited for, and the warp stalls on the same proof. A 1 s quiet window
    makes a fallback to it unmistakable on a busy machine."""
    doc, _notes = capture(overlay, [str(programs / "action_poller")], ("--settle", "1"))
    assert doc["state"] == "settled" and doc["settled_by"] == "poll"
    assert doc["quiescence"]["detected"] >= 1 and doc["quiescence"]["window"] == 0, doc["quiescence"]
    assert doc["time"]["warp_stalled"] and doc["time"]["jumps"] == 0


@pytest.mark.parametrize("executor", [[], ["multi"]], ids=["spin", "multi_threaded"])
def test_a_node_whose_timers_all_cancel_themselves(overlay, programs, executor):
    doc, notes = capture(overlay, [str(programs / "cancelled_timers"), *executor])
    assert doc["state"] == "settled"
    assert own_endpoints(doc, "/cancelled_timers") == {("publisher", "/after_timers", "std_msgs/msg/String")}
    [created] = [e for e in doc["endpoints"] if e["name"] == "/after_timers"]
    assert created["created_virtual_ms"] >= 250  # by the second timer, jumped to
    vt = doc["time"]
    assert vt["jumps"] >= 2 and not vt["warp_stalled"] and not vt["warp_budget_exhausted"]
    # nothing is left to wait for after the timers: it is idle for ever, and no horizon note is due
    assert doc["settled_by"] == "wait"
    assert not [n for n in notes if n.startswith("virtual time stopped")]


def test_a_sleep_for_loop_is_stepped_by_the_warp(overlay, programs):
    """`publish; sleep_for(10ms); spin_some`: std::this_thread::sleep_for reaches the middleware's
    nanosleep (docs/design.md, "Sleeps"): the loop is proven idle while it sleeps, the warp jumps
    its sleeps like a 10 ms timer (fast-forwarded to the horizon), and no horizon note is due."""
    doc, notes = capture(overlay, [str(programs / "sleep_loop")])
    assert doc["state"] == "settled"
    assert own_endpoints(doc, "/sleep_loop") == {("publisher", "/sleep_chatter", "std_msgs/msg/String"),
                                                 ("subscription", "/sleep_commands", "std_msgs/msg/String")}
    vt = doc["time"]
    assert vt["horizon_reached"] and not vt["warp_stalled"] and vt["jumps"] >= 100, vt
    assert doc["settled_by"] == "sleep"
    assert not [n for n in notes if n.startswith("virtual time stopped")]


def test_a_sleep_for_loop_with_real_sleeps_is_noted_as_sleeping_on_the_real_clock(overlay, programs):
    doc, notes = capture(overlay, [str(programs / "sleep_loop")], ("--env", "RMW_INTROSPECT_SLEEPS=0"))
    assert doc["state"] == "settled"
    assert doc["time"]["warp_stalled"] and doc["time"]["jumps"] == 0
    note = horizon_note(notes)
    assert "sleeps on the real clock" in note and "busy loop" not in note, note


def test_a_wall_rate_loop_is_noted_as_sleeping_on_the_real_clock(overlay, programs):
    doc, notes = capture(overlay, [str(programs / "wall_rate_loop")])
    assert doc["state"] == "settled"
    assert own_endpoints(doc, "/wall_rate_loop") == {("publisher", "/rate_chatter", "std_msgs/msg/String")}
    vt = doc["time"]
    assert vt["warp_stalled"] and vt["jumps"] == 0 and not vt["horizon_reached"]
    note = horizon_note(notes)
    assert "of the 10 s horizon" in note and "sleeps on the real clock" in note, note
    assert "busy loop" not in note
