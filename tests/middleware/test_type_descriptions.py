"""The capture's `types` table for a real rclpy node: every endpoint type and every type it
nests, checked field by field against rosidl's own Python classes (their SLOT_TYPES and
constants), which come from the same definitions but through a different generator."""

from __future__ import annotations

import dataclasses

import pytest
import rmwi_helpers as h
import type_tables


def _capture_field(name: str, slot) -> dict:
    """A rosidl_parser slot type in the capture's field shape (keys of unset attributes left out)."""
    field = dataclasses.asdict(type_tables.field_of(name, slot))
    return {key: value for key, value in field.items() if value is not None}


def _constant_matches(recorded: dict, value) -> bool:
    text = recorded["value"]
    if isinstance(value, bool):
        return text.lower() == str(value).lower()
    if isinstance(value, bytes):
        return int(text) == value[0]
    if isinstance(value, (int, float)):
        return float(text) == float(value)
    return text.strip("'\"") == value


@pytest.fixture(scope="module")
def types_capture(middleware_library, tmp_path_factory):
    result = h.run_on_middleware(middleware_library, h.python_node("types_node.py"), tmp_path_factory.mktemp("types"))
    h.assert_settled_process(result)
    return result.capture


def test_every_endpoint_type_and_every_type_it_refers_to_is_described(types_capture):
    types = types_capture["types"]
    for endpoint in types_capture["endpoints"]:
        assert endpoint["type"] in types, endpoint["type"]
    for name, entry in types.items():
        if entry["kind"] == "service":
            assert entry["request"] == name + "_Request" and entry["request"] in types
            assert entry["response"] == name + "_Response" and entry["response"] in types
        else:
            for field in entry["fields"]:
                if "/" in field["type"]:
                    assert field["type"] in types, (name, field)
    # action parts and their implicit goal / result / feedback types
    for part in ("Fibonacci_SendGoal", "Fibonacci_GetResult", "Fibonacci_FeedbackMessage", "Fibonacci_Goal",
                 "Fibonacci_Result", "Fibonacci_Feedback"):
        assert f"test_msgs/action/{part}" in types


def test_fields_and_constants_match_rosidl(types_capture):
    checked = 0
    for name, entry in types_capture["types"].items():
        if entry["kind"] != "message":
            continue
        cls = type_tables.python_class(name)
        expected = [_capture_field(field, slot) for field, slot in zip(cls.get_fields_and_field_types(), cls.SLOT_TYPES,
                                                                strict=True)]
        # rosidl gives an empty message a placeholder member (in the type hash too); Python hides it
        expected = expected or [{"name": "structure_needs_at_least_one_member", "type": "uint8"}]
        assert entry["fields"] == expected, name
        metaclass = type(cls)
        constants = getattr(metaclass, f"_{metaclass.__name__}__constants", {})
        assert "constants" in entry, f"{name}: constants unknown"
        assert [c["name"] for c in entry["constants"]] == list(constants), name
        for recorded in entry["constants"]:
            assert _constant_matches(recorded, constants[recorded["name"]]), (name, recorded)
        checked += 1
    assert checked > 40  # the node's own types and the infrastructure's (rcl_interfaces, ...)


def test_spot_checks(types_capture):
    types = types_capture["types"]
    multi = types["test_msgs/msg/MultiNested"]["fields"]
    assert multi[0] == {"name": "array_of_arrays", "type": "test_msgs/msg/Arrays", "array": "fixed", "array_size": 3}
    assert multi[4] == {"name": "bounded_sequence_of_bounded_sequences", "type": "test_msgs/msg/BoundedSequences",
                        "array": "bounded", "array_size": 3}
    assert multi[8] == {"name": "unbounded_sequence_of_unbounded_sequences",
                        "type": "test_msgs/msg/UnboundedSequences", "array": "unbounded"}
    strings = types["test_msgs/msg/Strings"]
    assert {"name": "bounded_string_value", "type": "string", "string_bound": 22} in strings["fields"]
    assert strings["constants"] == [{"name": "STRING_CONST", "type": "string", "value": '"Hello world!"'}]
    assert types["test_msgs/msg/Constants"]["constants"][2] == {"name": "CHAR_CONST", "type": "uint8", "value": "100"}
    assert types["test_msgs/srv/BasicTypes"] == {
        "kind": "service", "request": "test_msgs/srv/BasicTypes_Request",
        "response": "test_msgs/srv/BasicTypes_Response"}
    cancel = types["action_msgs/srv/CancelGoal_Response"]
    assert [c["name"] for c in cancel["constants"]] == [
        "ERROR_NONE", "ERROR_REJECTED", "ERROR_UNKNOWN_GOAL_ID", "ERROR_GOAL_TERMINATED"]
    assert types["test_msgs/action/Fibonacci_Goal"] == {
        "kind": "message", "fields": [{"name": "order", "type": "int32"}], "constants": []}
    assert types["test_msgs/action/Fibonacci_SendGoal_Request"]["fields"] == [
        {"name": "goal_id", "type": "unique_identifier_msgs/msg/UUID"},
        {"name": "goal", "type": "test_msgs/action/Fibonacci_Goal"}]
