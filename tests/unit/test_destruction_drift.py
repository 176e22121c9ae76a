"""What the program destroys while it runs (``destroyed_at``): the capture view keeps it, contracts
write and read it, drift.compare judges a change of it (compare/destruction_drift.py), reports and
the graph show it."""

from __future__ import annotations

import pytest

from pytest_rmw_introspect.compare import graph, report
from pytest_rmw_introspect.compare.compatibility import LaunchedProcess
from pytest_rmw_introspect.compare.drift import compare
from pytest_rmw_introspect.model import contract
from pytest_rmw_introspect.model.capture import Capture
from pytest_rmw_introspect.model.vocabulary import Severity

BREAKING, RISKY, SAFE = Severity.BREAKING, Severity.RISKY, Severity.SAFE
QOS = {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE",
       "liveliness": "SYSTEM_DEFAULT", "deadline_ns": 0, "lifespan_ns": 0, "liveliness_lease_duration_ns": 0,
       "avoid_ros_namespace_conventions": False}


def raw_node(node_id, name, destroyed_ms=None, *, in_teardown=False):
    return {"id": node_id, "seq": node_id, "name": name, "namespace": "/", "fqn": f"/{name}",
            "destroyed": destroyed_ms is not None or in_teardown, "in_teardown": in_teardown,
            "created_virtual_ms": 1.0, "created_real_ms": 1.0,
            "destroyed_virtual_ms": destroyed_ms, "destroyed_real_ms": None if destroyed_ms is None else 20.0}


def raw_endpoint(seq, node_id, node, name, kind="publisher", destroyed_ms=None, *, minor_4=True):
    out = {"seq": seq, "kind": kind, "node_id": node_id, "node": node, "name": name, "type": "std_msgs/msg/String",
           "type_hash": None, "qos": QOS, "destroyed": destroyed_ms is not None, "in_teardown": False}
    if minor_4:
        out["destroyed_virtual_ms"] = destroyed_ms
    return out


def capture(nodes, endpoints, minor=4):
    return Capture.from_dict({"format": "rmw_introspect_capture", "format_version": 1, "format_minor": minor,
                              "state": "settled", "nodes": nodes, "endpoints": endpoints})


# --------------------------------------------------------------------------- the capture view


def test_what_the_program_destroyed_is_kept_with_its_virtual_age():
    cap = capture(
        [raw_node(1, "keeper"), raw_node(2, "doomed", 8012.0)],
        [raw_endpoint(10, 1, "/keeper", "/kept"),
         raw_endpoint(11, 1, "/keeper", "/dropped", destroyed_ms=3049.9),
         raw_endpoint(12, 2, "/doomed", "/doomed_topic", destroyed_ms=8012.0),
         raw_endpoint(13, 2, "/doomed", "/doomed_early", kind="subscription", destroyed_ms=5000.0)])
    assert cap.node_names == ["/doomed", "/keeper"]
    assert cap["/keeper"].destroyed_at is None
    assert cap["/keeper"].get("publishers", "/dropped").destroyed_at == 3.0
    assert cap["/doomed"].destroyed_at == 8.0
    nodes = cap.to_contract_nodes(with_type_hash=False, with_qos=False)
    assert nodes["/keeper"]["publishers"] == [
        {"name": "/dropped", "type": "std_msgs/msg/String", "destroyed_at": 3.0},
        {"name": "/kept", "type": "std_msgs/msg/String"}]
    assert nodes["/doomed"]["destroyed_at"] == 8.0
    # an interface that went with its node does not repeat the age; one that went before does
    assert nodes["/doomed"]["publishers"] == [{"name": "/doomed_topic", "type": "std_msgs/msg/String"}]
    assert nodes["/doomed"]["subscriptions"] == [
        {"name": "/doomed_early", "type": "std_msgs/msg/String", "destroyed_at": 5.0}]
    summary = cap.summary()
    assert "/doomed (destroyed by the program at 8 s)" in summary
    assert "publishers: /dropped [std_msgs/msg/String] (destroyed by the program at 3 s)" in summary


def test_teardown_and_older_captures_keep_the_rule_before():
    # destroyed in the final teardown run: alive until its own end, no destroyed_at
    cap = capture([raw_node(1, "n", in_teardown=True)], [])
    assert cap["/n"].destroyed_at is None
    # a capture of format_minor 3 does not say when: its destroyed entities are left out
    old = capture([raw_node(1, "n")], [raw_endpoint(10, 1, "/n", "/gone", destroyed_ms=None, minor_4=False)
                                       | {"destroyed": True}], minor=3)
    assert old["/n"].publishers == []


def test_an_interface_recreated_under_the_same_name_is_alive():
    cap = capture([raw_node(1, "n")], [raw_endpoint(10, 1, "/n", "/p", destroyed_ms=2000.0),
                                       raw_endpoint(11, 1, "/n", "/p")])
    assert cap["/n"].get("publishers", "/p").destroyed_at is None


# --------------------------------------------------------------------------- contracts


def test_contracts_write_and_read_destroyed_at():
    nodes = {"/doomed": {"destroyed_at": 8.0, "publishers": [
        {"name": "/early", "type": "std_msgs/msg/String", "destroyed_at": 2.5}]}}
    text = contract.render(nodes)
    assert "    destroyed_at: 8.0\n" in text
    assert "        destroyed_at: 2.5\n" in text
    loaded = contract.loads(text)
    assert loaded.nodes["/doomed"]["destroyed_at"] == 8.0
    assert contract.loads(loaded.dump()).dump() == loaded.dump()


@pytest.mark.parametrize("bad", ["-1", "soon", "true"])
def test_a_destroyed_at_that_is_not_an_age_is_refused_with_its_place(bad):
    text = f"contract_version: 1\nnodes:\n  /n:\n    destroyed_at: {bad}\n"
    with pytest.raises(contract.ContractError) as info:
        contract.loads(text, path="n.interfaces.yaml")
    assert "nodes./n.destroyed_at" in str(info.value)


# --------------------------------------------------------------------------- drift rules


def pub(age=None, kind="publishers"):
    entry = {"name": "/p", "type": "std_msgs/msg/String"}
    if age is not None:
        entry["destroyed_at"] = age
    return {"/n": {kind: [entry]}}


ROWS = [
    # kind, contract age, captured age, rule, severity
    ("publishers", None, 8.0, "NEWLY_DESTROYED", BREAKING),
    ("service_servers", None, 8.0, "NEWLY_DESTROYED", BREAKING),
    ("subscriptions", None, 8.0, "REQUEST_NEWLY_DESTROYED", RISKY),
    ("service_clients", None, 8.0, "REQUEST_NEWLY_DESTROYED", RISKY),
    ("publishers", 8.0, 4.0, "DESTROYED_EARLIER", BREAKING),
    ("action_clients", 8.0, 4.0, "REQUEST_DESTROYED_EARLIER", RISKY),
    ("publishers", 8.0, None, "NO_LONGER_DESTROYED", SAFE),
    ("subscriptions", 4.0, 8.0, "DESTROYED_LATER", SAFE),
]
TESTED_RULES = {row[3] for row in ROWS}


@pytest.mark.parametrize(("kind", "old", "new", "rule", "severity"), ROWS)
def test_destruction_rules(kind, old, new, rule, severity):
    items = compare(pub(old, kind), pub(new, kind))
    assert [(i.rule, i.severity, i.change, i.old, i.new) for i in items] == [(rule, severity, "destroyed_at", old, new)]
    assert "/p" in items[0].message


def test_ages_within_the_tolerance_are_the_same_destruction():
    assert compare(pub(8.0), pub(8.4)) == []
    assert compare(pub(8.0), pub(8.6)) != []


def test_a_node_destroyed_is_one_item_its_interfaces_go_with_it():
    old = {"/n": {"publishers": [{"name": "/p", "type": "std_msgs/msg/String"}]}}
    new = {"/n": {"destroyed_at": 8.0, "publishers": [{"name": "/p", "type": "std_msgs/msg/String"}]}}
    items = compare(old, new)
    assert [(i.kind, i.rule, i.severity) for i in items] == [("node", "NEWLY_DESTROYED", BREAKING)]
    assert "node /n is now destroyed by the program at 8 s" in items[0].message
    # an interface that now goes earlier than its node is an item of its own
    new["/n"]["publishers"][0]["destroyed_at"] = 2.0
    assert sorted((i.kind, i.rule) for i in compare(old, new)) == [
        ("node", "NEWLY_DESTROYED"), ("publishers", "NEWLY_DESTROYED")]


def test_reports_show_the_age_of_what_was_destroyed():
    items = compare({"/n": {}}, pub(8.0))
    text = report.render_text(items)
    assert "[PUB_ADDED]" in text and "destroyed by the program at 8 s" in text


def test_the_graph_draws_what_was_destroyed_dashed_with_its_age():
    processes = [LaunchedProcess("talker", None, {"/n": {"destroyed_at": 8.0, **pub(3.0)["/n"]}})]
    drawn = graph.build(processes, [])
    mermaid, dot = graph.to_mermaid(drawn), graph.to_dot(drawn)
    assert '-. "destroyed at 3 s" .->' in mermaid
    assert "destroyed at 8 s" in mermaid
    assert "style=dashed" in dot and 'label="destroyed at 3 s"' in dot
    assert 'stroke-dasharray="5 4"' in graph.to_svg(drawn)


def test_a_golden_update_keeps_the_contract_s_age_of_the_same_destruction():
    old = {"/n": {"destroyed_at": 8.1, "publishers": [{"name": "/p", "type": "T/msg/T", "destroyed_at": 3.0}]}}
    new = {"/n": {"destroyed_at": 8.3, "publishers": [{"name": "/p", "type": "T/msg/T", "destroyed_at": 4.0}]}}
    kept = contract.preserve_spelling(old, new)
    assert kept["/n"]["destroyed_at"] == 8.1  # same destruction: the golden does not churn
    assert kept["/n"]["publishers"][0]["destroyed_at"] == 4.0  # a second later: the new age
