"""Type descriptions in comparisons: the contract's `types:` section against the capture's
table (include_types), and what --update-golden writes. Tables come from the real message
packages of the venv (type_tables.py)."""

from __future__ import annotations

import copy
import dataclasses
from pathlib import Path

import pytest
from type_tables import describe

from pytest_rmw_introspect.check import diff, pipeline
from pytest_rmw_introspect.compare import type_drift
from pytest_rmw_introspect.compare.drift import compare
from pytest_rmw_introspect.compare.options import ComparisonOptions, parse_layer
from pytest_rmw_introspect.model import contract as contract_module
from pytest_rmw_introspect.model.capture import Capture
from pytest_rmw_introspect.model.types import Constant, Field, MessageType, to_contract

HASH = "RIHS01_" + "ab" * 32
NODES = {"/n": {
    "publishers": [{"name": "/scan", "type": "sensor_msgs/msg/LaserScan", "type_hash": HASH}],
    "action_servers": [{"name": "/fib", "type": "test_msgs/action/Fibonacci"}],
}}
#: the rules of the types: section these tests trigger (test_drift.py checks every rule has a test)
TESTED_RULES = {"TYPE_DESCRIPTION_MISSING"}
ACTION_PARTS = ("test_msgs/action/Fibonacci_SendGoal", "test_msgs/action/Fibonacci_GetResult",
                "test_msgs/action/Fibonacci_FeedbackMessage")


def test_include_types_is_an_option_of_every_source():
    assert ComparisonOptions().include_types is False
    assert parse_layer({"include_types": "yes"}, "ini file") == {"include_types": True}
    assert parse_layer({"include_types": None}, "command line") == {}


def test_missing_descriptions_are_drift_only_with_include_types():
    captured = describe("sensor_msgs/msg/LaserScan", *ACTION_PARTS)
    partial = {k: v for k, v in captured.items() if k != "std_msgs/msg/Header"}
    items = compare(NODES, NODES, expected_types=partial, actual_types=captured, require_types=True)
    assert [(i.rule, i.kind, i.name, i.new) for i in items] == [
        ("TYPE_DESCRIPTION_MISSING", "publishers", "/scan", ["std_msgs/msg/Header"])]
    assert "does not describe std_msgs/msg/Header" in items[0].message
    # no section at all: every interface lacks its types
    items = compare(NODES, NODES, expected_types=None, actual_types=captured, require_types=True)
    assert {(i.name, i.new[0]) for i in items} == {
        ("/scan", "sensor_msgs/msg/LaserScan"), ("/fib", "test_msgs/action/Fibonacci_SendGoal")}
    # without include_types, or without types on the captured side, nothing is said
    assert compare(NODES, NODES, expected_types=None, actual_types=captured) == []
    assert compare(NODES, NODES, expected_types=None, actual_types=None, require_types=True) == []
    assert compare(NODES, NODES, expected_types=captured, actual_types=captured, require_types=True) == []


def _capture(table) -> Capture:
    from test_types import capture_doc  # the capture document of test_types (a publisher, a service, an action)

    return Capture.from_dict(capture_doc(table))


def _result(contract_text: str | None, options: ComparisonOptions, capture: Capture) -> pipeline.CheckResult:
    contract = contract_module.loads(contract_text, path="c.yaml") if contract_text else None
    prepared = pipeline.Prepared(path=Path("c.yaml"), shown="c.yaml", contract=contract, spec=None,  # type: ignore[arg-type]
                                 options=options)
    return pipeline.compare(prepared, capture)


def test_golden_types_follow_the_option_or_an_existing_section():
    from test_types import ALL_TYPES

    capture = _capture(describe(*ALL_TYPES))
    plain = "contract_version: 1\nnodes: {}\n"
    assert _result(plain, ComparisonOptions(), capture).golden_types() is None
    on = _result(plain, ComparisonOptions(include_types=True), capture).golden_types()
    assert on == capture.to_contract_types() and "sensor_msgs/msg/LaserScan" in on
    kept = _result(plain + "types: {}\n", ComparisonOptions(), capture).golden_types()
    assert kept == capture.to_contract_types()
    assert _result(None, ComparisonOptions(include_types=True), capture).golden_types() == on
    # a capture of a middleware without types never removes or empties a section
    assert _result(plain + "types: {}\n", ComparisonOptions(include_types=True), _capture(None)).golden_types() is None


def test_check_with_include_types_reports_then_accepts_the_section(tmp_path):
    from test_types import ALL_TYPES

    capture = _capture(describe(*ALL_TYPES))
    path = tmp_path / "c.yaml"
    path.write_text("contract_version: 1\noptions: {include_types: true}\n" + contract_module.dump_nodes(
        capture.to_contract_nodes()))
    prepared = pipeline.prepare(path, layers=pipeline.Layers(strong_target=[({"script": "x.py"}, tmp_path, "t")]))
    result = pipeline.compare(prepared, capture)
    assert {i.rule for i in result.items} == {"TYPE_DESCRIPTION_MISSING"} and result.failed
    assert result.update() == "updated"
    again = pipeline.compare(pipeline.prepare(path, layers=pipeline.Layers(
        strong_target=[({"script": "x.py"}, tmp_path, "t")])), capture)
    assert again.items == [] and again.contract is not None
    assert to_contract(again.contract.types or {}) == to_contract(capture.to_contract_types())


# ---------------------------------------------------------------------------- field-level diff
# Before/after definitions built from real message packages: pairs of real messages that
# differ the way a definition changes (Point32 → Point is float32 → float64), and hand-edited
# variants of real ones (dataclasses.replace on what type_tables.describe read from the venv).

REAL = describe(
    "sensor_msgs/msg/LaserScan", "geometry_msgs/msg/Point", "geometry_msgs/msg/Point32", "geometry_msgs/msg/Vector3",
    "geometry_msgs/msg/Twist", "geometry_msgs/msg/Wrench", "test_msgs/msg/Arrays", "test_msgs/msg/BoundedSequences",
    "test_msgs/msg/BoundedPlainSequences", "test_msgs/msg/UnboundedSequences", "test_msgs/msg/Strings",
    "test_msgs/msg/WStrings", "test_msgs/msg/Constants", "action_msgs/srv/CancelGoal", "std_msgs/msg/String",
    "std_msgs/msg/Int32",
)


def msg(name: str) -> MessageType:
    entry = REAL[name]
    assert isinstance(entry, MessageType)
    return entry


def edit(name: str, *, fields: list[str] | None = None, constants: list[str] | None = None) -> MessageType:
    """A hand-edited variant of a real message: its field (and constant) lines replaced."""
    base = msg(name)
    return dataclasses.replace(
        base,
        fields=tuple(Field.parse(f) for f in fields) if fields is not None else base.fields,
        constants=tuple(Constant.parse(c) for c in constants) if constants is not None else base.constants)


def lines(name: str) -> list[str]:
    return [f.line() for f in msg(name).fields]


def without(field_lines: list[str], *names: str) -> list[str]:
    return [line for line in field_lines if line.split()[1] not in names]


def replaced(field_lines: list[str], old: str, new: str) -> list[str]:
    return [new if line == old else line for line in field_lines]


SCAN = lines("sensor_msgs/msg/LaserScan")
SEQ_FIELDS = [f for f in lines("test_msgs/msg/BoundedSequences") if "[<=3]" in f]

DIFF_ROWS = [
    # (id, before, after, [(rule, old, new), ...] in report order)
    ("same_fields_other_name", msg("geometry_msgs/msg/Vector3"), msg("geometry_msgs/msg/Point"), []),
    ("float32_to_float64", msg("geometry_msgs/msg/Point32"), msg("geometry_msgs/msg/Point"), [
        ("TYPE_FIELD_RETYPED", "float32 x", "float64 x"),
        ("TYPE_FIELD_RETYPED", "float32 y", "float64 y"),
        ("TYPE_FIELD_RETYPED", "float32 z", "float64 z"),
    ]),
    ("string_to_int32", msg("std_msgs/msg/String"), msg("std_msgs/msg/Int32"), [
        ("TYPE_FIELD_RETYPED", "string data", "int32 data"),
    ]),
    ("twist_to_wrench_looks_renamed", msg("geometry_msgs/msg/Twist"), msg("geometry_msgs/msg/Wrench"), [
        ("TYPE_FIELD_RENAMED", "geometry_msgs/msg/Vector3 linear", "geometry_msgs/msg/Vector3 force"),
        ("TYPE_FIELD_RENAMED", "geometry_msgs/msg/Vector3 angular", "geometry_msgs/msg/Vector3 torque"),
    ]),
    ("string_fields_removed", msg("test_msgs/msg/BoundedSequences"), msg("test_msgs/msg/BoundedPlainSequences"), [
        ("TYPE_FIELD_REMOVED", "string[<=3] string_values", None),
        ("TYPE_FIELD_REMOVED", "string[<=3] string_values_default", None),
    ]),
    ("fixed_arrays_to_bounded_sequences", msg("test_msgs/msg/Arrays"), msg("test_msgs/msg/BoundedSequences"), [
        ("TYPE_FIELD_RETYPED", f.replace("[<=3]", "[3]"), f) for f in SEQ_FIELDS
    ]),
    ("bounded_to_unbounded_sequences", msg("test_msgs/msg/BoundedSequences"), msg("test_msgs/msg/UnboundedSequences"), [
        ("TYPE_FIELD_BOUND_WIDENED", f, f.replace("[<=3]", "[]")) for f in SEQ_FIELDS
    ]),
    ("unbounded_to_bounded_sequences", msg("test_msgs/msg/UnboundedSequences"), msg("test_msgs/msg/BoundedSequences"), [
        ("TYPE_FIELD_BOUND_NARROWED", f.replace("[<=3]", "[]"), f) for f in SEQ_FIELDS
    ]),
    ("string_bound_lowered", msg("test_msgs/msg/Strings"),
     edit("test_msgs/msg/Strings", fields=replaced(lines("test_msgs/msg/Strings"), "string<=22 bounded_string_value",
                                                   "string<=10 bounded_string_value")), [
        ("TYPE_FIELD_BOUND_NARROWED", "string<=22 bounded_string_value", "string<=10 bounded_string_value"),
    ]),
    ("string_bound_removed", msg("test_msgs/msg/Strings"),
     edit("test_msgs/msg/Strings", fields=replaced(lines("test_msgs/msg/Strings"), "string<=22 bounded_string_value",
                                                   "string bounded_string_value")), [
        ("TYPE_FIELD_BOUND_WIDENED", "string<=22 bounded_string_value", "string bounded_string_value"),
    ]),
    ("sequence_and_string_bounds_at_once", msg("test_msgs/msg/WStrings"),
     edit("test_msgs/msg/WStrings", fields=replaced(lines("test_msgs/msg/WStrings"),
                                                    "wstring[<=3] bounded_sequence_of_wstrings",
                                                    "wstring<=8[<=5] bounded_sequence_of_wstrings")), [
        ("TYPE_FIELD_BOUND_WIDENED", "wstring[<=3] bounded_sequence_of_wstrings",
         "wstring<=8[<=5] bounded_sequence_of_wstrings"),
        ("TYPE_FIELD_BOUND_NARROWED", "wstring[<=3] bounded_sequence_of_wstrings",
         "wstring<=8[<=5] bounded_sequence_of_wstrings"),
    ]),
    ("fixed_size_changed", msg("test_msgs/msg/Arrays"),
     edit("test_msgs/msg/Arrays", fields=replaced(lines("test_msgs/msg/Arrays"), "int32[3] int32_values",
                                                  "int32[4] int32_values")), [
        ("TYPE_FIELD_RETYPED", "int32[3] int32_values", "int32[4] int32_values"),
    ]),
    ("field_renamed_in_place", msg("sensor_msgs/msg/LaserScan"),
     edit("sensor_msgs/msg/LaserScan", fields=replaced(SCAN, "float32 range_min", "float32 range_minimum")), [
        ("TYPE_FIELD_RENAMED", "float32 range_min", "float32 range_minimum"),
    ]),
    ("renamed_and_retyped_is_removed_plus_inserted", msg("sensor_msgs/msg/LaserScan"),
     edit("sensor_msgs/msg/LaserScan", fields=replaced(SCAN, "float32 range_min", "float64 range_minimum")), [
        ("TYPE_FIELD_REMOVED", "float32 range_min", None),
        ("TYPE_FIELD_INSERTED", None, "float64 range_minimum"),
    ]),
    ("field_appended", msg("sensor_msgs/msg/LaserScan"),
     edit("sensor_msgs/msg/LaserScan", fields=SCAN + ["uint8[] quality"]), [
        ("TYPE_FIELD_ADDED", None, "uint8[] quality"),
    ]),
    ("field_inserted", msg("sensor_msgs/msg/LaserScan"),
     edit("sensor_msgs/msg/LaserScan", fields=SCAN[:1] + ["string<=16 sensor_id"] + SCAN[1:]), [
        ("TYPE_FIELD_INSERTED", None, "string<=16 sensor_id"),
    ]),
    ("fields_reordered", msg("sensor_msgs/msg/LaserScan"),
     edit("sensor_msgs/msg/LaserScan", fields=[SCAN[0], SCAN[2], SCAN[1], *SCAN[3:]]), [
        ("TYPE_FIELDS_REORDERED", [f.split()[1] for f in SCAN],
         [f.split()[1] for f in [SCAN[0], SCAN[2], SCAN[1], *SCAN[3:]]]),
    ]),
    ("field_removed_from_the_middle", msg("sensor_msgs/msg/LaserScan"),
     edit("sensor_msgs/msg/LaserScan", fields=without(SCAN, "time_increment")), [
        ("TYPE_FIELD_REMOVED", "float32 time_increment", None),
    ]),
    ("constants_changed_removed_added", msg("action_msgs/srv/CancelGoal_Response"),
     edit("action_msgs/srv/CancelGoal_Response", constants=[
         "int8 ERROR_NONE=0", "int8 ERROR_REJECTED=5", "int8 ERROR_UNKNOWN_GOAL_ID=2", "int8 ERROR_TIMEOUT=4"]), [
        ("TYPE_CONSTANT_CHANGED", "int8 ERROR_REJECTED=1", "int8 ERROR_REJECTED=5"),
        ("TYPE_CONSTANT_REMOVED", "int8 ERROR_GOAL_TERMINATED=3", None),
        ("TYPE_CONSTANT_ADDED", None, "int8 ERROR_TIMEOUT=4"),
    ]),
    ("constant_type_changed", msg("test_msgs/msg/Constants"),
     edit("test_msgs/msg/Constants", constants=[c.line().replace("int8 INT8_CONST", "int16 INT8_CONST")
                                                for c in msg("test_msgs/msg/Constants").constants or ()]), [
        ("TYPE_CONSTANT_CHANGED", "int8 INT8_CONST=-50", "int16 INT8_CONST=-50"),
    ]),
    ("unknown_constants_are_not_compared", msg("test_msgs/msg/Constants"),
     dataclasses.replace(msg("test_msgs/msg/Constants"), constants=None), []),
]
TESTED_RULES |= {rule for row in DIFF_ROWS for rule, _old, _new in row[3]}


@pytest.mark.parametrize("before, after, expected", [row[1:] for row in DIFF_ROWS], ids=[row[0] for row in DIFF_ROWS])
def test_field_level_diff(before, after, expected):
    changes = type_drift.compare_messages(before, after)
    assert [(c.rule, c.old, c.new) for c in changes] == expected
    for c in changes:
        assert c.type_name == before.name and c.message.startswith(before.name + ": ")
        assert c.rule in type_drift.RULES


def test_every_field_rule_has_a_row():
    assert set(type_drift.RULES) <= TESTED_RULES


def test_messages_say_what_changed():
    by_rule = {row[0]: type_drift.compare_messages(row[1], row[2]) for row in DIFF_ROWS}
    assert by_rule["float32_to_float64"][0].message == (
        "geometry_msgs/msg/Point32: field `x` float32 -> float64: the field's wire representation changes")
    assert "field `linear` looks renamed to `force` (same type geometry_msgs/msg/Vector3, same place)" in (
        by_rule["twist_to_wrench_looks_renamed"][0].message)
    assert "inserted before `angle_min`: every field after it moves on the wire" in by_rule["field_inserted"][0].message
    assert "fields reordered (`angle_min` moved): the wire layout changes" in by_rule["fields_reordered"][0].message
    assert by_rule["field_removed_from_the_middle"][0].message.endswith("the fields after it move on the wire")
    assert by_rule["string_fields_removed"][1].message.endswith(
        "string_values_default` removed: readers of it break and the fields after it move on the wire")
    assert "strings longer than 10, valid before, are now rejected" in by_rule["string_bound_lowered"][0].message
    assert "reject strings longer than 22" in by_rule["string_bound_removed"][0].message
    assert "not in the type hash" in by_rule["constants_changed_removed_added"][0].message


def test_nested_types_are_compared_through_the_interface_roots():
    before = describe("sensor_msgs/msg/LaserScan")
    after = dict(before)
    header = msg("std_msgs/msg/Header")
    after["std_msgs/msg/Header"] = dataclasses.replace(header, fields=(header.fields[0], Field("frame", "string")))
    changes = type_drift.compare_tables(before, after, ["sensor_msgs/msg/LaserScan"])
    assert [(c.type_name, c.rule, c.old, c.new) for c in changes] == [
        ("std_msgs/msg/Header", "TYPE_FIELD_RENAMED", "string frame_id", "string frame")]
    # a field retyped to another nested type: one item, the two nested types are not compared
    scan = msg("sensor_msgs/msg/LaserScan")
    after = dict(before, **describe("geometry_msgs/msg/Point"))
    after["sensor_msgs/msg/LaserScan"] = dataclasses.replace(
        scan, fields=(Field("header", "geometry_msgs/msg/Point"), *scan.fields[1:]))
    changes = type_drift.compare_tables(before, after, ["sensor_msgs/msg/LaserScan"])
    assert [(c.rule, c.old, c.new) for c in changes] == [
        ("TYPE_FIELD_RETYPED", "std_msgs/msg/Header header", "geometry_msgs/msg/Point header")]


# ---------------------------------------------------------------------------- in drift.compare

OTHER_HASH = "RIHS01_" + "cd" * 32


def scan_with(fields: list[str]) -> dict:
    table = describe("sensor_msgs/msg/LaserScan", *ACTION_PARTS)
    table["sensor_msgs/msg/LaserScan"] = edit("sensor_msgs/msg/LaserScan", fields=fields)
    return table


def changed_nodes() -> dict:
    nodes = copy.deepcopy(NODES)
    nodes["/n"]["publishers"][0]["type_hash"] = OTHER_HASH
    return nodes


def test_drift_reports_field_changes_under_the_interface_whose_hash_changed():
    before = describe("sensor_msgs/msg/LaserScan", *ACTION_PARTS)
    after = scan_with(replaced(SCAN, "float32 range_min", "float32 range_minimum") + ["uint8[] quality"])
    items = compare(NODES, changed_nodes(), expected_types=before, actual_types=after)
    assert [(i.severity.name, i.rule, i.kind, i.name, i.change, i.old, i.new) for i in items] == [
        ("BREAKING", "TYPE_HASH_CHANGED", "publishers", "/scan", "type_hash", HASH, OTHER_HASH),
        ("BREAKING", "TYPE_FIELD_RENAMED", "publishers", "/scan", "type:sensor_msgs/msg/LaserScan",
         "float32 range_min", "float32 range_minimum"),
        ("RISKY", "TYPE_FIELD_ADDED", "publishers", "/scan", "type:sensor_msgs/msg/LaserScan", None,
         "uint8[] quality"),
    ]
    assert items[0].message == ("message definition of sensor_msgs/msg/LaserScan changed; the types: section "
                                "shows how (2 field-level changes listed under this interface)")
    # options that remove the hash item keep the field-level items (they judge the change themselves)
    ignored = compare(NODES, changed_nodes(), ComparisonOptions(ignore_type_hash=True),
                      expected_types=before, actual_types=after)
    assert [i.rule for i in ignored] == ["TYPE_FIELD_RENAMED", "TYPE_FIELD_ADDED"]


def test_a_hash_change_the_descriptions_do_not_explain_says_so():
    table = describe("sensor_msgs/msg/LaserScan", *ACTION_PARTS)
    items = compare(NODES, changed_nodes(), expected_types=table, actual_types=table)
    assert [i.rule for i in items] == ["TYPE_HASH_CHANGED"]
    assert items[0].message.endswith("; the recorded type descriptions show no difference (a change they do not "
                                     "hold, or a types: section older than the type hash)")
    # without descriptions on one side the hash item is as before
    plain = compare(NODES, changed_nodes(), expected_types=None, actual_types=table)
    assert plain[0].message == "message definition of sensor_msgs/msg/LaserScan changed"


def test_constant_changes_are_drift_even_with_the_same_hash():
    before = describe("sensor_msgs/msg/LaserScan", *ACTION_PARTS)
    after = dict(before)
    goal = msg("action_msgs/srv/CancelGoal_Response")  # any real constants, moved onto the action's goal
    after["test_msgs/action/Fibonacci_Goal"] = dataclasses.replace(
        before["test_msgs/action/Fibonacci_Goal"], constants=goal.constants)
    items = compare(NODES, NODES, expected_types=before, actual_types=after)
    assert [(i.kind, i.name, i.rule, i.change) for i in items] == [
        ("action_servers", "/fib", "TYPE_CONSTANT_ADDED", "type:test_msgs/action/Fibonacci_Goal")] * 4


def test_interfaces_with_a_changed_type_name_are_not_compared_field_by_field():
    nodes = copy.deepcopy(NODES)
    nodes["/n"]["publishers"][0]["type"] = "geometry_msgs/msg/Point"
    table = describe("sensor_msgs/msg/LaserScan", "geometry_msgs/msg/Point", *ACTION_PARTS)
    assert [i.rule for i in compare(NODES, nodes, expected_types=table, actual_types=table)] == ["TYPE_CHANGED"]


# ---------------------------------------------------------------------------- report and diff


def test_report_groups_field_changes_under_their_interface():
    from pytest_rmw_introspect.compare import report

    before = describe("sensor_msgs/msg/LaserScan", *ACTION_PARTS)
    after = scan_with(replaced(SCAN, "float32 range_min", "float32 range_minimum") + ["uint8[] quality"])
    items = compare(NODES, changed_nodes(), expected_types=before, actual_types=after)
    assert report.render_text(items, contract_path="scan.yaml") == (
        "Interface drift against scan.yaml: 3 changes (2 breaking, 1 risky, 0 safe)\n"
        "Result: FAIL (fail on: any)\n"
        "\n"
        "BREAKING (2)\n"
        "  /n\n"
        "    publisher /scan\n"
        "      [TYPE_HASH_CHANGED] message definition of sensor_msgs/msg/LaserScan changed; the types: section shows "
        "how (2 field-level changes listed under this interface) (RIHS01_abababa...abab -> RIHS01_cdcdcdc...cdcd)\n"
        "      [TYPE_FIELD_RENAMED] sensor_msgs/msg/LaserScan: field `range_min` looks renamed to `range_minimum` "
        "(same type float32, same place): the bytes are the same, but everything that reads the field by name "
        "breaks\n"
        "\n"
        "RISKY (1)\n"
        "  /n\n"
        "    publisher /scan\n"
        "      [TYPE_FIELD_ADDED] sensor_msgs/msg/LaserScan: field `uint8[] quality` added at the end: peers built "
        "from the old definition ignore or reject the longer messages (depending on the middleware), and their "
        "messages lack it\n"
    )
    assert report.to_json(items)[1] == {
        "node": "/n", "kind": "publishers", "name": "/scan", "change": "type:sensor_msgs/msg/LaserScan",
        "rule": "TYPE_FIELD_RENAMED", "severity": "BREAKING", "old": "float32 range_min",
        "new": "float32 range_minimum", "message": items[1].message,
    }


def _contract_file(path: Path, nodes: dict, table: dict) -> Path:
    from pytest_rmw_introspect.model.types import render_section

    path.write_text("contract_version: 1\n" + contract_module.dump_nodes(nodes) + "\n" + render_section(table))
    return path


def test_diff_contracts_shows_the_field_level_changes(tmp_path):
    before = describe("sensor_msgs/msg/LaserScan", *ACTION_PARTS)
    old = _contract_file(tmp_path / "old.yaml", NODES, before)
    new = _contract_file(tmp_path / "new.yaml", changed_nodes(),
                         scan_with([SCAN[0], "float64 angle_min", *SCAN[2:]]))
    result = diff.diff_contracts(old, new)
    assert [(i.rule, i.old, i.new) for i in result.items] == [
        ("TYPE_HASH_CHANGED", HASH, OTHER_HASH),
        ("TYPE_FIELD_RETYPED", "float32 angle_min", "float64 angle_min"),
    ]
    assert "[TYPE_FIELD_RETYPED] sensor_msgs/msg/LaserScan: field `angle_min` float32 -> float64" in result.render_text()
    # a file without a section: nothing to compare field by field, and nothing missing (diff never requires it)
    bare = tmp_path / "bare.yaml"
    bare.write_text("contract_version: 1\n" + contract_module.dump_nodes(changed_nodes()))
    assert [i.rule for i in diff.diff_contracts(old, bare, {"include_types": True}).items] == ["TYPE_HASH_CHANGED"]
