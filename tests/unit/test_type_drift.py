"""Type descriptions in comparisons: the contract's `types:` section against the capture's
table (include_types), and what --update-golden writes. Tables come from the real message
packages of the venv (type_tables.py)."""

from __future__ import annotations

from pathlib import Path

from type_tables import describe

from pytest_rmw_introspect.check import pipeline
from pytest_rmw_introspect.compare.drift import compare
from pytest_rmw_introspect.compare.options import ComparisonOptions, parse_layer
from pytest_rmw_introspect.model import contract as contract_module
from pytest_rmw_introspect.model.capture import Capture
from pytest_rmw_introspect.model.types import to_contract

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
