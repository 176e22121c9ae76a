"""Programs that poll or never wait (issue 24): a poll of rmw_wait (timeout 0) counts towards the
settle like an activity call, a thread that polls back to back and finds nothing is proven idle
(docs/design.md, "Detected quiescence", idle pollers), the warp ends as soon as it sees that the
program never waits with a timeout (nothing to jump to) and says so, and a capture that does not
settle names what was seen instead of blaming changes that never happened."""

from __future__ import annotations

import pytest
import rmwi_helpers as h
from rmwi_helpers import ep, node
from rmwi_helpers import rclpy_node_infrastructure as infra

from pytest_rmw_introspect.run import runner
from pytest_rmw_introspect.run.target import TargetSpec

HORIZON = {"RMW_INTROSPECT_HORIZON_MS": "10000", "RMW_INTROSPECT_SETTLE_MS": "100"}
# A quiet window far longer than an idle run (10 ms): on a busy machine a process that is still
# warming up (page faults, lazy imports: it blocks between its first polls) may otherwise reach
# the 100 ms window first, which is the fallback working, not what these tests look at.
DETECT = {"RMW_INTROSPECT_HORIZON_MS": "10000", "RMW_INTROSPECT_SETTLE_MS": "1000"}


def test_a_loop_of_zero_timeout_polls_settles_and_says_the_horizon_was_not_observed(run):
    result = run(h.python_node("poll_loop.py"), env=HORIZON, timeout=20)
    h.assert_settled_process(result)
    n = "/poller"
    h.assert_capture(result.capture, [node("poller")],
                     infra(n) + [ep("publisher", n, "/polled", "std_msgs/msg/String"),
                                 ep("subscription", n, "/never", "std_msgs/msg/String")])
    assert result.capture["settled_by"] == "poll"
    assert result.capture["quiescence"]["polls"] >= 2
    vt = result.capture["time"]
    assert vt["warp_stalled"] is True and vt["warp_budget_exhausted"] is False and vt["jumps"] == 0


def test_a_loop_of_idle_polls_is_proven_idle_instead_of_waited_for(run):
    """Its first settle ends by detection (not the quiet window), the warp stalls on the same
    proof, and the final settle is the first one again: no settle waits for the window."""
    result = run(h.python_node("poll_loop.py"), env=DETECT, timeout=20)
    h.assert_settled_process(result)
    q = result.capture["quiescence"]
    assert q["detected"] == 1 and q["window"] == 0, q
    assert result.capture["settled_by"] == "poll"
    assert result.capture["time"]["warp_stalled"] is True


def test_the_same_loop_without_detection_waits_for_the_quiet_window(run):
    result = run(h.python_node("poll_loop.py"), env={**DETECT, "RMW_INTROSPECT_IDLE": "0"}, timeout=20)
    h.assert_settled_process(result)
    q = result.capture["quiescence"]
    assert q["detected"] == 0 and q["window"] == 1, q


@pytest.mark.parametrize("script,loop,not_loop", [
    ("poll_loop.py", "without pausing: a busy loop", "sleeps on the real clock"),
    # (its sleeps on the real clock: RMW_INTROSPECT_SLEEPS=0, or a sleep the middleware does not
    # see - select(), a timed condition wait)
    ("sleep_poll_loop.py", "sleeps on the real clock", "busy loop"),
])
def test_the_capture_of_a_polling_loop_notes_that_virtual_time_could_not_advance(script, loop, not_loop):
    cap = runner.run(TargetSpec.from_mapping(
        {"script": str(h.NODES / script), "timeout": 20, "env": {"RMW_INTROSPECT_SLEEPS": "0"}}))
    assert cap.state == "settled"
    (note,) = [n for n in cap.notes() if "virtual time stopped" in n]
    assert "never waited with a timeout" in note and "zero-timeout polls of its executor" in note
    assert loop in note and not_loop not in note, note  # which loop it was, as the middleware counted it
    assert "very fast timer" not in note  # it has no timer at all


def test_a_task_spun_by_spin_once_that_never_ends_is_captured_at_once():
    """stuck_task.py awaits an answer that never comes in a spin_once loop (issue 24 item 5):
    measured, rclpy's spin_once(node) adds and removes the node (two triggers of the executor's
    guard condition), yields the pending task again and, on the next call, waits in rmw_wait
    (no timeout) - which returns at once on that guard condition. Such a wait counts as a poll:
    the warp stalls, the final settle comes from the polls, and the capture is what it had."""
    cap = runner.run(TargetSpec.from_mapping({"script": str(h.NODES / "stuck_task.py"), "timeout": 10}))
    assert cap.state == "settled" and cap.settled_by == "poll"
    assert cap["/stuck_task"].names("service_clients") == ["/nobody_answers"]
    vt = cap.virtual_time
    assert vt is not None and vt.jumps >= 1  # the timer's 0.5 s were jumped
    # the warp stalls (or, on a very busy machine, spends its 3 s budget first)
    assert vt.warp_stalled or vt.warp_budget_exhausted
    (note,) = [n for n in cap.notes() if "virtual time stopped" in n]
    assert "a task that awaits an answer that never comes" in note
    assert "very fast timer" not in note


def test_an_rcl_c_node_that_polls_rcl_wait_with_a_zero_timeout_settles_by_its_polls(run, c_node):
    """rmwi_c_timer_node poll: `rcl_wait(&wait_set, 0)` in a loop (issue 24 item 6, the C side):
    the polls settle it, the warp stalls at once (nothing to jump to) instead of spending its
    real-time budget, and the note says why. `make bench` measures it against a plain capture."""
    result = run([c_node.parent / "rmwi_c_timer_node", "poll"], env=HORIZON, timeout=20)
    h.assert_settled_process(result)
    assert result.capture["settled_by"] == "poll"
    vt = result.capture["time"]
    assert vt["warp_stalled"] is True and vt["warp_budget_exhausted"] is False and vt["jumps"] == 0
    assert [n["name"] for n in result.capture["nodes"]] == ["c_timer"]


def test_an_rcl_c_node_polling_rcl_wait_is_proven_idle(run, c_node):
    result = run([c_node.parent / "rmwi_c_timer_node", "poll"], env=DETECT, timeout=20)
    h.assert_settled_process(result)
    q = result.capture["quiescence"]
    assert q["detected"] == 1 and q["window"] == 0, q  # proven idle, not waited for
    assert result.capture["settled_by"] == "poll" and result.capture["time"]["warp_stalled"] is True


@pytest.mark.parametrize("polls", [200, 1000])
def test_a_bounded_loop_of_polls_that_then_creates_a_publisher_is_captured_with_it(run, c_node, polls):
    """rmwi_c_timer_node poll N: N zero-timeout polls that find nothing (far more than the 20 of an
    idle run, in a few milliseconds: much less than the settle), then a publisher, then polls on.
    A count of polls alone proves nothing: the run must also last 10 ms, so the publisher is in."""
    result = run([c_node.parent / "rmwi_c_timer_node", "poll", str(polls)], env=DETECT, timeout=20)
    h.assert_settled_process(result)
    assert "/c/after_polls" in [e["name"] for e in result.capture["endpoints"] if e["kind"] == "publisher"]
    assert result.capture["quiescence"]["detected"] >= 1


def test_a_program_waiting_on_its_own_nodes_service_is_captured_with_a_note():
    cap = runner.run(TargetSpec.from_mapping({"script": str(h.NODES / "self_client.py"), "timeout": 20}))
    assert cap.state == "settled"
    names = [e.name for e in cap.endpoints()]
    assert "/ping" in names and "/after_answer" not in names
    (note,) = [n for n in cap.notes() if "/ping" in n]
    assert "node /self_caller has a client of /ping, a service of its own node" in note
    assert "never answered" in note
