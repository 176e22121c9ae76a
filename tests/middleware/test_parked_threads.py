"""Threads parked in rmw_wait do not make a busy thread look idle (issue 50 item 1): a process
with a thread blocked in an executor from the start, whose main thread waits on the real clock
before it declares its parameters and creates its publishers, is settled only once that thread
woke and went on (docs/design.md, "Detected quiescence", threads still setting up). Before,
the thread census counted the main thread's wait (its deadline past the quiet window) as idle:
the capture settled at ~20 ms, the parameters declared later were not read ("no executor serves
/late/list_parameters") and what came after the wait was only seen in the warp, if at all."""

from __future__ import annotations

import rmwi_helpers as h

HORIZON = {"RMW_INTROSPECT_HORIZON_MS": "10000", "RMW_INTROSPECT_SETTLE_MS": "100"}


def test_a_thread_parked_in_an_executor_does_not_make_a_waiting_main_thread_idle(run):
    result = run(h.python_node("parked_then_sleep.py"), env=HORIZON, timeout=30)
    h.assert_settled_process(result)
    capture = result.capture
    late = next(n for n in capture["nodes"] if n["fqn"] == "/late")
    assert late["parameters_error"] is None, late["parameters_error"]
    assert {"rate", "gain"} <= {p["name"] for p in late["parameters"]}, late["parameters"]
    publishers = {e["name"]: e for e in capture["endpoints"] if e["kind"] == "publisher"}
    assert {"/after_sleep", "/after_wait"} <= set(publishers), sorted(publishers)
    # Created before the first settle, in real time: waited for, not found by the warp.
    assert publishers["/after_wait"]["created_real_ms"] >= 500
    assert capture["time_to_settle_ms"] >= 500
    assert capture["probe"]["unanswered"] == 0, capture["probe"]
