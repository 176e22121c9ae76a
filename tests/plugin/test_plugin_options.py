"""Comparison options: parsing from every source and precedence (fast, no ROS)."""

from __future__ import annotations

import pytest

from pytest_rmw_introspect.compare import drift
from pytest_rmw_introspect.compare.options import (
    ComparisonOptions,
    OptionError,
    parse_layer,
    resolve,
)
from pytest_rmw_introspect.model.vocabulary import Severity


def test_defaults():
    opts = resolve()
    assert opts == ComparisonOptions()
    assert opts.fail_on == "any" and opts.threshold() is Severity.SAFE
    assert opts.ignore_qos == frozenset() and not opts.ignores_all_qos


def test_later_layers_win_and_unset_values_do_not_override():
    opts = resolve(
        ({"fail_on": "breaking", "ignore_type_hash": True, "allow_extra": True}, "ini file"),
        ({"fail_on": "risky", "allow_extra": None}, "command line"),
        ({"ignore_type_hash": False}, "contract"),
        ({"fail_on": "any"}, "marker"),
    )
    assert opts == ComparisonOptions(ignore_type_hash=False, allow_extra=True, fail_on="any")


@pytest.mark.parametrize("value, expected", [
    (True, True), (False, frozenset()), ("all", True), ("true", True), ("", frozenset()), ("none", frozenset()),
    ("depth,history", frozenset({"depth", "history"})), ("depth history", frozenset({"depth", "history"})),
    (["depth"], frozenset({"depth"})),
])
def test_ignore_qos_spellings(value, expected):
    assert resolve(({"ignore_qos": value}, "x")).ignore_qos == expected


@pytest.mark.parametrize("values, message", [
    ({"ignore_qos": ["colour"]}, "marker: `ignore_qos` names unknown QoS field(s) colour"),
    ({"ignore_qos": 3}, "marker: `ignore_qos` must be true/false or a list of QoS fields"),
    ({"fail_on": "sometimes"}, "marker: `fail_on` must be one of any, risky, breaking, got 'sometimes'"),
    ({"allow_extra": "maybe"}, "marker: `allow_extra` must be true or false, got 'maybe'"),
    ({"strict": True}, "marker: unknown option 'strict'"),
])
def test_bad_values_name_their_source(values, message):
    with pytest.raises(OptionError) as info:
        parse_layer(values, "marker")
    assert message in str(info.value)


def test_string_booleans_from_ini_files():
    assert parse_layer({"allow_extra": "yes", "include_infrastructure": "0"}, "ini") == {
        "allow_extra": True, "include_infrastructure": False}


def test_drift_compare_takes_the_comparison_options_as_they_are():
    opts = ComparisonOptions(ignore_type_hash=True, ignore_qos=True, allow_extra=True, fail_on="risky")
    pub = {"name": "/chatter", "type": "std_msgs/msg/String", "type_hash": "RIHS01_aa", "qos": {"depth": 10}}
    changed = dict(pub, type_hash="RIHS01_bb", qos={"depth": 1})
    extra = {"name": "/extra", "type": "std_msgs/msg/String"}
    expected = {"/n": {"publishers": [pub]}}
    actual = {"/n": {"publishers": [changed, extra]}}
    assert drift.compare(expected, actual, opts) == []
    assert {i.rule for i in drift.compare(expected, actual, ComparisonOptions())} >= {"TYPE_HASH_CHANGED", "PUB_ADDED"}
    assert opts.threshold() is Severity.RISKY and opts.ignores_all_qos
