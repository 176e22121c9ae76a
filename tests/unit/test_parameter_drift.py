"""Parameter and lifecycle drift (compare/parameter_drift.py through drift.compare): one row per
change with the rule and severity it must get, the options that suppress them, ranges, and what
a golden keeps of ignored parameters."""

from __future__ import annotations

import pytest

from pytest_rmw_introspect.compare import parameter_drift
from pytest_rmw_introspect.compare.drift import compare
from pytest_rmw_introspect.compare.options import ComparisonOptions, parse_layer
from pytest_rmw_introspect.errors import OptionError
from pytest_rmw_introspect.model.parameters import ParameterRange
from pytest_rmw_introspect.model.vocabulary import Severity

BREAKING, RISKY, SAFE = Severity.BREAKING, Severity.RISKY, Severity.SAFE
EMPTY_LISTS = {k: [] for k in ("publishers", "subscriptions", "service_servers", "service_clients",
                               "action_servers", "action_clients")}


def node(*params, lifecycle=None, **extra):
    out = dict(EMPTY_LISTS, parameters=[dict(p) for p in params], **extra)
    if lifecycle is not None:
        out["lifecycle"] = lifecycle
    return out


def p(name="rate", type_="double", default=10.0, **fields):
    entry = {"name": name, "type": type_}
    if default is not ...:
        entry["default_value"] = default
    entry.update(fields)
    return entry


RANGE = {"from_value": 0, "to_value": 100, "step": 2}
FRANGE = {"from_value": 0.0, "to_value": 1.0, "step": 0.0}

#: (old parameter, new parameter, change, rule, severity)
ROWS = [
    (p(), p(type_="integer", default=10), "type", "PARAM_TYPE_CHANGED", BREAKING),
    (p(dynamic_typing=True), p(type_="string", default="10", dynamic_typing=True), "default_value",
     "PARAM_DEFAULT_CHANGED", RISKY),
    (p(), p(default=5.0), "default_value", "PARAM_DEFAULT_CHANGED", RISKY),
    (p(default=float("nan")), p(default=0.0), "default_value", "PARAM_DEFAULT_CHANGED", RISKY),
    (p("ids", "integer_array", [1, 2]), p("ids", "integer_array", [1, 2, 3]), "default_value",
     "PARAM_DEFAULT_CHANGED", RISKY),
    (p(), p(read_only=True), "read_only", "PARAM_READ_ONLY_ADDED", BREAKING),
    (p(read_only=True), p(), "read_only", "PARAM_READ_ONLY_REMOVED", SAFE),
    (p(), p(dynamic_typing=True), "dynamic_typing", "PARAM_DYNAMIC_TYPING_ADDED", SAFE),
    (p(dynamic_typing=True), p(), "dynamic_typing", "PARAM_DYNAMIC_TYPING_REMOVED", RISKY),
    (p("n", "integer", 4), p("n", "integer", 4, integer_range=RANGE), "integer_range", "PARAM_RANGE_NARROWED", RISKY),
    (p("n", "integer", 4, integer_range=RANGE), p("n", "integer", 4), "integer_range", "PARAM_RANGE_WIDENED", SAFE),
    (p("n", "integer", 4, integer_range=RANGE), p("n", "integer", 4, integer_range=dict(RANGE, to_value=50)),
     "integer_range", "PARAM_RANGE_NARROWED", RISKY),
    (p("n", "integer", 4, integer_range=RANGE), p("n", "integer", 4, integer_range=dict(RANGE, to_value=200)),
     "integer_range", "PARAM_RANGE_WIDENED", SAFE),
    (p("n", "integer", 4, integer_range=RANGE), p("n", "integer", 4, integer_range=dict(RANGE, step=1)),
     "integer_range", "PARAM_RANGE_WIDENED", SAFE),
    (p("n", "integer", 4, integer_range=RANGE), p("n", "integer", 4, integer_range=dict(RANGE, step=4)),
     "integer_range", "PARAM_RANGE_NARROWED", RISKY),
    (p("n", "integer", 4, integer_range=RANGE), p("n", "integer", 4, integer_range=dict(RANGE, from_value=1)),
     "integer_range", "PARAM_RANGE_NARROWED", RISKY),  # same bounds width, shifted grid
    (p(floating_point_range=FRANGE), p(floating_point_range=dict(FRANGE, to_value=2.0)),
     "floating_point_range", "PARAM_RANGE_WIDENED", SAFE),
    (p(floating_point_range=FRANGE), p(floating_point_range=dict(FRANGE, step=0.1)),
     "floating_point_range", "PARAM_RANGE_NARROWED", RISKY),
    (p(floating_point_range=dict(FRANGE, step=0.2)), p(floating_point_range=dict(FRANGE, step=0.1)),
     "floating_point_range", "PARAM_RANGE_WIDENED", SAFE),
    (p(floating_point_range=FRANGE), p(floating_point_range=dict(FRANGE, from_value=-float("inf"))),
     "floating_point_range", "PARAM_RANGE_WIDENED", SAFE),
    (p(), p(description="Hz"), "description", "PARAM_DESCRIPTION_CHANGED", SAFE),
    (p(additional_constraints="even"), p(), "additional_constraints", "PARAM_CONSTRAINTS_CHANGED", SAFE),
    (p(), p(declared_in="configure"), "declared_in", "PARAM_DECLARED_LATER", RISKY),
    (p(declared_in="configure"), p(declared_in="activate"), "declared_in", "PARAM_DECLARED_LATER", RISKY),
    (p(declared_in="activate"), p(), "declared_in", "PARAM_DECLARED_EARLIER", SAFE),
]


def only(items):
    assert len(items) == 1, items
    return items[0]


@pytest.mark.parametrize(("old", "new", "change", "rule", "severity"), ROWS,
                         ids=[f"{r[3]}-{i}" for i, r in enumerate(ROWS)])
def test_parameter_rules(old, new, change, rule, severity):
    item = only(compare({"/n": node(old)}, {"/n": node(new)}))
    assert (item.kind, item.name, item.change, item.rule, item.severity) == ("parameters", old["name"], change, rule,
                                                                             severity)
    assert item.node == "/n" and item.message
    assert old["name"] in item.message or item.change != "added"


def test_a_megabyte_value_changed_in_one_byte_is_reported_in_one_short_line():
    """Values are cut with a digest: the report of a 1 MB string parameter used to be a 2 MB line
    (a 50 MB value, 100 MB of output)."""
    from pytest_rmw_introspect.compare.report import render_text

    big = "a" * 1_000_000
    changed = big[:500_000] + "b" + big[500_001:]
    item = only(compare({"/n": node(p("blob", "string", big))}, {"/n": node(p("blob", "string", changed))}))
    assert item.rule == "PARAM_DEFAULT_CHANGED" and item.new == changed  # the data stays whole
    assert len(item.message) < 500, item.message[:1000]
    assert "(1,000,000 characters, sha256 " in item.message
    old_digest, new_digest = (part.split(")")[0] for part in item.message.split("sha256 ")[1:])
    assert old_digest != new_digest
    assert "they differ from character 500,001 on" in item.message
    report = render_text([item])
    assert max(len(line) for line in report.splitlines()) < 500 and len(report) < 1000


def test_long_descriptions_and_list_values_are_cut_too():
    old = p("s", "string_array", ["x" * 5000] * 20, description="d" * 5000)
    new = p("s", "string_array", ["y" * 5000] * 20, description="e" * 5000)
    items = compare({"/n": node(old)}, {"/n": node(new)})
    assert {i.rule for i in items} == {"PARAM_DEFAULT_CHANGED", "PARAM_DESCRIPTION_CHANGED"}
    assert all(len(i.message) < 500 for i in items), [i.message[:2000] for i in items]
    assert "(20 items, sha256 " in next(i.message for i in items if i.rule == "PARAM_DEFAULT_CHANGED")


def test_type_change_implies_value_and_range_changes():
    old = p("n", "integer", 4, integer_range=RANGE)
    new = p("n", "double", 4.5, floating_point_range=FRANGE)
    assert [i.rule for i in compare({"/n": node(old)}, {"/n": node(new)})] == ["PARAM_TYPE_CHANGED"]


def test_a_double_written_as_an_integer_is_the_same_value():
    assert compare({"/n": node(p(default=10))}, {"/n": node(p(default=10.0))}) == []


@pytest.mark.parametrize(("old", "new", "rule", "severity"), [
    ([p()], [], "PARAM_REMOVED", BREAKING),
    ([], [p()], "PARAM_ADDED", SAFE),
    ([], [p("frame", "string", None)], "PARAM_ADDED_WITHOUT_VALUE", RISKY),
    ([], [p("frame", "string", ...)], "PARAM_ADDED", SAFE),  # value not stated: not judged as missing
    ([p("rate")], [p("rate_hz")], "PARAM_RENAMED", BREAKING),
])
def test_parameter_presence(old, new, rule, severity):
    item = only(compare({"/n": node(*old)}, {"/n": node(*new)}))
    assert (item.rule, item.severity) == (rule, severity)
    assert item.change == {"PARAM_REMOVED": "removed", "PARAM_RENAMED": "renamed"}.get(rule, "added")


def test_no_rename_across_types_or_when_ambiguous():
    items = compare({"/n": node(p("a"), p("b"))}, {"/n": node(p("c"), p("d"))})
    assert sorted(i.rule for i in items) == ["PARAM_ADDED", "PARAM_ADDED", "PARAM_REMOVED", "PARAM_REMOVED"]
    items = compare({"/n": node(p("a"))}, {"/n": node(p("b", "integer", 1))})
    assert sorted(i.rule for i in items) == ["PARAM_ADDED", "PARAM_REMOVED"]


def test_parameters_of_added_and_removed_nodes_go_with_the_node():
    assert [i.rule for i in compare({}, {"/n": node(p("frame", "string", None), lifecycle="active")})] == ["NODE_ADDED"]
    assert [i.rule for i in compare({"/n": node(p())}, {})] == ["NODE_REMOVED"]


def test_parameters_not_stated_are_not_compared():
    without = dict(EMPTY_LISTS)
    assert compare({"/n": without}, {"/n": node(p())}) == []
    assert compare({"/n": node(p(default=...))}, {"/n": node(p(default=3.0))}) == []
    assert compare({"/n": node(p(default=3.0))}, {"/n": node(p(default=...))}) == []


def test_parameters_stated_but_not_read_are_reported():
    item = only(compare({"/n": node(p())}, {"/n": dict(EMPTY_LISTS)}))
    assert (item.kind, item.name, item.change, item.rule, item.severity) == ("node", "/n", "parameters",
                                                                             "PARAMS_NOT_READ", RISKY)
    assert item.old == ["rate"] and "see the notes" in item.message
    assert compare({"/n": node()}, {"/n": dict(EMPTY_LISTS)}) == []  # nothing listed, nothing missing
    assert compare({"/n": node(p())}, {"/n": dict(EMPTY_LISTS)}, ComparisonOptions(ignore_parameters=True)) == []


@pytest.mark.parametrize(("options", "remaining"), [
    (ComparisonOptions(), {"PARAM_REMOVED", "PARAM_ADDED", "PARAM_DEFAULT_CHANGED", "PARAM_READ_ONLY_ADDED"}),
    (ComparisonOptions(ignore_parameters=True), set()),
    (ComparisonOptions(ignore_parameters=frozenset({"old*"})), {"PARAM_ADDED", "PARAM_DEFAULT_CHANGED",
                                                                "PARAM_READ_ONLY_ADDED"}),
    (ComparisonOptions(ignore_parameter_values=True), {"PARAM_REMOVED", "PARAM_ADDED", "PARAM_READ_ONLY_ADDED"}),
    (ComparisonOptions(ignore_parameter_values=frozenset({"ra?e"})), {"PARAM_REMOVED", "PARAM_ADDED",
                                                                       "PARAM_READ_ONLY_ADDED"}),
    (ComparisonOptions(ignore_parameter_values=frozenset({"other"})), {"PARAM_REMOVED", "PARAM_ADDED",
                                                                        "PARAM_DEFAULT_CHANGED",
                                                                        "PARAM_READ_ONLY_ADDED"}),
    (ComparisonOptions(allow_extra=True), {"PARAM_REMOVED", "PARAM_DEFAULT_CHANGED", "PARAM_READ_ONLY_ADDED"}),
])
def test_options(options, remaining):
    old = node(p("old_one", "bool", True), p(default=1.0))
    new = node(p("new_one", "string", "x"), p(default=2.0, read_only=True))
    assert {i.rule for i in compare({"/n": old}, {"/n": new}, options)} == remaining


# ---------------------------------------------------------------------------- lifecycle


@pytest.mark.parametrize(("old", "new", "rule", "severity"), [
    (node(), node(lifecycle="active"), "LIFECYCLE_ADDED", BREAKING),
    (node(lifecycle="active"), node(), "LIFECYCLE_REMOVED", BREAKING),
    (node(lifecycle="active"), node(lifecycle="inactive"), "LIFECYCLE_STATE_CHANGED", RISKY),
    (dict(EMPTY_LISTS, lifecycle="active"), dict(EMPTY_LISTS, lifecycle="unconfigured"),
     "LIFECYCLE_STATE_CHANGED", RISKY),
])
def test_lifecycle_rules(old, new, rule, severity):
    item = only(compare({"/n": old}, {"/n": new}))
    assert (item.kind, item.name, item.change, item.rule, item.severity) == ("node", "/n", "lifecycle", rule, severity)
    assert (item.old, item.new) == (old.get("lifecycle"), new.get("lifecycle"))


@pytest.mark.parametrize(("old", "new"), [
    (dict(EMPTY_LISTS), dict(EMPTY_LISTS, lifecycle="active")),  # the contract says nothing either way
    (dict(EMPTY_LISTS, lifecycle="active"), dict(EMPTY_LISTS)),  # a capture that cannot say (a C node)
    (node(lifecycle="unknown"), node(lifecycle="active")),
    (node(lifecycle="active"), node(lifecycle="unknown")),
    (node(lifecycle="active"), node(lifecycle="active")),
])
def test_lifecycle_not_judged(old, new):
    assert compare({"/n": old}, {"/n": new}) == []


def test_items_sort_lifecycle_before_interfaces_and_parameters_after():
    old = {"/n": dict(node(p()), lifecycle="active",
                      publishers=[{"name": "/a", "type": "std_msgs/msg/String"}])}
    new = {"/n": dict(node(p(default=2.0)), lifecycle="inactive")}
    assert [(i.kind, i.rule) for i in compare(old, new)] == [
        ("publishers", "PUB_REMOVED"), ("node", "LIFECYCLE_STATE_CHANGED"), ("parameters", "PARAM_DEFAULT_CHANGED")]


# ---------------------------------------------------------------------------- ranges


@pytest.mark.parametrize(("outer", "inner", "contained"), [
    ((0, 100, 0), (10, 20, 0), True),
    ((0, 100, 2), (10, 20, 2), True),
    ((0, 100, 2), (10, 20, 4), True),
    ((0, 100, 2), (11, 21, 2), False),
    ((0, 100, 2), (10, 20, 0), False),
    ((0, 100, 2), (10, 10, 0), True),  # a single value on the grid
    ((0, 100, 2), (0, 100, 200), True),  # a step beyond the width: only the bounds
    ((0, 10, 3), (0, 10, 0), False),
    ((0, 10, 3), (10, 10, 0), True),  # to_value is always valid
    ((0.0, 1.0, 0.0), (0.0, 1.0, 0.1), True),
    ((0.0, 1.0, 0.1), (0.0, 1.0, 0.2), True),
    ((0.0, 1.0, 0.2), (0.0, 1.0, 0.1), False),
    ((0.0, 1.0, 0.0), (-0.5, 1.0, 0.0), False),
    ((float("nan"), 1.0, 0.0), (0.0, 1.0, 0.0), False),
])
def test_range_containment(outer, inner, contained):
    assert parameter_drift.contains(ParameterRange(*outer), ParameterRange(*inner)) is contained


# ---------------------------------------------------------------------------- options and goldens


@pytest.mark.parametrize(("value", "parsed"), [
    (True, True), ("all", True), ("true", True), (False, frozenset()), ("none", frozenset()), ("", frozenset()),
    ("qos_overrides.*, frame_id", frozenset({"qos_overrides.*", "frame_id"})),
    (["a.*", "b"], frozenset({"a.*", "b"})),
])
def test_pattern_options_parse(value, parsed):
    for key in ("ignore_parameters", "ignore_parameter_values"):
        assert parse_layer({key: value}, "test")[key] == parsed


@pytest.mark.parametrize("value", [3, ["a", ""], [1], {"a": 1}])
def test_bad_pattern_options_name_the_source(value):
    with pytest.raises(OptionError, match="contracts/n.yaml: options: `ignore_parameters` must be true/false or a list"):
        parse_layer({"ignore_parameters": value}, "contracts/n.yaml: options")


def test_golden_keeps_ignored_parameters_as_the_contract_has_them():
    contract = {"/n": node(p("qos_overrides./x.depth", "integer", 5), p(default=1.0), p("gain", default=0.5))}
    captured = {"/n": node(p("qos_overrides./x.depth", "integer", 7), p(default=2.0), p("gain", default=0.7),
                           p("qos_overrides./y.depth", "integer", 1)),
                "/new": node(p(default=3.0))}
    options = ComparisonOptions(ignore_parameters=frozenset({"qos_overrides.*"}),
                                ignore_parameter_values=frozenset({"rate"}))
    golden = parameter_drift.keep_ignored(contract, captured, options)
    assert golden["/n"]["parameters"] == [p("gain", default=0.7), p("qos_overrides./x.depth", "integer", 5),
                                          p(default=1.0)]
    assert golden["/new"]["parameters"] == [p(default=...)]  # a new node: an ignored value is not written
    everything = parameter_drift.keep_ignored(contract, captured, ComparisonOptions(ignore_parameters=True))
    assert everything["/n"]["parameters"] == contract["/n"]["parameters"]
    assert "parameters" not in everything["/new"]


def test_golden_keeps_parameters_the_capture_could_not_read():
    contract = {"/n": node(p())}
    assert parameter_drift.keep_ignored(contract, {"/n": dict(EMPTY_LISTS)}, ComparisonOptions()) == contract


def test_gains_lists_what_an_update_adds():
    assert parameter_drift.gains({"/n": dict(EMPTY_LISTS), "/m": node()},
                                 {"/n": node(lifecycle="active"), "/m": node(), "/new": node()}) == [
        "/n lifecycle", "/n parameters"]


TESTED_RULES = {r[3] for r in ROWS} | {"PARAM_REMOVED", "PARAM_ADDED", "PARAM_ADDED_WITHOUT_VALUE", "PARAM_RENAMED",
                                       "PARAM_ADDED_SUSPICIOUS",
                                       "PARAMS_NOT_READ", "LIFECYCLE_ADDED", "LIFECYCLE_REMOVED",
                                       "LIFECYCLE_STATE_CHANGED"}


def test_every_parameter_rule_has_a_test():
    assert TESTED_RULES == set(parameter_drift.RULES)


@pytest.mark.parametrize("name, others, suspicious", [
    ("rte", ["rate", "frame_id"], "is 1 character(s) from rate: it looks like a typo of it"),
    ("frame_di", ["frame_id"], "is 1 character(s) from frame_id: it looks like a typo of it"),
    ("max range", ["rate"], "has a name that is no parameter name a node would declare"),
    ("a..b", [], "has a name that is no parameter name a node would declare"),
    ("gain_y", ["gain_x"], None),  # an axis apart
    ("joint2", ["joint1"], None),  # an index apart
    ("qos_overrides./chatter.publisher.depth", ["rate"], None),
    ("timeout", ["rate"], None),
    ("kd", ["kp"], None),  # too short to tell
])
def test_a_new_parameter_that_looks_like_a_typo_or_garbage_is_not_safe(name, others, suspicious):
    nodes_old = {"/n": {"parameters": [{"name": o, "type": "double", "default_value": 1.0} for o in others]}}
    nodes_new = {"/n": {"parameters": [*nodes_old["/n"]["parameters"],
                                       {"name": name, "type": "double", "default_value": 1.0}]}}
    (item,) = compare(nodes_old, nodes_new)
    if suspicious is None:
        assert (item.rule, item.severity) == ("PARAM_ADDED", Severity.SAFE)
    else:
        assert (item.rule, item.severity) == ("PARAM_ADDED_SUSPICIOUS", Severity.RISKY)
        assert suspicious in item.message
