"""A compiled C node on rcl (C type supports, no interpreter): exact capture, time to settle."""

import rmwi_helpers as h
from rmwi_helpers import ep, node, qos


def test_c_node_capture_and_time_to_settle(run, c_node):
    result = run([c_node])
    h.assert_settled_process(result)
    n = "/c/c_talker"
    # rcl itself creates no /rosout or parameter endpoints: only what the node asked for.
    h.assert_capture(result.capture, [node("c_talker", "/c")], [
        ep("publisher", n, "/c/chatter", "std_msgs/msg/String"),
        ep("subscription", n, "/commands", "std_msgs/msg/String",
           qos(depth=3, reliability="BEST_EFFORT")),
    ])
    tts = result.capture["time_to_settle_ms"]
    print(f"C node: time_to_settle {tts:.1f} ms, spawn-to-exit {result.wall_s * 1000:.1f} ms")
    # rmw_init -> settled is a few ms of node setup, plus the settle time when the quiet window
    # decided (the process was not proven idle: docs/design.md, "Detected quiescence").
    assert (10 if result.capture["quiescence"]["window"] else 0) <= tts < 100
    assert result.wall_s < 2.0
