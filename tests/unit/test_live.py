"""The live check's pure parts (issue 52): the reader's environment (never the recording
middleware) and what a live graph cannot show, taken from the contract. Live graphs themselves are
only ever read from real processes (tests/cli/test_cli_live*.py, tests/plugin/test_plugin_live.py)."""

from __future__ import annotations

import re
import sys
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


class _FakeClock:
    """time.monotonic and time.sleep of the reader, advanced by the reader's own sleeps."""

    def __init__(self) -> None:
        self.now = 0.0

    def monotonic(self) -> float:
        return self.now

    def sleep(self, seconds: float) -> None:
        self.now += seconds


class _BurstyGraph:
    """A graph whose nodes are discovered at given times (a second burst after a quiet gap)."""

    def __init__(self, clock: _FakeClock, arrivals: dict[str, float]) -> None:
        self.clock, self.arrivals = clock, arrivals

    def spin_once(self, timeout: float) -> None:
        self.clock.now += timeout

    def signature(self):
        seen = sorted((fqn[1:], "/", "/") for fqn, at in self.arrivals.items() if at <= self.clock.now)
        return (seen, [], [], [])


def test_the_reader_waits_for_the_nodes_the_contracts_name_through_a_gap_in_discovery(monkeypatch):
    from pytest_rmw_introspect.live import ABSENT_AFTER, reader

    clock = _FakeClock()
    monkeypatch.setattr(reader, "time", clock)
    monkeypatch.setattr(reader, "say", lambda text: None)
    arrivals = {"/talker": 0.5, "/listener": 0.6, "/c_talker": 6.5}  # the second burst 6 s after the first
    settled, waited, absent = reader.wait_stable(_BurstyGraph(clock, arrivals), 1.5, 30.0)
    assert settled and absent == [] and waited < 6.5  # without --expect: read before the second burst

    clock.now = 0.0
    settled, waited, absent = reader.wait_stable(_BurstyGraph(clock, arrivals), 1.5, 30.0,
                                                 ["/talker", "/listener", "/c_talker"])
    assert settled and absent == [] and 6.5 + 1.5 <= waited < 6.5 + 3  # waited for it, then settled as usual

    clock.now = 0.0  # a node the contract names that never comes: absent once the graph was quiet long enough
    settled, waited, absent = reader.wait_stable(_BurstyGraph(clock, arrivals), 1.5, 30.0, ["/talker", "/gone"])
    assert settled and absent == ["/gone"] and ABSENT_AFTER <= waited < 6.5 + ABSENT_AFTER + 1

    clock.now = 0.0  # and --timeout bounds it all
    settled, waited, absent = reader.wait_stable(_BurstyGraph(clock, arrivals), 1.5, 5.0, ["/talker", "/gone"])
    assert not settled and absent == ["/gone"] and 5.0 <= waited < 5.5


def test_each_answer_while_watching_names_the_nodes_missing_then_not_those_missing_at_the_start(monkeypatch):
    import argparse

    from pytest_rmw_introspect.live import reader

    clock = _FakeClock()
    monkeypatch.setattr(reader, "time", clock)
    answers = []
    monkeypatch.setattr(reader, "snapshot", lambda _r, _a, live, _i, parameters: answers.append(live) or {"live": live})
    monkeypatch.setattr("builtins.print", lambda *args, **kwargs: None)
    arrivals = {"/talker": 0.0, "/c_talker": 20.0}  # came late, after the first answer said it was absent
    args = argparse.Namespace(duration=30.0, settle=1.5, expect=["/talker", "/c_talker", "/gone"])
    reader.watch(_BurstyGraph(clock, arrivals), args, {"expected_absent": ["/c_talker", "/gone"]}, "rmw_fastrtps_cpp")
    assert [answer["expected_absent"] for answer in answers] == [["/gone"]]


def test_the_nodes_to_wait_for_are_those_a_contract_names_literally(tmp_path):
    from pytest_rmw_introspect.live.check import expected_nodes, load

    (tmp_path / "a.yaml").write_text(
        "contract_version: 1\nnodes:\n"
        "  /robot/talker:\n    publishers: []\n"
        "  /anonymous_*:\n    publishers: []\n"
        "  /once:\n    destroyed_at: 0.5\n    publishers: []\n")
    (tmp_path / "b.yaml").write_text("contract_version: 1\nnodes:\n  /robot/listener:\n    subscriptions: []\n")
    contracts = [load(tmp_path / "a.yaml"), load(tmp_path / "b.yaml")]
    assert expected_nodes(contracts) == ("/robot/listener", "/robot/talker")


def test_a_node_the_contracts_name_that_did_not_come_is_a_note_not_an_error():
    graph = _graph(expected_absent=["/gone"])
    assert any("not running: /gone" in note and "10 s" in note for note in graph.notes())
    assert not [n for n in graph.notes(nodes=["/other"]) if "not running" in n]


def test_the_projects_rule_levels_apply_to_a_live_graph_as_to_a_capture(tmp_path):
    """A node someone started by hand beside the system: NODE_ADDED and PUB_ADDED, which the project turned off,
    and a QoS change it lowered to a note."""
    from test_destruction_drift import raw_endpoint, raw_node

    from pytest_rmw_introspect.live.check import check_contract

    endpoints = [raw_endpoint(10, 1, "/talker", "/chatter"), raw_endpoint(11, 2, "/by_hand", "/debug")]
    endpoints[0]["qos"] = {**endpoints[0]["qos"], "depth": 5}
    capture = Capture.from_dict({"format": "rmw_introspect_capture", "format_version": 1, "format_minor": 4,
                                 "state": "live", "nodes": [raw_node(1, "talker"), raw_node(2, "by_hand")],
                                 "endpoints": endpoints})
    graph = LiveGraph(capture=capture, domain_id=7, rmw_implementation="rmw_fastrtps_cpp", settled=True, waited=1.0,
                      settings=LiveSettings())
    (tmp_path / "robot.system.yaml").write_text(
        "system_version: 1\nlaunch: {path: robot.launch.xml}\nprocesses:\n  - {executable: talker, nodes: [/talker]}\n"
        "options:\n  rules: {'*_ADDED': 'off', QOS_DEPTH_DECREASED: note}\n"
        "nodes:\n  /talker:\n    publishers:\n      - name: /chatter\n        type: std_msgs/msg/String\n"
        "        qos: {history: KEEP_LAST, depth: 10, reliability: RELIABLE, durability: VOLATILE}\n")
    result = check_contract(tmp_path / "robot.system.yaml", graph)
    assert result.error is None, result.error
    assert [(i.rule, i.severity.name) for i in result.drift_items] == [("QOS_DEPTH_DECREASED", "NOTE")]
    assert not result.failed and result.turned_off == 2
    assert "2 findings turned off by the project's rules" in result.notes()


# ---------------------------------------------------------------------------- usage and the reader's answers


@pytest.mark.parametrize(("argv", "said"), [
    (["check", "--live", "--settle", "-1", "c.yaml"], "--settle must not be negative"),
    (["check", "--live", "--settle", "9", "--timeout", "3", "c.yaml"], "--settle 9 is longer than --timeout 3"),
    (["check", "--live", "--update", "c.yaml"], "--live does not update contracts"),
    (["check", "--live", "--package", "p", "--executable", "e", "c.yaml"], "a target to run"),
    (["check", "--live", "--launch", "robot.launch.xml", "c.yaml"], "a launch file (--launch, --launch-package) is not run"),
    (["capture", "--live", "--format", "nodl"], "writes a system contract (--format yaml) or JSON"),
    (["capture", "--live"], "give its launch file"),
    (["check", "--live", "--watch", "--format", "sarif", "c.yaml"], "--format text or json"),
    (["check", "--live", "--watch", "--duration", "0", "c.yaml"], "--duration must be positive"),
    (["check", "--live", "--watch", "--summary", "s.md", "c.yaml"], "--watch takes no --baseline"),
    (["check", "--watch", "c.yaml"], "--watch, --duration and --parameter-timeout are for a running graph"),
    (["check", "--parameter-timeout", "3", "c.yaml"], "are for a running graph: give --live too"),
    (["check", "--live", "--bag", "rec", "c.yaml"], "--live checks the running graph and --bag a recording"),
    (["capture", "--parameter-timeout", "3", "--script", "n.py"], "--parameter-timeout is for a running graph"),
])
def test_what_the_live_commands_refuse_before_joining_the_graph(tmp_path, monkeypatch, capsys, argv, said):
    from pytest_rmw_introspect import cli
    from pytest_rmw_introspect.live import graph as live_graph

    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("CI", raising=False)  # (in CI, --update is refused for being in CI first)
    (tmp_path / "c.yaml").write_text("contract_version: 1\nnodes:\n  /talker:\n    publishers: []\n")
    monkeypatch.setattr(live_graph.subprocess, "run", lambda *a, **k: pytest.fail("the graph was joined"))
    monkeypatch.setattr(live_graph.subprocess, "Popen", lambda *a, **k: pytest.fail("the graph was joined"))
    assert cli.main(argv) == 2
    assert said in capsys.readouterr().err


@pytest.mark.parametrize(("status", "said"), [
    (3, "nothing is running in ROS_DOMAIN_ID 42"), (4, "found itself on the recording middleware"),
    (1, "the live reader failed (exit status 1) in ROS_DOMAIN_ID 42"),
])
def test_each_way_the_reader_can_end_is_a_clear_error(monkeypatch, status, said):
    """The reader's exit statuses (``live.EXIT_*``), with a stand-in reader that only exits."""
    from pytest_rmw_introspect.live import graph as live_graph

    monkeypatch.setattr(live_graph, "_reader_command", lambda settings: [sys.executable, "-c", f"raise SystemExit({status})"])
    with pytest.raises(LiveGraphError, match=re.escape(said)):
        live_graph.read_graph(LiveSettings(timeout=1), ros=WHEELS_ENV, base_env={"ROS_DOMAIN_ID": "42"})


@pytest.mark.parametrize("text", ["", "{", '{"capture": {}}', '{"live": {}, "capture": {"format": "other"}}'])
def test_an_answer_the_reader_did_not_finish_is_a_clear_error(text):
    from pytest_rmw_introspect.live.graph import parse_answer

    with pytest.raises(LiveGraphError, match="the live reader's answer could not be read"):
        parse_answer(text, LiveSettings(), include_infrastructure=False, notes=[], domain="0")


def test_an_empty_answer_while_watching_is_an_empty_graph_and_every_read_note_is_said():
    from pytest_rmw_introspect.live.graph import parse_answer

    graph = parse_answer('{"live": {"domain_id": 3, "settled": false, "other_readers": ["/_rmw_introspect_live_9"], '
                         '"launchers": ["/launch_ros_12"], "parameters_unanswered": ["/a"], '
                         '"lifecycle_unanswered": ["/b"], "duplicate_nodes": {"/d": 2}}}', LiveSettings(timeout=7),
                         include_infrastructure=False, notes=[], domain="0")
    assert graph.capture.nodes == {} and graph.domain_id == 3
    notes = graph.notes()
    assert notes[0] == "the graph was still changing after 7 s (--timeout): it was read as it was then"
    assert any("other live readers" in n for n in notes) and any("parameters not read" in n and "/a" in n for n in notes)
    assert any("lifecycle state not read" in n and "/b" in n for n in notes)
    assert any(n.startswith("the node of `ros2 launch`") and n.endswith("left out of it: /launch_ros_12") for n in notes)
    assert "the graph has 2 nodes named /d: their interfaces are read together, as one node's" in notes
    assert graph.notes(nodes=["/c"]) == notes[:3]  # the rest is about other nodes


def test_a_live_view_is_written_as_a_capture_is_and_a_live_check_never_writes_a_contract():
    from pytest_rmw_introspect.errors import RmwIntrospectError
    from pytest_rmw_introspect.live.check import LiveCheckResult, LiveView

    nodes = {"/n": _node(publishers=[{"name": "/a", "type": "std_msgs/msg/String", "type_hash": "RIHS01_" + "1" * 64,
                                      "qos": "default"}])}
    view = LiveView(graph=_graph(), nodes=nodes)
    bare = view.to_contract_nodes(with_type_hash=False, with_qos=False)
    assert bare["/n"]["publishers"] == [{"name": "/a", "type": "std_msgs/msg/String"}]
    assert nodes["/n"]["publishers"][0]["qos"] == "default"  # the view itself is left as it is
    assert view.summary() == "live graph of ROS_DOMAIN_ID 7: 0 node(s): "
    with pytest.raises(RmwIntrospectError, match="capture --live -o FILE"):
        LiveCheckResult(path=Path("c.yaml"), shown="c.yaml").update()
