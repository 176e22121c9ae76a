"""Capture parsing, action grouping, infrastructure filtering and the contract view."""

from __future__ import annotations

import copy
import dataclasses
import json
from pathlib import Path

import pytest
from sample_contracts import STRING_HASH

import pytest_rmw_introspect
from pytest_rmw_introspect.errors import CaptureFormatError
from pytest_rmw_introspect.model.capture import Capture, OtherProcess, RunFacts
from pytest_rmw_introspect.model.capture_file import Endpoint
from pytest_rmw_introspect.model.capture_view import is_infrastructure

HASH = "RIHS01_" + "ab" * 32

DEFAULT_QOS = {
    "history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE",
    "liveliness": "SYSTEM_DEFAULT", "deadline_ns": 0, "lifespan_ns": 0,
    "liveliness_lease_duration_ns": 0, "avoid_ros_namespace_conventions": False,
}
ROSOUT_QOS = dict(DEFAULT_QOS, depth=1000, durability="TRANSIENT_LOCAL", lifespan_ns=10_000_000_000)
PARAM_QOS = dict(DEFAULT_QOS, depth=1000)
STATUS_QOS = dict(DEFAULT_QOS, depth=1, durability="TRANSIENT_LOCAL")
SENSOR_QOS = dict(DEFAULT_QOS, depth=5, reliability="BEST_EFFORT")

PARAM_SERVICES = {
    "describe_parameters": "rcl_interfaces/srv/DescribeParameters",
    "get_parameter_types": "rcl_interfaces/srv/GetParameterTypes",
    "get_parameters": "rcl_interfaces/srv/GetParameters",
    "list_parameters": "rcl_interfaces/srv/ListParameters",
    "set_parameters": "rcl_interfaces/srv/SetParameters",
    "set_parameters_atomically": "rcl_interfaces/srv/SetParametersAtomically",
    "get_type_description": "type_description_interfaces/srv/GetTypeDescription",
}


class Builder:
    """Writes capture documents the way the middleware does (design.md section 1)."""

    def __init__(self, state: str = "settled") -> None:
        self.seq = 0
        self.doc = {
            "format": "rmw_introspect_capture",
            "format_version": 1,
            "rmw_implementation": "rmw_introspect_cpp",
            "pid": 4242,
            "argv": ["/usr/bin/python3", "node.py"],
            "state": state,
            "settle_ms": 10,
            "time_to_settle_ms": 31.7,
            "elapsed_ms": 31.9,
            "nodes": [],
            "endpoints": [],
        }

    def _next(self) -> int:
        self.seq += 1
        return self.seq

    def node(self, name: str, namespace: str = "/", *, infrastructure: bool = True, destroyed: bool = False) -> int:
        node_id = len(self.doc["nodes"]) + 1
        fqn = ("/" if namespace == "/" else namespace + "/") + name
        self.doc["nodes"].append(
            {"id": node_id, "seq": self._next(), "name": name, "namespace": namespace, "fqn": fqn,
             "enclave": "/", "destroyed": destroyed}
        )
        if infrastructure:
            self.ep(node_id, "publisher", "/rosout", "rcl_interfaces/msg/Log", ROSOUT_QOS)
            self.ep(node_id, "publisher", "/parameter_events", "rcl_interfaces/msg/ParameterEvent", PARAM_QOS)
            for srv, srv_type in PARAM_SERVICES.items():
                self.ep(node_id, "service", f"{fqn}/{srv}", srv_type, PARAM_QOS)
        return node_id

    def ep(self, node_id: int, kind: str, name: str, type_: str, qos=None, *, type_hash=HASH, destroyed=False):
        node = self.doc["nodes"][node_id - 1]
        self.doc["endpoints"].append(
            {"seq": self._next(), "kind": kind, "node_id": node_id, "node": node["fqn"], "name": name,
             "type": type_, "type_hash": type_hash, "typesupport": "rosidl_typesupport_c",
             "qos": dict(qos or DEFAULT_QOS), "destroyed": destroyed}
        )

    def action(self, node_id: int, name: str, action_type: str, *, server: bool = True):
        srv, topic = ("service", "publisher") if server else ("client", "subscription")
        self.ep(node_id, srv, f"{name}/_action/send_goal", f"{action_type}_SendGoal", type_hash="RIHS01_" + "01" * 32)
        self.ep(node_id, srv, f"{name}/_action/cancel_goal", "action_msgs/srv/CancelGoal")
        self.ep(node_id, srv, f"{name}/_action/get_result", f"{action_type}_GetResult", type_hash="RIHS01_" + "02" * 32)
        self.ep(node_id, topic, f"{name}/_action/feedback", f"{action_type}_FeedbackMessage", type_hash="RIHS01_" + "03" * 32)
        self.ep(node_id, topic, f"{name}/_action/status", "action_msgs/msg/GoalStatusArray", STATUS_QOS)

    def capture(self, **kwargs) -> Capture:
        return Capture.from_dict(copy.deepcopy(self.doc), **kwargs)


@pytest.fixture
def talker() -> Builder:
    b = Builder()
    t = b.node("talker")
    b.ep(t, "publisher", "/chatter", "std_msgs/msg/String", type_hash=STRING_HASH)
    return b


# ---------------------------------------------------------------------------- parsing


def test_talker_contract_view(talker):
    cap = talker.capture()
    assert cap.node_names == ["/talker"]
    assert cap.state == "settled" and cap.settled
    node = cap["/talker"]
    assert [p.name for p in node.publishers] == ["/chatter"]
    assert node.subscriptions == node.service_servers == node.action_servers == []
    assert cap.to_contract_nodes() == {
        "/talker": {
            "publishers": [
                {"name": "/chatter", "type": "std_msgs/msg/String", "type_hash": STRING_HASH,
                 "qos": {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE"}}
            ],
            "subscriptions": [],
            "service_servers": [],
            "service_clients": [],
            "action_servers": [],
            "action_clients": [],
        }
    }


def test_raw_endpoints_stay_available(talker):
    cap = talker.capture()
    names = [e.name for e in cap.endpoints()]
    assert "/rosout" in names and "/talker/get_parameters" in names and "/chatter" in names
    assert cap["/talker"].publishers[0].raw_qos["liveliness"] == "SYSTEM_DEFAULT"
    assert cap.raw_nodes[0].fqn == "/talker"
    assert cap.pid == 4242 and cap.time_to_settle_ms == 31.7


def test_include_infrastructure_keeps_rosout_and_parameter_services(talker):
    cap = talker.capture(include_infrastructure=True)
    node = cap["/talker"]
    assert node.names("publishers") == ["/chatter", "/parameter_events", "/rosout"]
    assert "/talker/get_type_description" in node.names("service_servers")
    assert len(node.service_servers) == 7
    rosout = node.get("publishers", "/rosout")
    assert rosout.qos == {"history": "KEEP_LAST", "depth": 1000, "reliability": "RELIABLE",
                          "durability": "TRANSIENT_LOCAL", "lifespan_ns": 10_000_000_000}
    # switching the filter on an existing capture
    assert talker.capture().with_infrastructure(True).to_contract_nodes() == cap.to_contract_nodes()
    assert cap.with_infrastructure(False)["/talker"].names("publishers") == ["/chatter"]


def test_qos_is_in_contract_form_and_services_have_none():
    b = Builder()
    n = b.node("qos_node", "/robot")
    b.ep(n, "publisher", "/robot/scan", "sensor_msgs/msg/LaserScan", SENSOR_QOS)
    b.ep(n, "publisher", "/map", "nav_msgs/msg/OccupancyGrid", dict(DEFAULT_QOS, depth=1, durability="TRANSIENT_LOCAL",
                                                                   deadline_ns=-1, lifespan_ns=0))
    b.ep(n, "subscription", "/cmd", "std_msgs/msg/String", dict(DEFAULT_QOS, history="KEEP_ALL", depth=0,
                                                               liveliness="MANUAL_BY_TOPIC", deadline_ns=100_000_000))
    b.ep(n, "service", "/robot/reset", "std_srvs/srv/Empty")
    b.ep(n, "client", "/other/trigger", "std_srvs/srv/Trigger")
    nodes = b.capture().to_contract_nodes()
    node = nodes["/robot/qos_node"]
    assert node["publishers"] == [
        {"name": "/map", "type": "nav_msgs/msg/OccupancyGrid", "type_hash": HASH,
         "qos": {"history": "KEEP_LAST", "depth": 1, "reliability": "RELIABLE", "durability": "TRANSIENT_LOCAL"}},
        {"name": "/robot/scan", "type": "sensor_msgs/msg/LaserScan", "type_hash": HASH,
         "qos": {"history": "KEEP_LAST", "depth": 5, "reliability": "BEST_EFFORT", "durability": "VOLATILE"}},
    ]
    assert node["subscriptions"][0]["qos"] == {
        "history": "KEEP_ALL", "reliability": "RELIABLE", "durability": "VOLATILE",
        "liveliness": "MANUAL_BY_TOPIC", "deadline_ns": 100_000_000,
    }
    assert node["service_servers"] == [{"name": "/robot/reset", "type": "std_srvs/srv/Empty", "type_hash": HASH}]
    assert node["service_clients"] == [{"name": "/other/trigger", "type": "std_srvs/srv/Trigger", "type_hash": HASH}]


def test_actions_are_grouped_from_their_services_and_topics():
    b = Builder()
    s = b.node("fib_server")
    b.action(s, "/fibonacci", "test_msgs/action/Fibonacci")
    c = b.node("fib_client", "/ns")
    b.action(c, "/ns/fibonacci", "test_msgs/action/Fibonacci", server=False)
    cap = b.capture()
    server = cap["/fib_server"]
    assert server.service_servers == [] and server.publishers == []
    [action] = server.action_servers
    assert action.name == "/fibonacci"
    assert action.type == "test_msgs/action/Fibonacci"
    assert action.type_hash == {"send_goal": "RIHS01_" + "01" * 32, "get_result": "RIHS01_" + "02" * 32,
                                "feedback": "RIHS01_" + "03" * 32}
    assert len(action.endpoints) == 5
    assert action.to_contract() == {"name": "/fibonacci", "type": "test_msgs/action/Fibonacci",
                                    "type_hash": dict(action.type_hash)}
    client = cap["/ns/fib_client"]
    assert client.service_clients == [] and client.subscriptions == []
    assert [a.name for a in client.action_clients] == ["/ns/fibonacci"]
    assert client.action_servers == []


def test_lone_action_topic_is_not_an_action():
    b = Builder()
    n = b.node("odd")
    b.ep(n, "publisher", "/x/_action/status", "action_msgs/msg/GoalStatusArray", STATUS_QOS)
    node = b.capture()["/odd"]
    assert node.action_servers == []
    assert node.names("publishers") == ["/x/_action/status"]


def test_lifecycle_endpoints_are_infrastructure():
    b = Builder()
    n = b.node("lc", "/ns")
    for srv in ("change_state", "get_state", "get_available_states", "get_available_transitions", "get_transition_graph"):
        b.ep(n, "service", f"/ns/lc/{srv}", "lifecycle_msgs/srv/X")
    b.ep(n, "publisher", "/ns/lc/transition_event", "lifecycle_msgs/msg/TransitionEvent")
    b.ep(n, "publisher", "/ns/lc/status", "std_msgs/msg/String")
    node = b.capture()["/ns/lc"]
    assert node.names("publishers") == ["/ns/lc/status"]
    assert node.service_servers == []
    assert len(b.capture(include_infrastructure=True)["/ns/lc"].service_servers) == 5 + 7


def test_parameter_service_of_another_node_is_not_infrastructure():
    b = Builder()
    n = b.node("caller")
    b.ep(n, "client", "/talker/get_parameters", "rcl_interfaces/srv/GetParameters")
    b.ep(n, "service", "/talker/get_parameters", "rcl_interfaces/srv/GetParameters")
    b.ep(n, "subscription", "/rosout", "rcl_interfaces/msg/Log", ROSOUT_QOS)
    node = b.capture()["/caller"]
    assert node.names("service_clients") == ["/talker/get_parameters"]
    assert node.names("service_servers") == ["/talker/get_parameters"]
    assert node.names("subscriptions") == ["/rosout"]  # reading the log is a real interface


def test_is_infrastructure_for_the_root_namespace():
    ep = Endpoint(seq=1, kind="service", node_id=1, node="/t", name="/t/set_parameters",
                                 type="x", type_hash=None, qos={})
    assert is_infrastructure(ep, "/t")
    assert not is_infrastructure(ep, "/u")


def test_hidden_names_are_kept():
    b = Builder()
    n = b.node("_hidden_node")
    b.ep(n, "publisher", "/_private/data", "std_msgs/msg/String")
    cap = b.capture()
    assert cap["/_hidden_node"].names("publishers") == ["/_private/data"]


def test_destroyed_endpoints_and_nodes_are_left_out_of_the_view_but_kept_raw():
    b = Builder()
    n = b.node("talker")
    b.ep(n, "publisher", "/gone", "std_msgs/msg/String", destroyed=True)
    b.ep(n, "publisher", "/kept", "std_msgs/msg/String")
    d = b.node("temporary", destroyed=True)
    b.ep(d, "publisher", "/temp", "std_msgs/msg/String")
    cap = b.capture()
    assert cap.node_names == ["/talker"]
    assert cap["/talker"].names("publishers") == ["/kept"]
    assert "/gone" not in [e.name for e in cap.endpoints()]
    assert "/gone" in [e.name for e in cap.endpoints(include_destroyed=True)]
    assert [n.fqn for n in cap.raw_nodes] == ["/talker", "/temporary"]


def test_a_node_a_launched_process_destroyed_is_kept_in_the_system_s_nodes():
    from pytest_rmw_introspect.launch.result import LaunchedNode, Where
    from pytest_rmw_introspect.run.system_capture import ProcessCapture, SystemCapture

    def process(label: str, destroyed_ms: float | None) -> ProcessCapture:
        b = Builder()
        n = b.node("worker", infrastructure=False)
        b.ep(n, "publisher", "/work", "std_msgs/msg/String", type_hash=STRING_HASH)
        if destroyed_ms is not None:  # the program destroyed it while it ran (not its final teardown)
            b.doc["nodes"][0].update(destroyed=True, destroyed_virtual_ms=destroyed_ms)
        launched = LaunchedNode(executable=label, package="demo", where=Where(Path("robot.launch.xml"), 3))
        return ProcessCapture(launched=launched, label=label, capture=b.capture())

    def nodes(*processes: ProcessCapture) -> dict:
        return SystemCapture(spec=None, launch=None, processes=list(processes)).to_contract_nodes()

    # used to fail: the node's destroyed_at was merged like a list of entries
    [(fqn, node)] = nodes(process("a", 8100.0)).items()
    assert (fqn, node["destroyed_at"], [p["name"] for p in node["publishers"]]) == ("/worker", 8.1, ["/work"])
    # a name several processes hold: destroyed when the last holder was; alive when one lived on
    assert nodes(process("a", 3000.0), process("b", 8100.0))["/worker"]["destroyed_at"] == 8.1
    assert "destroyed_at" not in nodes(process("a", 3000.0), process("b", None))["/worker"]
    assert "destroyed_at" not in nodes(process("a", None), process("b", 3000.0))["/worker"]


def test_same_topic_twice_gives_one_entry_with_both_endpoints():
    b = Builder()
    n = b.node("twice")
    b.ep(n, "publisher", "/a", "std_msgs/msg/String")
    b.ep(n, "publisher", "/a", "std_msgs/msg/String")
    b.ep(n, "subscription", "/a", "std_msgs/msg/String")
    node = b.capture()["/twice"]
    assert len(node.publishers) == 1 and len(node.publishers[0].endpoints) == 2
    assert len(node.subscriptions) == 1


def test_two_nodes_with_one_name_are_one_contract_node():
    b = Builder()
    a = b.node("dup")
    b.ep(a, "publisher", "/x", "std_msgs/msg/String")
    c = b.node("dup")
    b.ep(c, "subscription", "/y", "std_msgs/msg/String")
    cap = b.capture()
    assert cap.node_names == ["/dup"]
    assert cap["/dup"].names("publishers") == ["/x"]
    assert cap["/dup"].names("subscriptions") == ["/y"]
    assert len(cap["/dup"].raw) == 2


def test_entries_and_nodes_are_sorted():
    b = Builder()
    z = b.node("z")
    b.ep(z, "publisher", "/b", "std_msgs/msg/String")
    b.ep(z, "publisher", "/a", "std_msgs/msg/String")
    b.node("a", "/ns")
    nodes = b.capture().to_contract_nodes()
    assert list(nodes) == ["/ns/a", "/z"]
    assert [e["name"] for e in nodes["/z"]["publishers"]] == ["/a", "/b"]


def test_without_type_hash_and_qos():
    b = Builder()
    n = b.node("t")
    b.ep(n, "publisher", "/a", "std_msgs/msg/String")
    b.ep(n, "publisher", "/nohash", "std_msgs/msg/String", type_hash=None)
    nodes = b.capture().to_contract_nodes(with_type_hash=False, with_qos=False)
    assert nodes["/t"]["publishers"] == [{"name": "/a", "type": "std_msgs/msg/String"},
                                         {"name": "/nohash", "type": "std_msgs/msg/String"}]
    assert "type_hash" not in b.capture().to_contract_nodes()["/t"]["publishers"][1]


def test_summary_lists_nodes_and_interfaces(talker):
    text = talker.capture().summary()
    assert "/talker" in text and "publishers: /chatter [std_msgs/msg/String]" in text


def test_missing_node_lookup_names_the_nodes(talker):
    with pytest.raises(KeyError, match=r"/listener.*\['/talker'\]"):
        talker.capture()["/listener"]


# ---------------------------------------------------------------------------- format errors


def test_load_from_file(tmp_path, talker):
    path = tmp_path / "c.json"
    path.write_text(json.dumps(talker.doc))
    cap = Capture.load(path)
    assert cap.path == path and cap.node_names == ["/talker"]


@pytest.mark.parametrize(
    "mutate, message",
    [
        (lambda d: d.update(format="something_else"), "`format` is 'something_else'"),
        (lambda d: d.update(format_version=2), "`format_version` 2 is not supported"),
        (lambda d: d.pop("format_version"), "`format_version` None is not supported"),
        (lambda d: d.update(nodes={}), "`nodes` is not a list"),
        (lambda d: d["endpoints"][0].pop("name"), r"endpoints\[0\]: missing or malformed field 'name'"),
        (lambda d: d["endpoints"][0].update(kind="topic"), r"endpoints\[0\]: unknown kind 'topic'"),
        (lambda d: d["nodes"][0].pop("id"), r"nodes\[0\]: missing or malformed field 'id'"),
    ],
)
def test_malformed_capture_documents(talker, mutate, message):
    doc = copy.deepcopy(talker.doc)
    mutate(doc)
    with pytest.raises(CaptureFormatError, match=message):
        Capture.from_dict(doc, path="/tmp/x.json")


def test_unreadable_capture_files(tmp_path):
    with pytest.raises(CaptureFormatError, match="does not exist"):
        Capture.load(tmp_path / "missing.json")
    empty = tmp_path / "empty.json"
    empty.write_text("")
    with pytest.raises(CaptureFormatError, match="empty"):
        Capture.load(empty)
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": ')
    with pytest.raises(CaptureFormatError, match=r"bad\.json: not valid JSON"):
        Capture.load(bad)
    with pytest.raises(CaptureFormatError, match="not a JSON object"):
        Capture.from_dict([1, 2])


def test_yaml_capture_is_read_too(tmp_path, talker):
    import yaml

    path = tmp_path / "c.yaml"
    path.write_text(yaml.safe_dump(talker.doc, sort_keys=False))
    assert Capture.load(path).node_names == ["/talker"]


def test_package_capture_is_the_library_function_even_after_importing_the_model():
    import importlib

    from pytest_rmw_introspect.run import api

    importlib.import_module("pytest_rmw_introspect.model.capture")
    assert pytest_rmw_introspect.capture is api.capture
    assert pytest_rmw_introspect.Capture is Capture


# ---------------------------------------------------------------------------- virtual time, endings


def test_entities_destroyed_in_the_final_teardown_are_in_the_view(talker):
    """A program that ended by itself: what was alive just before its own teardown."""
    for entity in talker.doc["nodes"] + talker.doc["endpoints"]:
        entity.update(destroyed=True, in_teardown=True)
    talker.doc.update(state="exit", time_to_settle_ms=None, ended={"before_settle": True})
    cap = talker.capture()
    assert cap.node_names == ["/talker"]
    assert [p.name for p in cap["/talker"].publishers] == ["/chatter"]
    assert all(e.destroyed and e.in_teardown for e in cap.raw_endpoints)  # the raw truth
    assert cap.ended_before_settle is True and not cap.settled_once
    assert not cap.ended_by_itself  # the runner knows the exit status; the file alone does not
    assert cap.with_facts(RunFacts(returncode=0)).ended_by_itself


def test_an_endpoint_destroyed_before_the_final_teardown_stays_out(talker):
    talker.ep(1, "publisher", "/old", "std_msgs/msg/String", destroyed=True)
    talker.doc["endpoints"][-1]["in_teardown"] = False
    cap = talker.capture()
    assert [p.name for p in cap["/talker"].publishers] == ["/chatter"]


def test_virtual_time_and_creation_ages_are_read(talker):
    talker.doc["time"] = {"horizon_ms": 10000, "virtual_elapsed_ms": 10000.5, "real_elapsed_ms": 140.2, "jumps": 21,
                          "warp_ms": 9850.0, "horizon_reached": True, "warp_budget_exhausted": False}
    talker.doc.update(settled_by="wait", ever_waited=True, activity_calls=22)
    talker.doc["endpoints"][-1].update(created_virtual_ms=3000.4, created_real_ms=95.1)
    cap = talker.capture()
    vt = cap.virtual_time
    assert vt is not None and vt.enabled and vt.jumps == 21 and vt.horizon_reached
    assert cap.settled_by == "wait" and cap.ever_waited and cap.activity_calls == 22
    assert cap["/talker"].publishers[0].endpoints[0].created_virtual_ms == 3000.4
    assert "virtual time: 10 s of a 10 s horizon in 0.14 s real (21 jumps)" in cap.summary()
    assert cap.notes() == []


def test_a_warp_that_ran_out_of_budget_is_noted(talker):
    talker.doc["time"] = {"horizon_ms": 10000, "virtual_elapsed_ms": 2500.0, "real_elapsed_ms": 3100.0, "jumps": 2500,
                          "warp_ms": 2400.0, "horizon_reached": False, "warp_budget_exhausted": True}
    (note,) = talker.capture().notes()
    assert "virtual time stopped at 2.5 s of the 10 s horizon" in note and "2500 jumps" in note


def test_a_warp_the_idle_proof_ended_while_a_thread_waited_on_the_real_clock_is_noted(talker):
    """Issue 50 item 1: diagnostic_updater's example loops on rclcpp::Rate::sleep(); the warp ends
    when the process is proven idle, far short of the horizon, and says why."""
    talker.doc["time"] = {"horizon_ms": 10000, "virtual_elapsed_ms": 1400.0, "real_elapsed_ms": 1400.0, "jumps": 0,
                          "warp_ms": 0.0, "horizon_reached": False, "warp_budget_exhausted": False,
                          "warp_stalled": False, "warp_real_waits": True}
    (note,) = talker.capture().notes()
    assert note.startswith("virtual time stopped at 1.4 s of the 10 s horizon after 0 jumps: the idle proof ended it")
    assert "waited on the real clock" in note and "Rate" in note
    talker.doc["time"]["warp_real_waits"] = False  # nothing was due: a listener, no note
    assert talker.capture().notes() == []


STALLED = {"horizon_ms": 10000, "virtual_elapsed_ms": 400.0, "real_elapsed_ms": 400.0, "jumps": 0, "warp_ms": 0.0,
           "horizon_reached": False, "warp_budget_exhausted": False, "warp_stalled": True}


@pytest.mark.parametrize("counted,says,never", [
    # spin_some until an answer that never comes: thousands of returns a second
    ({"warp_real_ms": 100.0, "warp_polls": 2300, "warp_activity": 0},
     ["2300 zero-timeout polls of its executor in 0.1 s", "without pausing", "busy loop at full CPU"],
     ["sleeps on the real clock", "very fast timer"]),
    # publish; sleep_for(10ms); spin_some
    ({"warp_real_ms": 110.0, "warp_polls": 10, "warp_activity": 10},
     ["10 zero-timeout polls of its executor in 0.11 s", "one every 11 ms", "sleeps on the real clock", "WallRate"],
     ["busy loop", "very fast timer"]),
    # a 2 Hz WallRate loop
    ({"warp_real_ms": 525.0, "warp_polls": 1, "warp_activity": 1},
     ["1 zero-timeout poll of its executor in 0.53 s", "one every 525 ms", "sleeps on the real clock"], ["busy loop"]),
    # publish; time.sleep(0.1) without ever spinning
    ({"warp_real_ms": 200.0, "warp_polls": 0, "warp_activity": 3},
     ["made 3 calls into ROS", "never waited in an executor", "without spinning"], ["busy loop", "polls of"]),
])
def test_a_stalled_warp_is_noted_with_the_loop_that_was_seen(talker, counted, says, never):
    talker.doc["time"] = {**STALLED, **counted}
    (note,) = talker.capture().notes()
    assert note.startswith("virtual time stopped at 0.4 s of the 10 s horizon after 0 jumps: the program kept "
                           "running but never waited with a timeout: ")
    assert note.endswith("interfaces created later are not in the capture")
    for text in says:
        assert text in note
    for text in never:
        assert text not in note


def test_a_stalled_warp_of_an_older_capture_lists_what_it_may_have_been(talker):
    talker.doc["time"] = STALLED
    talker.doc["quiescence"] = {"detect": True, "detected": 0, "window": 2, "polls": 30, "not_idle": None}
    (note,) = talker.capture().notes()
    assert "30 zero-timeout polls of its executor" in note and "sleeps on its own clock" in note
    assert talker.capture().virtual_time.warp_polls is None


def test_a_node_on_sim_time_is_noted(talker):
    talker.ep(1, "subscription", "/clock", "rosgraph_msgs/msg/Clock")
    cap = talker.capture()
    assert cap["/talker"].uses_sim_time
    (note,) = cap.notes()
    assert "node /talker uses sim time" in note


@pytest.mark.parametrize("time_field", [[], "soon", {"jumps": "many"}])
def test_malformed_time_field(talker, time_field):
    talker.doc["time"] = time_field
    with pytest.raises(CaptureFormatError, match="`time`"):
        talker.capture()


def test_two_live_nodes_with_one_name_are_reported():
    b = Builder()
    a = b.node("dup")
    b.ep(a, "publisher", "/x", "std_msgs/msg/String")
    b.node("dup")
    b.node("other")
    gone = b.node("other", destroyed=True)  # a destroyed namesake is no collision
    assert gone
    cap = b.capture()
    assert cap.duplicate_node_names == ["/dup"]
    (note,) = [n for n in cap.notes() if "/dup" in n]
    assert note.startswith("2 nodes are named /dup in one process") and "parameter services collide" in note


def test_logger_services_are_infrastructure():
    b = Builder()
    n = b.node("talker")
    b.ep(n, "service", "/talker/get_logger_levels", "rcl_interfaces/srv/GetLoggerLevels")
    b.ep(n, "service", "/talker/set_logger_levels", "rcl_interfaces/srv/SetLoggerLevels")
    b.ep(n, "service", "/talker/reset", "std_srvs/srv/Empty")
    assert b.capture()["/talker"].names("service_servers") == ["/talker/reset"]
    assert len(b.capture(include_infrastructure=True)["/talker"].service_servers) == 3 + len(PARAM_SERVICES)


def test_a_client_of_a_service_of_the_same_process_is_noted():
    b = Builder()
    own = b.node("caller")
    b.ep(own, "service", "/ping", "std_srvs/srv/Trigger")
    b.ep(own, "client", "/ping", "std_srvs/srv/Trigger")
    other = b.node("asker")
    b.ep(other, "client", "/ping", "std_srvs/srv/Trigger")
    b.ep(other, "client", "/elsewhere", "std_srvs/srv/Trigger")  # served by another process: no note
    notes = b.capture().notes()
    assert len(notes) == 2
    assert notes[0].startswith("node /caller has a client of /ping, a service of its own node in this process")
    assert notes[1].startswith("node /asker has a client of /ping, a service of node /caller in this process")
    assert "never answered in a capture" in notes[1]


def test_the_runners_facts_are_one_frozen_value_given_once(talker, tmp_path):
    cap = Capture.from_dict(copy.deepcopy(talker.doc), path=tmp_path / "capture.1.json")
    assert cap.facts == RunFacts() and cap.returncode is None and cap.started is None  # read from a file
    child = OtherProcess(pid=7, argv=["python3", "child.py"], node_names=["/child"])
    facts = RunFacts(returncode=-2, stderr="tail", wall_time=1.5, command=("python3", "talker.py"),
                     other_processes=(child,), from_child=None, ros_distribution="jazzy", started="warm",
                     start_note=None)
    given = cap.with_facts(facts, argv=["python3", "talker.py"], keep_path=False)
    assert (given.returncode, given.stderr, given.wall_time, given.command, given.other_processes) == (
        -2, "tail", 1.5, ["python3", "talker.py"], [child])
    assert (given.ros_distribution, given.started, given.start_note, given.from_child) == ("jazzy", "warm", None, None)
    assert given.argv == ["python3", "talker.py"] and given.path is None
    assert cap.facts == RunFacts() and cap.path == tmp_path / "capture.1.json"  # the capture read is unchanged
    assert given.nodes is cap.nodes  # the contract view is shared, not built again
    with pytest.raises(AttributeError):
        given.returncode = 0  # type: ignore[misc]
    with pytest.raises(dataclasses.FrozenInstanceError):
        facts.returncode = 0  # type: ignore[misc]
    again = given.with_infrastructure(True)
    assert again.facts is facts and again.argv == given.argv and "/rosout" in again["/talker"].names("publishers")
