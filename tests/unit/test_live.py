"""The live check's pure parts (issue 52): the reader's environment (never the recording
middleware) and what a live graph cannot show, taken from the contract. Live graphs themselves are
only ever read from real processes (tests/cli/test_cli_live*.py, tests/plugin/test_plugin_live.py)."""

from __future__ import annotations

from pathlib import Path

import pytest

from pytest_rmw_introspect.errors import LiveGraphError
from pytest_rmw_introspect.live.check import observable
from pytest_rmw_introspect.live.graph import LiveGraph, LiveSettings, reader_environment
from pytest_rmw_introspect.model.capture import Capture
from pytest_rmw_introspect.run.ros_env import WHEELS, RosEnvironment

WHEELS_ENV = RosEnvironment(kind=WHEELS, prefix=Path("/venv"), distro="jazzy", library_dirs=(Path("/venv/lib"),))


def test_the_reader_never_runs_on_the_recording_middleware():
    with pytest.raises(LiveGraphError, match="is the recording middleware"):
        reader_environment(WHEELS_ENV, {"RMW_IMPLEMENTATION": "rmw_introspect_cpp"})
    with pytest.raises(LiveGraphError, match="rmw_cyclonedds_cpp names a middleware that is not installed here"):
        reader_environment(WHEELS_ENV, {"RMW_IMPLEMENTATION": "rmw_cyclonedds_cpp"})
    env, notes = reader_environment(WHEELS_ENV, {
        "LD_PRELOAD": "/usr/lib/libasan.so /cache/lib/librmw_introspect_cpp.so", "RMW_INTROSPECT_OUTPUT": "/tmp/x",
        "RMW_IMPLEMENTATION": "rmw_fastrtps_cpp", "ROS_DOMAIN_ID": "7"})
    assert env["LD_PRELOAD"] == "/usr/lib/libasan.so" and "RMW_INTROSPECT_OUTPUT" not in env
    assert env["RMW_IMPLEMENTATION"] == "rmw_fastrtps_cpp" and env["ROS_DOMAIN_ID"] == "7"
    assert notes and "runs without it" in notes[0]
    assert reader_environment(WHEELS_ENV, {})[1] == []


def _graph(**unanswered: list[str]) -> LiveGraph:
    empty = Capture.from_dict({"format": "rmw_introspect_capture", "format_version": 1})
    return LiveGraph(capture=empty, domain_id=7, rmw_implementation="rmw_fastrtps_cpp", settled=True, waited=1.0,
                     settings=LiveSettings(), **unanswered)


def _node(**lists):
    return {"publishers": [], "subscriptions": [], "service_servers": [], "service_clients": [], "action_servers": [],
            "action_clients": [], **lists}


def test_what_the_graph_cannot_show_is_taken_from_the_contract_and_noted():
    expected = {"/n": _node(
        publishers=[{"name": "/a", "type": "std_msgs/msg/String", "qos": {"history": "KEEP_LAST", "depth": 5,
                                                                          "reliability": "SYSTEM_DEFAULT",
                                                                          "durability": "VOLATILE"}},
                    {"name": "/b", "type": "std_msgs/msg/String", "qos": "default"}],
        service_servers=[{"name": "/s", "type": "std_srvs/srv/Trigger", "type_hash": "RIHS01_" + "1" * 64}],
        parameters=[{"name": "rate", "type": "double", "default_value": 5.0}])}
    live = {"/n": _node(
        publishers=[{"name": "/a", "type": "std_msgs/msg/String", "qos": {"history": "UNKNOWN", "reliability": "RELIABLE",
                                                                          "durability": "VOLATILE",
                                                                          "liveliness": "AUTOMATIC"}},
                    {"name": "/b", "type": "std_msgs/msg/String", "qos": {"history": "UNKNOWN", "reliability": "BEST_EFFORT",
                                                                          "durability": "VOLATILE"}}],
        service_servers=[{"name": "/s", "type": "std_srvs/srv/Trigger"}])}
    seen, notes = observable(expected, live, _graph(parameters_unanswered=["/n"]))
    a, b = seen["/n"]["publishers"]
    assert a["qos"] == {"history": "KEEP_LAST", "depth": 5, "reliability": "SYSTEM_DEFAULT", "durability": "VOLATILE"}
    assert b["qos"]["reliability"] == "BEST_EFFORT"  # what the graph shows differs: kept, it is drift
    assert seen["/n"]["service_servers"][0]["type_hash"] == "RIHS01_" + "1" * 64
    assert seen["/n"]["parameters"] == expected["/n"]["parameters"]  # not read: as the contract states them
    assert any("type hashes of services" in n and "(/n)" in n for n in notes)
    assert any("QoS history and depth, which the middleware does not report" in n for n in notes)
    assert any("QoS reliability the contract leaves to the middleware" in n for n in notes)
    assert "qos" in live["/n"]["publishers"][0] and live["/n"]["publishers"][0]["qos"]["history"] == "UNKNOWN"  # untouched
