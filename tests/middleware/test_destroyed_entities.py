"""What a program destroys while it runs is part of its interface (issue 24 item 4): the
middleware records the virtual and real age of each destruction the program makes (not its final
teardown), and the capture view and contract keep the entity with ``destroyed_at``."""

from __future__ import annotations

import rmwi_helpers as h

from pytest_rmw_introspect.model.capture import Capture
from pytest_rmw_introspect.run import runner
from pytest_rmw_introspect.run.target import TargetSpec

HORIZON = {"RMW_INTROSPECT_HORIZON_MS": "10000"}


def _record(records, name):
    return next(r for r in records if r["name"] == name)


def _assert_destroyed_about_8s(record):
    assert record["destroyed"] is True and record["in_teardown"] is False
    # the timer's 8 s count from its creation, a little after the first rmw_init
    assert 8000 <= record["destroyed_virtual_ms"] < 9000, record
    assert record["destroyed_real_ms"] < record["destroyed_virtual_ms"]


def test_an_rclpy_program_that_destroys_a_node_and_a_publisher_after_8_s(run):
    result = run(h.python_node("vt_destroys_at_8s.py"), env=HORIZON, timeout=30)
    h.assert_settled_process(result)
    raw = result.capture
    assert raw["format_minor"] >= 4
    _assert_destroyed_about_8s(_record(raw["nodes"], "doomed"))
    _assert_destroyed_about_8s(_record(raw["endpoints"], "/status"))
    _assert_destroyed_about_8s(_record(raw["endpoints"], "/heartbeat"))  # with its node
    alive = _record(raw["endpoints"], "/alive")
    assert alive["destroyed"] is False and alive["destroyed_virtual_ms"] is None
    assert _record(raw["nodes"], "survivor")["destroyed_virtual_ms"] is None

    nodes = Capture.from_dict(raw).to_contract_nodes(with_type_hash=False, with_qos=False)
    doomed_at = nodes["/doomed"]["destroyed_at"]
    assert 8.0 <= doomed_at < 9.0
    assert nodes["/doomed"]["publishers"] == [{"name": "/heartbeat", "type": "std_msgs/msg/String"}]
    assert nodes["/doomed"]["service_servers"] == [{"name": "/doomed/ping", "type": "std_srvs/srv/Empty"}]
    assert "destroyed_at" not in nodes["/survivor"]
    assert nodes["/survivor"]["publishers"] == [
        {"name": "/alive", "type": "std_msgs/msg/String"},
        {"name": "/status", "type": "std_msgs/msg/String", "destroyed_at": doomed_at}]


def test_the_runner_keeps_what_was_destroyed_and_a_shorter_horizon_never_sees_it():
    script = str(h.NODES / "vt_destroys_at_8s.py")
    cap = runner.run(TargetSpec.from_mapping({"script": script, "timeout": 30}))  # default horizon: 10 s
    assert cap.node_names == ["/doomed", "/survivor"]
    assert 8.0 <= (cap["/doomed"].destroyed_at or 0) < 9.0
    assert "(destroyed by the program at" in cap.summary()
    short = runner.run(TargetSpec.from_mapping({"script": script, "timeout": 30, "horizon": 5}))
    assert short["/doomed"].destroyed_at is None
    assert short["/survivor"].get("publishers", "/status").destroyed_at is None


def test_an_rcl_c_node_that_destroys_its_publisher_after_8_s(run, c_node):
    result = run([c_node.parent / "rmwi_c_timer_node", "destroy"], env=HORIZON, timeout=30)
    h.assert_settled_process(result)
    doomed = _record(result.capture["endpoints"], "/c/doomed")
    assert doomed["destroyed"] is True and doomed["in_teardown"] is False
    assert 8000 <= doomed["destroyed_virtual_ms"] < 9000, doomed
    nodes = Capture.from_dict(result.capture).to_contract_nodes(with_type_hash=False, with_qos=False)
    assert nodes["/c/c_timer"]["publishers"] == [
        {"name": "/c/doomed", "type": "std_msgs/msg/String",
         "destroyed_at": round(doomed["destroyed_virtual_ms"] / 1000, 1)}]
