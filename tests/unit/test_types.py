"""Type descriptions (model.types): the capture's `types` table, field and constant lines, which
types an interface needs, and the contract's `types:` section. Tables come from the real message
packages of the venv (type_tables.py)."""

from __future__ import annotations

import copy
import json
from typing import Any

import pytest
from type_tables import describe

from pytest_rmw_introspect.errors import CaptureFormatError, ContractError
from pytest_rmw_introspect.model import contract as contract_module
from pytest_rmw_introspect.model import types as type_model
from pytest_rmw_introspect.model.capture import Capture
from pytest_rmw_introspect.model.types import Constant, Field, MessageType, ServiceType

RICH = ("test_msgs/msg/MultiNested", "test_msgs/msg/Strings", "test_msgs/msg/WStrings",
        "test_msgs/msg/BoundedPlainSequences", "sensor_msgs/msg/LaserScan", "nav_msgs/msg/OccupancyGrid",
        "action_msgs/srv/CancelGoal", "test_msgs/action/Fibonacci_SendGoal")


def to_capture_json(table: type_model.TypeTable) -> dict[str, Any]:
    """A table in the capture file's shape (docs/design.md section 1), as the middleware writes it."""
    out: dict[str, Any] = {}
    for name, entry in table.items():
        if isinstance(entry, ServiceType):
            out[name] = {"kind": "service", "request": entry.request, "response": entry.response}
            continue
        fields = []
        for f in entry.fields:
            field: dict[str, Any] = {"name": f.name, "type": f.type}
            if f.array:
                field["array"] = f.array
                if f.array != "unbounded":
                    field["array_size"] = f.array_size
            if f.string_bound:
                field["string_bound"] = f.string_bound
            fields.append(field)
        out[name] = {"kind": "message", "fields": fields}
        if entry.constants is not None:
            out[name]["constants"] = [{"name": c.name, "type": c.type, "value": c.value} for c in entry.constants]
    return out


# ---------------------------------------------------------------------------- lines


def test_field_lines_round_trip_over_real_messages():
    table = describe(*RICH)
    lines = [f.line() for entry in table.values() if isinstance(entry, MessageType) for f in entry.fields]
    assert len(lines) > 150
    for line in lines:
        assert Field.parse(line).line() == line
    multi = table["test_msgs/msg/MultiNested"]
    assert isinstance(multi, MessageType)
    assert [f.line() for f in multi.fields][3:6] == [
        "test_msgs/msg/Arrays[<=3] bounded_sequence_of_arrays",
        "test_msgs/msg/BoundedSequences[<=3] bounded_sequence_of_bounded_sequences",
        "test_msgs/msg/UnboundedSequences[<=3] bounded_sequence_of_unbounded_sequences",
    ]
    strings = table["test_msgs/msg/Strings"]
    assert isinstance(strings, MessageType)
    assert strings.fields[6] == Field("bounded_string_value", "string", string_bound=22)
    assert strings.constants == (Constant("STRING_CONST", "string", '"Hello world!"'),)


@pytest.mark.parametrize("line, field", [
    ("float64 x", Field("x", "float64")),
    ("string<=10 name", Field("name", "string", string_bound=10)),
    ("wstring<=3[<=5] names", Field("names", "wstring", "bounded", 5, 3)),
    ("int32[3] xs", Field("xs", "int32", "fixed", 3)),
    ("uint8[] data", Field("data", "uint8", "unbounded")),
    ("geometry_msgs/msg/Point[<=2] ends", Field("ends", "geometry_msgs/msg/Point", "bounded", 2)),
])
def test_field_parse(line, field):
    assert Field.parse(line) == field
    assert field.line() == line


@pytest.mark.parametrize("line, reason", [
    ("float64", "is not a field line"),
    ("float64 x y", "is not a field line"),
    ("float64 9x", "is not a field name"),
    ("int32<=3 x", "only string and wstring take a bound"),
    ("int32[<=] x", "needs its bound"),
    ("int32[x] x", "is not a field type"),
    (3, "is not a field line"),
])
def test_field_parse_errors(line, reason):
    with pytest.raises(ValueError, match=reason):
        Field.parse(line)


def test_constant_lines():
    constant = Constant.parse('string GREETING="a = b # c"')
    assert constant == Constant("GREETING", "string", '"a = b # c"')
    assert constant.line() == 'string GREETING="a = b # c"'
    assert Constant.parse("int8  ERROR_NONE = 0") == Constant("ERROR_NONE", "int8", "0")
    for bad in ("int8 ERROR_NONE", "ERROR=1", "int8 BAD NAME=1", "int8<x X=1"):
        with pytest.raises(ValueError):
            Constant.parse(bad)


# ---------------------------------------------------------------------------- capture table


def test_capture_table_reads_what_the_middleware_writes():
    table = describe(*RICH)
    assert type_model.from_capture(to_capture_json(table)) == table
    assert type_model.from_capture(None) == {}


def test_constants_unknown_stay_unknown():
    data = {"pkg/msg/Idl": {"kind": "message", "fields": [{"name": "x", "type": "int32"}]}}
    entry = type_model.from_capture(data)["pkg/msg/Idl"]
    assert isinstance(entry, MessageType) and entry.constants is None


def test_capture_table_entries_read_before_are_reused_while_they_are_equal():
    data = to_capture_json(describe("std_msgs/msg/String"))
    first = type_model.from_capture(data)["std_msgs/msg/String"]
    again = type_model.from_capture(json.loads(json.dumps(data)))["std_msgs/msg/String"]
    assert again is first  # the same entry (an equal copy): read once
    # and the copy in the second capture's document is the first one's: N captures of a system
    # hold one description of each type, not N (issue 42)
    second = json.loads(json.dumps(data))
    type_model.from_capture(second)
    assert second["std_msgs/msg/String"] is data["std_msgs/msg/String"]
    changed = json.loads(json.dumps(data))
    changed["std_msgs/msg/String"]["fields"].append({"name": "extra", "type": "int8"})
    read = type_model.from_capture(changed)["std_msgs/msg/String"]
    assert [f.name for f in read.fields] == ["data", "extra"]
    broken = json.loads(json.dumps(data))
    broken["std_msgs/msg/String"]["fields"].append({"name": "x"})
    with pytest.raises(ValueError, match="needs a `name` and a `type`"):  # an entry read before is no pass
        type_model.from_capture(broken)


@pytest.mark.parametrize("mutate, reason", [
    (lambda t: t.update({"x/msg/Y": []}), "is not an object"),
    (lambda t: t.update({"x/msg/Y": {"kind": "enum"}}), "unknown kind"),
    (lambda t: t["std_msgs/msg/String"].update({"fields": {}}), "`fields` is not a list"),
    (lambda t: t["std_msgs/msg/String"]["fields"].append({"name": "x"}), "needs a `name` and a `type`"),
    (lambda t: t["std_msgs/msg/String"]["fields"].append({"name": "x", "type": "int8", "array": "ring"}),
     "unknown array kind"),
    (lambda t: t["std_msgs/msg/String"]["fields"].append(
        {"name": "x", "type": "int8", "array": "fixed", "array_size": -1}), "not a non-negative integer"),
    (lambda t: t["std_msgs/msg/String"].update({"constants": [{"name": "A"}]}), "needs `name`, `type` and `value`"),
    (lambda t: t.update({"x/srv/Y": {"kind": "service", "request": "x/srv/Y_Request"}}),
     "needs `request` and `response`"),
])
def test_capture_table_errors(mutate, reason):
    data = to_capture_json(describe("std_msgs/msg/String"))
    mutate(data)
    with pytest.raises(ValueError, match=reason):
        type_model.from_capture(data)


# ---------------------------------------------------------------------------- the capture model

HASH = "RIHS01_" + "ab" * 32
QOS = {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE",
       "liveliness": "SYSTEM_DEFAULT", "deadline_ns": 0, "lifespan_ns": 0, "liveliness_lease_duration_ns": 0,
       "avoid_ros_namespace_conventions": False}


def capture_doc(table: type_model.TypeTable | None) -> dict[str, Any]:
    endpoints = [
        ("publisher", "/scan", "sensor_msgs/msg/LaserScan"),
        ("publisher", "/rosout", "rcl_interfaces/msg/Log"),
        ("service", "/cancel", "action_msgs/srv/CancelGoal"),
        ("service", "/fib/_action/send_goal", "test_msgs/action/Fibonacci_SendGoal"),
        ("service", "/fib/_action/get_result", "test_msgs/action/Fibonacci_GetResult"),
        ("publisher", "/fib/_action/feedback", "test_msgs/action/Fibonacci_FeedbackMessage"),
    ]
    doc: dict[str, Any] = {
        "format": "rmw_introspect_capture", "format_version": 1, "state": "settled",
        "nodes": [{"id": 1, "seq": 1, "name": "n", "namespace": "/", "fqn": "/n"}],
        "endpoints": [
            {"seq": i + 2, "kind": kind, "node_id": 1, "node": "/n", "name": name, "type": type_name,
             "type_hash": HASH, "qos": QOS}
            for i, (kind, name, type_name) in enumerate(endpoints)
        ],
    }
    if table is not None:
        doc["types"] = to_capture_json(table)
    return doc


ALL_TYPES = ("sensor_msgs/msg/LaserScan", "rcl_interfaces/msg/Log", "action_msgs/srv/CancelGoal",
             "test_msgs/action/Fibonacci_SendGoal", "test_msgs/action/Fibonacci_GetResult",
             "test_msgs/action/Fibonacci_FeedbackMessage")


def test_capture_reads_its_types_and_gives_the_contract_part():
    table = describe(*ALL_TYPES)
    capture = Capture.from_dict(capture_doc(table))
    assert capture.has_types and capture.types == table
    section = capture.to_contract_types()
    # the contract view's interfaces (no /rosout: infrastructure), actions by their three parts
    assert list(section) == sorted(section)
    assert "rcl_interfaces/msg/Log" not in section
    assert set(section) == {
        "sensor_msgs/msg/LaserScan", "std_msgs/msg/Header", "builtin_interfaces/msg/Time",
        "action_msgs/srv/CancelGoal", "action_msgs/srv/CancelGoal_Request", "action_msgs/srv/CancelGoal_Response",
        "action_msgs/msg/GoalInfo", "unique_identifier_msgs/msg/UUID",
        "test_msgs/action/Fibonacci_SendGoal", "test_msgs/action/Fibonacci_SendGoal_Request",
        "test_msgs/action/Fibonacci_SendGoal_Response", "test_msgs/action/Fibonacci_Goal",
        "test_msgs/action/Fibonacci_GetResult", "test_msgs/action/Fibonacci_GetResult_Request",
        "test_msgs/action/Fibonacci_GetResult_Response", "test_msgs/action/Fibonacci_Result",
        "test_msgs/action/Fibonacci_FeedbackMessage", "test_msgs/action/Fibonacci_Feedback",
    }
    with_infra = capture.with_infrastructure(True)
    assert with_infra.types == table and "rcl_interfaces/msg/Log" in with_infra.to_contract_types()


def test_capture_without_types_table():
    capture = Capture.from_dict(capture_doc(None))
    assert not capture.has_types and capture.types == {} and capture.to_contract_types() == {}


def test_capture_with_a_malformed_types_table_is_a_format_error():
    doc = capture_doc(describe("sensor_msgs/msg/LaserScan"))
    broken = copy.deepcopy(doc)
    broken["types"]["sensor_msgs/msg/LaserScan"]["kind"] = "blob"
    with pytest.raises(CaptureFormatError, match="unknown kind"):
        Capture.from_dict(broken)


def test_closure_order_roots_first_then_depth_first():
    table = describe("action_msgs/srv/CancelGoal")
    assert type_model.closure(table, ["action_msgs/srv/CancelGoal", "not/msg/Described"]) == [
        "action_msgs/srv/CancelGoal", "action_msgs/srv/CancelGoal_Request", "action_msgs/msg/GoalInfo",
        "unique_identifier_msgs/msg/UUID", "builtin_interfaces/msg/Time", "action_msgs/srv/CancelGoal_Response",
    ]
    assert type_model.interface_roots("action_clients", "a/action/B") == [
        "a/action/B_SendGoal", "a/action/B_GetResult", "a/action/B_FeedbackMessage"]
    assert type_model.interface_roots("subscriptions", "a/msg/B") == ["a/msg/B"]


# ---------------------------------------------------------------------------- contract section

CONTRACT = """\
# header comment
contract_version: 1
options:
  include_types: true
nodes:
  /n:
    publishers:
      - name: /scan
        type: sensor_msgs/msg/LaserScan
"""


def test_section_round_trips_and_is_deterministic():
    table = describe(*RICH)
    text = type_model.render_section(table)
    assert text.startswith("# Generated with include_types")
    assert type_model.render_section(dict(reversed(list(table.items())))) == text  # sorted by name
    loaded = contract_module.loads(CONTRACT + "\n" + text)
    assert loaded.types == {name: table[name] for name in sorted(table)}
    # service entries name their parts; message lines are .msg lines
    assert "  action_msgs/srv/CancelGoal:\n    request: action_msgs/srv/CancelGoal_Request\n" in text
    assert ("  test_msgs/msg/Strings:\n    fields:\n      - string string_value\n" in text)
    assert "      - string<=22 bounded_string_value\n" in text
    assert "    constants:\n      - string STRING_CONST=\"Hello world!\"\n" in text
    assert "  builtin_interfaces/msg/Time:\n    fields:\n      - int32 sec\n      - uint32 nanosec\n    constants: []\n" in text


def test_unknown_constants_are_left_out_and_read_back_as_unknown():
    table = {"pkg/msg/Idl": MessageType("pkg/msg/Idl", (Field("x", "int32"),), None)}
    text = type_model.render_section(table)
    assert "constants" not in text
    assert contract_module.loads(CONTRACT + text).types == table


def test_replace_section_appends_then_replaces_in_place():
    table = describe("sensor_msgs/msg/LaserScan")
    first = type_model.replace_section(CONTRACT, table)
    assert first.startswith(CONTRACT + "\n# Generated with include_types")
    assert type_model.replace_section(first, table) == first  # regenerating changes no byte
    trailer = "\n# a key after the section\nextra: 1\n"
    with_trailer = first + trailer
    smaller = describe("std_msgs/msg/Header")
    replaced = type_model.replace_section(with_trailer, smaller)
    assert replaced == CONTRACT + "\n" + type_model.render_section(smaller) + trailer
    assert type_model.replace_section("", {}) == type_model.render_section({})
    assert "types: {}" in type_model.render_section({})


def test_a_section_above_nodes_is_replaced_where_it_is():
    table = describe("std_msgs/msg/Header")
    text = "contract_version: 1\ntypes:\n  x/msg/Y:\n    fields:\n      - int8 a\nnodes: {}\n"
    replaced = type_model.replace_section(text, table)
    assert replaced == "contract_version: 1\n" + type_model.render_section(table) + "nodes: {}\n"


def test_contracts_without_a_section_have_none():
    assert contract_module.loads(CONTRACT).types is None
    assert contract_module.loads(CONTRACT + "types:\n").types == {}


@pytest.mark.parametrize("section, location, reason", [
    ("types: [1]\n", "types", "is not of type"),
    ("types:\n  notatype:\n    fields: []\n", "types.notatype", "is not an interface type"),
    ("types:\n  a/msg/B: 3\n", "types.a/msg/B", "is not of type"),
    ("types:\n  a/msg/B:\n    constants: []\n", "types.a/msg/B.fields", "a message needs its `fields`"),
    ("types:\n  a/msg/B:\n    fields:\n      - int8 x\n      - bad\n", "types.a/msg/B.fields[1]",
     "is not a field line"),
    ("types:\n  a/msg/B:\n    fields:\n      - int8 x\n      - int16 x\n", "types.a/msg/B.fields", "appears twice"),
    ("types:\n  a/msg/B:\n    fields: []\n    constants:\n      - int8 X\n", "types.a/msg/B.constants[0]",
     "is not a constant line"),
    ("types:\n  a/srv/B:\n    request: a/srv/B_Request\n", "types.a/srv/B.response", "needs its response"),
    ("types:\n  a/srv/B:\n    request: a/srv/B_Request\n    response: a/srv/B_Response\n    fields: []\n",
     "types.a/srv/B", "not both"),
    ("types:\n  a/msg/B:\n    fields: []\n    comment: x\n", "types.a/msg/B", "unknown key 'comment'"),
])
def test_section_errors_name_the_place(section, location, reason):
    with pytest.raises(ContractError) as info:
        contract_module.loads(CONTRACT + section)
    assert info.value.location == location and reason in info.value.reason, (info.value.location, info.value.reason)
    assert info.value.line is not None
