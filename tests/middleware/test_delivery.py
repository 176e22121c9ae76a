"""In-process delivery (RMW_INTROSPECT_DELIVERY=1) in a real rclpy process: a message and a
service call reach their receivers in the same process, and what the receivers create then
is recorded. Off (the default), nothing arrives and the capture is what it always was."""

import rmwi_helpers as h

NODE = h.python_node("in_process.py")


def names(capture, kind):
    return {e["name"] for e in capture["endpoints"] if e["kind"] == kind}


def test_delivery_on_reaches_the_receivers_of_the_process(run):
    result = run(NODE, env={"RMW_INTROSPECT_DELIVERY": "1"}, timeout=20.0)
    assert result.returncode == 0, str(result)
    assert "heard: hello in process" in result.stdout, str(result)
    assert "answered: success=True" in result.stdout, str(result)
    assert {"/chatter", "/heard", "/answered"} <= names(result.capture, "publisher")
    assert result.capture["state"] == "settled"


def test_delivery_off_by_default_nothing_arrives(run):
    result = run(NODE, timeout=20.0)
    assert result.returncode == 0, str(result)
    assert "heard:" not in result.stdout and "answered:" not in result.stdout, str(result)
    publishers = names(result.capture, "publisher")
    assert "/chatter" in publishers
    assert not {"/heard", "/answered"} & publishers
