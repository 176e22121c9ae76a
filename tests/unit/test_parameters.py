"""Parameters and lifecycle in the model: reading them from captures (issue 10, format_minor 1),
the contract view (infrastructure filter), and the contract's ``parameters:`` / ``lifecycle:``
(schema, semantic checks, deterministic writing, spelling kept on update)."""

from __future__ import annotations

import copy
import math

import pytest
import yaml
from test_capture import Builder

from pytest_rmw_introspect.errors import CaptureFormatError, ContractError
from pytest_rmw_introspect.model import contract as contract_module
from pytest_rmw_introspect.model import parameters as parameter_model
from pytest_rmw_introspect.model.capture import Capture
from pytest_rmw_introspect.model.locate import line_index
from pytest_rmw_introspect.model.vocabulary import is_infrastructure_parameter


def param(name, type_, value, **descriptor):
    record = {"name": name, "type": type_, "value": value, "read_only": False, "dynamic_typing": False,
              "description": "", "additional_constraints": "", "integer_range": None,
              "floating_point_range": None, "declared_in": None}
    record.update(descriptor)
    return record


RCLPY = [param("use_sim_time", "bool", False),
         param("start_type_description_service", "bool", True, read_only=True,
               description="If enabled, start the ~/get_type_description service.")]

EVERY_TYPE = [
    param("flag", "bool", True),
    param("count", "integer", 64, description="how many", integer_range={"from_value": 0, "to_value": 100, "step": 2}),
    param("gain", "double", 0.5, additional_constraints="tuned on the robot",
          floating_point_range={"from_value": 0.0, "to_value": 1.0, "step": 0.0}),
    param("frame", "string", "odom", read_only=True, description="TF frame"),
    param("blob", "byte_array", [0, 1, 255]),
    param("flags", "bool_array", [True, False, True]),
    param("ids", "integer_array", [1, -2, 3]),
    param("weights", "double_array", [0.25, 1.0, -1e300, "nan", "inf"]),
    param("names", "string_array", ["a", "b c", "ü"]),
    param("limits.max_speed", "double", 3.5),
    param("odd", "double", "-inf"),
    param("anything", "string", "hello", dynamic_typing=True),
    param("typed_only", "string", None),
    param("qos_overrides./chatter.publisher.depth", "integer", 10, read_only=True),
    param("qos_overrides./parameter_events.publisher.depth", "integer", 1000, read_only=True),
]

LIFECYCLE = {"target": "active", "initial_state": "unconfigured", "state": "active",
             "transitions": [{"id": 1, "label": "configure", "result": "success", "success": True},
                             {"id": 3, "label": "activate", "result": "success", "success": True}],
             "error": None}


def probed(builder: Builder, node_id: int, parameters=None, lifecycle=None, error=None) -> Builder:
    doc = builder.doc
    doc["format_minor"] = 1
    doc["probe"] = {"state": "done", "parameters": True, "lifecycle": "active", "answer_timeout_ms": 5000,
                    "requests": 14, "unanswered": 0}
    node = doc["nodes"][node_id - 1]
    node["parameters"] = parameters
    node["parameters_error"] = error
    node["lifecycle"] = lifecycle
    for e in doc["endpoints"]:
        e.setdefault("created_in", None)
    return builder


@pytest.fixture
def params_node() -> Builder:
    b = Builder()
    n = b.node("params_node")
    b.ep(n, "publisher", "/chatter", "std_msgs/msg/String")
    return probed(b, n, RCLPY + EVERY_TYPE)


@pytest.fixture
def managed() -> Builder:
    b = Builder()
    n = b.node("managed")
    b.ep(n, "publisher", "/status", "std_msgs/msg/String")
    b.doc["endpoints"][-1]["created_in"] = "configure"
    probed(b, n, RCLPY + [param("rate", "double", 10.0, description="Hz"),
                          param("depth", "integer", 5, declared_in="configure",
                                integer_range={"from_value": 1, "to_value": 10, "step": 1})],
           lifecycle=copy.deepcopy(LIFECYCLE))
    return b


# ---------------------------------------------------------------------------- reading captures


def test_every_parameter_type_is_read(params_node):
    cap = params_node.capture()
    assert cap.format_minor == 1
    assert cap.probe is not None and cap.probe.state == "done" and cap.probe.requests == 14
    node = cap["/params_node"]
    assert node.lifecycle is None and node.lifecycle_state is None and node.parameters_error is None
    by_name = {p.name: p for p in node.parameters}
    assert by_name["count"].integer_range == parameter_model.ParameterRange(0, 100, 2)
    assert by_name["gain"].floating_point_range.to_value == 1.0
    assert isinstance(by_name["gain"].floating_point_range.to_value, float)
    assert by_name["frame"].read_only and by_name["frame"].description == "TF frame"
    assert by_name["blob"].value == [0, 1, 255]
    weights = by_name["weights"].value
    assert weights[:3] == [0.25, 1.0, -1e300] and math.isnan(weights[3]) and weights[4] == math.inf
    assert by_name["odd"].value == -math.inf
    assert by_name["anything"].dynamic_typing
    assert by_name["typed_only"].value is None and by_name["typed_only"].type == "string"
    assert node.parameter("flag").value is True and node.parameter("nope") is None


def test_infrastructure_parameters_are_left_out_unless_asked_for(params_node):
    names = [p.name for p in params_node.capture()["/params_node"].parameters]
    assert names == sorted(names)
    assert "use_sim_time" not in names and "start_type_description_service" not in names
    assert "qos_overrides./parameter_events.publisher.depth" not in names
    assert "qos_overrides./chatter.publisher.depth" in names  # the node's own topic: its interface
    everything = [p.name for p in params_node.capture(include_infrastructure=True)["/params_node"].parameters]
    assert {"use_sim_time", "start_type_description_service",
            "qos_overrides./parameter_events.publisher.depth"} <= set(everything)
    assert len(everything) == len(RCLPY) + len(EVERY_TYPE)


@pytest.mark.parametrize(("name", "infrastructure"), [
    ("use_sim_time", True), ("start_type_description_service", True),
    ("qos_overrides./rosout.publisher.durability", True), ("qos_overrides./clock.subscription.depth", True),
    ("qos_overrides./parameter_events.publisher.history", True),
    ("qos_overrides./scan.publisher.depth", False), ("use_sim_time_too", False), ("rate", False),
])
def test_infrastructure_parameter_names(name, infrastructure):
    assert is_infrastructure_parameter(name) is infrastructure


def test_contract_view_of_parameters(params_node):
    node = params_node.capture().to_contract_nodes()["/params_node"]
    assert "lifecycle" not in node
    entries = {e["name"]: e for e in node["parameters"]}
    assert entries["count"] == {"name": "count", "type": "integer", "default_value": 64, "description": "how many",
                                "integer_range": {"from_value": 0, "to_value": 100, "step": 2}}
    assert entries["flag"] == {"name": "flag", "type": "bool", "default_value": True}  # defaults left out
    assert entries["typed_only"] == {"name": "typed_only", "type": "string", "default_value": None}
    assert entries["anything"]["dynamic_typing"] is True
    assert entries["frame"]["read_only"] is True
    assert "parameters" not in params_node.capture().to_contract_nodes(with_parameters=False)["/params_node"]


def test_lifecycle_node_contract_view_and_created_in(managed):
    cap = managed.capture()
    node = cap["/managed"]
    assert node.lifecycle.state == "active" and node.lifecycle.failed_transition is None
    assert [t.label for t in node.lifecycle.transitions] == ["configure", "activate"]
    assert node.publishers[0].created_in == "configure"
    view = cap.to_contract_nodes()["/managed"]
    assert list(view)[0] == "lifecycle" and view["lifecycle"] == "active"
    assert [e.get("declared_in") for e in view["parameters"]] == ["configure", None]
    assert "/managed (lifecycle node, active)" in cap.summary()
    assert "publishers: /status [std_msgs/msg/String] (created in configure)" in cap.summary()
    assert "parameter: rate [double] = 10.0" in cap.summary()


def test_a_lifecycle_node_left_alone_is_in_an_unknown_state(managed):
    managed.doc["nodes"][0]["lifecycle"] = {"target": "none", "initial_state": None, "state": None,
                                            "transitions": [], "error": None}
    assert managed.capture().to_contract_nodes()["/managed"]["lifecycle"] == "unknown"


def test_a_failed_transition_is_recorded_and_noted(managed):
    managed.doc["nodes"][0]["lifecycle"] = dict(
        LIFECYCLE, state="unconfigured",
        transitions=[{"id": 1, "label": "configure", "result": "failure", "success": False}],
        error="transition configure of /managed failed: change_state answered success=false")
    cap = managed.capture()
    failed = cap["/managed"].lifecycle.failed_transition
    assert failed is not None and failed.label == "configure" and failed.success is False
    assert any("transition configure of /managed failed" in note for note in cap.notes())


def test_parameters_not_read_are_none_and_noted():
    b = Builder()
    n = b.node("idle")
    probed(b, n, None, error="no executor serves /idle/list_parameters (it was never in a wait set)")
    cap = b.capture()
    assert cap["/idle"].parameters is None
    assert "parameters" not in cap.to_contract_nodes()["/idle"]
    assert any("parameters of node /idle could not be read (no executor serves" in note for note in cap.notes())
    b.doc["probe"]["state"] = "skipped"
    assert any("parameters were not read and lifecycle nodes were not driven" in n for n in b.capture().notes())


def test_captures_of_older_middleware_versions_have_no_parameters():
    b = Builder()
    b.node("talker")
    cap = b.capture()
    assert cap.format_minor == 0 and cap.probe is None
    assert cap["/talker"].parameters is None and cap["/talker"].lifecycle is None
    assert set(cap.to_contract_nodes()["/talker"]) == {"publishers", "subscriptions", "service_servers",
                                                       "service_clients", "action_servers", "action_clients"}


def _set(doc, path, value):
    target = doc
    for part in path[:-1]:
        target = target[part]
    target[path[-1]] = value


@pytest.mark.parametrize(("path", "value", "reason"), [
    (("nodes", 0, "parameters"), {"a": 1}, "nodes[0].parameters is not a list"),
    (("nodes", 0, "parameters", 2), "x", "nodes[0].parameters[2] is not an object"),
    (("nodes", 0, "parameters", 2, "name"), 5, "nodes[0].parameters[2].name is not a string"),
    (("nodes", 0, "parameters", 2, "name"), "", "nodes[0].parameters[2].name is empty"),
    (("nodes", 0, "parameters", 2, "type"), "int", "nodes[0].parameters[2].type 'int' is not one of bool"),
    (("nodes", 0, "parameters", 2, "value"), "yes", "nodes[0].parameters[2].value: 'yes' is not a bool"),
    (("nodes", 0, "parameters", 3, "value"), 1.5, "nodes[0].parameters[3].value: 1.5 is not an integer"),
    (("nodes", 0, "parameters", 3, "value"), True, "nodes[0].parameters[3].value: True is not an integer"),
    (("nodes", 0, "parameters", 4, "value"), "NaN", "nodes[0].parameters[4].value: 'NaN' is not a double"),
    (("nodes", 0, "parameters", 6, "value"), [0, 256], "a byte_array holds integers from 0 to 255"),
    (("nodes", 0, "parameters", 9, "value"), [0.5, "x"], "nodes[0].parameters[9].value[1]: 'x' is not a double"),
    (("nodes", 0, "parameters", 9, "value"), 0.5, "double_array value 0.5 is not a list"),
    (("nodes", 0, "parameters", 2, "read_only"), "no", "nodes[0].parameters[2].read_only is not true or false"),
    (("nodes", 0, "parameters", 3, "integer_range"), {"from_value": 0, "to_value": 1}, "integer_range.step is missing"),
    (("nodes", 0, "parameters", 3, "integer_range"), {"from_value": 0.5, "to_value": 1, "step": 1},
     "integer_range.from_value is not an integer"),
    (("nodes", 0, "parameters", 3, "integer_range"), {"from_value": 0, "to_value": 1, "step": -1},
     "integer_range.step must not be negative"),
    (("nodes", 0, "parameters", 4, "floating_point_range"), [1], "floating_point_range is not an object"),
    (("nodes", 0, "parameters", 2, "declared_in"), 3, "nodes[0].parameters[2].declared_in is not a string"),
    (("nodes", 0, "parameters_error"), 3, "nodes[0].parameters_error is not a string"),
    (("nodes", 0, "lifecycle"), "active", "nodes[0].lifecycle is not an object"),
    (("nodes", 0, "lifecycle"), {"target": "on"}, "nodes[0].lifecycle.target 'on' is not one of active"),
    (("nodes", 0, "lifecycle"), {"target": "active", "transitions": [{"id": "1"}]},
     "nodes[0].lifecycle.transitions[0].id is not an integer"),
    (("nodes", 0, "lifecycle"), {"target": "active", "state": 3}, "nodes[0].lifecycle.state is not a string"),
    (("endpoints", 0, "created_in"), 1, "endpoints[0].created_in is not a string"),
    (("probe",), [], "`probe` is not an object"),
    (("probe", "requests"), -1, "`probe.requests` is not a count"),
    (("probe", "parameters"), "yes", "`probe.parameters` is not true or false"),
    (("format_minor",), "1", "`format_minor` is not a non-negative integer"),
])
def test_malformed_parameter_records_are_capture_format_errors(params_node, path, value, reason):
    doc = copy.deepcopy(params_node.doc)
    _set(doc, path, value)
    with pytest.raises(CaptureFormatError) as info:
        Capture.from_dict(doc, path="c.json")
    assert reason in str(info.value), str(info.value)
    assert "c.json" in str(info.value)


# ---------------------------------------------------------------------------- contracts

CONTRACT = """\
contract_version: 1
nodes:
  /managed:
    lifecycle: active
    publishers: []
    subscriptions: []
    service_servers: []
    service_clients: []
    action_servers: []
    action_clients: []
    parameters:
      - name: blob
        type: byte_array
        default_value: [0, 1, 255]
      - name: depth
        type: integer
        default_value: 5
        integer_range: {from_value: 1, to_value: 10, step: 1}
        declared_in: configure
      - name: description
        type: string
        default_value: "two\\nlines"
        description: 'a, b: [c]'
      - name: gain
        type: double
        default_value: 1.0e+300
        read_only: true
        dynamic_typing: true
        additional_constraints: tuned
        floating_point_range: {from_value: -.inf, to_value: .inf, step: 0.0}
      - name: names
        type: string_array
        default_value: [a, b c, 'x, y']
      - name: nan
        type: double_array
        default_value: [.nan, -.inf]
      - name: typed_only
        type: string
        default_value: null
  /plain:
    publishers: []
    subscriptions: []
    service_servers: []
    service_clients: []
    action_servers: []
    action_clients: []
    parameters: []
"""


def test_contract_with_parameters_and_lifecycle_round_trips_byte_for_byte():
    c = contract_module.loads(CONTRACT)
    assert c.nodes["/managed"]["lifecycle"] == "active"
    assert [p["name"] for p in c.nodes["/managed"]["parameters"]][:2] == ["blob", "depth"]
    assert c.nodes["/plain"]["parameters"] == []
    assert contract_module.dump_nodes(c.nodes) == CONTRACT.split("contract_version: 1\n", 1)[1]
    assert c.dump() == CONTRACT
    assert "parameters" in c.expanded_nodes()["/managed"]


def test_written_capture_view_loads_and_writes_identically(params_node, managed):
    for builder in (params_node, managed):
        nodes = builder.capture().to_contract_nodes()
        text = contract_module.render(nodes)
        loaded = contract_module.loads(text)
        assert contract_module.render(loaded.nodes) == text
        reloaded = yaml.safe_load(text)["nodes"]
        for fqn, node in nodes.items():
            for a, b in zip(node.get("parameters", []), reloaded[fqn].get("parameters", []), strict=True):
                assert all(parameter_model.same_value(a[k], b[k]) for k in a), (a, b)


def test_a_contract_without_parameters_or_lifecycle_states_none():
    c = contract_module.loads("contract_version: 1\nnodes:\n  /t:\n    publishers: []\n")
    assert "parameters" not in c.nodes["/t"] and "lifecycle" not in c.nodes["/t"]
    assert "parameters" not in contract_module.dump_nodes(c.nodes)


def test_line_index_has_parameter_entries():
    index = line_index(CONTRACT)
    assert index[("/managed", "parameters", "depth")] == CONTRACT.splitlines().index("      - name: depth") + 1


@pytest.mark.parametrize(("node_text", "location", "reason"), [
    ("    lifecycle: running\n", "nodes./n.lifecycle", "'running' is not one of: unconfigured, inactive, active"),
    ("    parameters:\n", "nodes./n.parameters", "write `parameters: []` for a node without parameters"),
    ("    parameters:\n      - {name: a}\n", "nodes./n.parameters[0]", "'type' is required"),
    ("    parameters:\n      - {name: a, type: int}\n", "nodes./n.parameters[0].type", "'int' is not one of"),
    ("    parameters:\n      - {name: a, type: bool, default: 1}\n", "nodes./n.parameters[0]", "unknown key 'default'; did you mean 'default_value'?"),
    ("    parameters:\n      - {name: a, type: bool}\n      - {name: a, type: bool}\n",
     "nodes./n.parameters[1].name", "duplicate parameter 'a' (also at parameters[0])"),
    ("    parameters:\n      - {name: a, type: integer, default_value: 1.5}\n", "nodes./n.parameters[0].default_value",
     "parameter 'a': 1.5 is not an integer (node /n)"),
    ("    parameters:\n      - {name: a, type: byte_array, default_value: [300]}\n",
     "nodes./n.parameters[0].default_value", "a byte_array holds integers from 0 to 255"),
    ("    parameters:\n      - {name: a, type: string, integer_range: {from_value: 0, to_value: 1, step: 1}}\n",
     "nodes./n.parameters[0].integer_range", "parameter 'a' of type string cannot have an integer_range"),
    ("    parameters:\n      - {name: a, type: integer, integer_range: {from_value: 0, to_value: 1}}\n",
     "nodes./n.parameters[0].integer_range", "'step' is required"),
])
def test_malformed_parameters_name_place_and_reason(node_text, location, reason):
    text = "contract_version: 1\nnodes:\n  /n:\n" + node_text
    with pytest.raises(ContractError) as info:
        contract_module.loads(text, path="n.interfaces.yaml")
    assert info.value.location == location, str(info.value)
    assert reason in info.value.reason, str(info.value)
    assert info.value.line is not None


def test_preserve_spelling_keeps_a_left_out_default_value_and_adds_missing_parameters():
    old = {"/n": {"publishers": [], "parameters": [{"name": "rate", "type": "double"}]},
           "/m": {"publishers": []}}
    new = {"/n": {"publishers": [], "parameters": [{"name": "rate", "type": "double", "default_value": 2.0},
                                                   {"name": "new", "type": "bool", "default_value": True}]},
           "/m": {"publishers": [], "parameters": [{"name": "x", "type": "bool", "default_value": False}]}}
    out = contract_module.preserve_spelling(old, new)
    assert out["/n"]["parameters"] == [{"name": "rate", "type": "double"},
                                       {"name": "new", "type": "bool", "default_value": True}]
    assert out["/m"]["parameters"] == [{"name": "x", "type": "bool", "default_value": False}]


@pytest.mark.parametrize(("a", "b", "same"), [
    (1.0, 1.0, True), (math.nan, math.nan, True), (1, 1.0, True), (True, 1, False), (False, 0.0, False),
    ([1.0, math.nan], [1.0, math.nan], True), ([1], [1, 2], False), ("a", "a", True), (None, None, True),
    (None, 0, False),
])
def test_same_value(a, b, same):
    assert parameter_model.same_value(a, b) is same


# ---------------------------------------------------------------------------- NoDL export


def test_nodl_export_has_parameters_in_nodl_spelling_and_the_lifecycle_state_in_a_comment(params_node, managed):
    from pytest_rmw_introspect.cli.formats import nodl_documents

    text = nodl_documents(params_node.capture(), raw=False)
    assert "left out" not in text  # NoDL v2's parameter schema has byte arrays
    (doc,) = yaml.safe_load_all(text)
    assert "base" not in doc
    params = doc["parameters"]
    assert params["count"] == {"type": "int", "default_value": 64, "description": "how many"}
    assert params["ids"]["type"] == "int_array"
    assert params["frame"] == {"type": "string", "default_value": "odom", "description": "TF frame", "read_only": True}
    assert params["gain"]["additional_constraints"] == "tuned on the robot"
    assert params["typed_only"] == {"type": "string"}
    assert params["blob"]["type"] == "byte_array"
    assert "use_sim_time" not in params
    raw = next(yaml.safe_load_all(nodl_documents(params_node.capture(), raw=True)))
    assert "use_sim_time" in raw["parameters"]  # raw: the infrastructure ones too
    managed_text = nodl_documents(managed.capture(), raw=False)
    (managed_doc,) = yaml.safe_load_all(managed_text)
    # NoDL v2 has no field for it (its schema allows no other top-level key): a comment says it
    assert "# lifecycle: active (a lifecycle node: NoDL v2 cannot say so, not compared)\n" in managed_text
    assert list(managed_doc)[:2] == ["nodl_version", "parameters"]
