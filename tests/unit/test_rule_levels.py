"""The comparison option `rules` (issue 49): a project's level of each rule, by id or fnmatch
pattern, merged across layers, applied to drift items and system problems alike, said in the
report; bad input is an error naming where it was set and the closest known id. And the one list
of every rule id (`rule_levels.known`) holds every rule id the code uses."""

from __future__ import annotations

import ast
import json
import re
from pathlib import Path

import pytest
from sample_contracts import REPORT_CAPTURED as CAPTURED
from sample_contracts import REPORT_TALKER as TALKER

from pytest_rmw_introspect.compare import ci_report, report, rule_levels, sarif
from pytest_rmw_introspect.compare.compatibility import CompatItem, ContractEndpoint
from pytest_rmw_introspect.compare.drift import compare
from pytest_rmw_introspect.compare.options import ComparisonOptions, resolve
from pytest_rmw_introspect.errors import OptionError
from pytest_rmw_introspect.model import qos
from pytest_rmw_introspect.model.contract import loads
from pytest_rmw_introspect.model.vocabulary import Severity

PACKAGE = Path(rule_levels.__file__).parents[1]
WHERE = "contracts/x.yaml: options"


def levels(rules, source: str = WHERE) -> ComparisonOptions:
    return resolve(({"rules": rules}, source))


def test_exact_ids_win_over_patterns_and_longer_patterns_over_shorter():
    entries = levels({"QOS_*": "off", "QOS_DEPTH_*": "note", "QOS_DEPTH_DECREASED": "breaking"}).rules
    assert rule_levels.level_of("QOS_DEPTH_DECREASED", entries).level == "breaking"
    assert rule_levels.level_of("QOS_DEPTH_INCREASED", entries).level == "note"
    assert rule_levels.level_of("QOS_HISTORY_CHANGED", entries).level == "off"
    assert rule_levels.level_of("PUB_REMOVED", entries) is None


def test_layers_merge_key_by_key_the_stronger_winning():
    merged = resolve(({"rules": ["SUB_ADDED=note", "PUB_ADDED=risky"]}, "ini file"),
                     ({"rules": {"SUB_ADDED": "breaking"}}, WHERE)).rules
    assert {(e.key, e.level, e.source) for e in merged} == {("SUB_ADDED", "breaking", WHERE),
                                                           ("PUB_ADDED", "risky", "ini file")}
    # an ini key is one string of RULE=LEVEL words; YAML reads a bare `off` as false
    assert [(e.key, e.level) for e in levels("SUB_ADDED=off, PUB_ADDED=note").rules] == [
        ("SUB_ADDED", "off"), ("PUB_ADDED", "note")]
    assert [(e.key, e.level) for e in levels({"SUB_ADDED": False}).rules] == [("SUB_ADDED", "off")]


@pytest.mark.parametrize("rules, message", [
    ({"SUB_ADDD": "off"}, f"{WHERE}: `rules`: unknown rule id SUB_ADDD; the closest known rule id is SUB_ADDED "
                          "(the rule ids are in docs/drift-rules.md)"),
    ({"REMAP_UNUSD": "note"}, f"{WHERE}: `rules`: unknown rule id REMAP_UNUSD; the closest known rule id is "
                              "REMAP_UNUSED"),
    ({"SUB_ADDED": "loud"}, f"{WHERE}: `rules`: SUB_ADDED: unknown level 'loud'; the levels are off, note, safe, "
                            "risky, breaking"),
    ({"QXS_*": "off"}, f"{WHERE}: `rules`: the pattern QXS_* matches no rule id; the closest family of rule ids is "
                       "QOS_*"),
    (["SUB_ADDED"], f"{WHERE}: `rules`: 'SUB_ADDED' is not RULE=LEVEL"),
    (5, f"{WHERE}: `rules` must be a mapping of rule ids (or fnmatch patterns) to one of off, note, safe, risky, "
        "breaking, got 5"),
    ({"QOS_*_WEAKENED": "off", "QOS_*_CHANGED": "risky", "QOS_HISTORY_*": "safe"},
     f"{WHERE}: `rules`: QOS_*_CHANGED: risky and QOS_HISTORY_*: safe are equally specific and both match "
     "QOS_HISTORY_CHANGED"),
])
def test_bad_rules_are_errors_that_say_where_and_what_is_close(rules, message):
    with pytest.raises(OptionError) as raised:
        levels(rules)
    assert str(raised.value).startswith(message), str(raised.value)


def test_a_command_line_flag_names_the_command_line():
    with pytest.raises(OptionError, match=r"^command line: `rules`: unknown rule id PUB_REMOVD; the closest known "
                                          r"rule id is PUB_REMOVED"):
        levels(["PUB_REMOVD=off"], "command line")


def drift_items():
    return compare(loads(TALKER).nodes, CAPTURED)


def test_the_levels_apply_to_drift_and_are_said_in_every_format():
    items = drift_items()
    rules = sorted({i.rule for i in items})
    assert "QOS_DEPTH_DECREASED" in rules, rules
    entries = levels({"QOS_DEPTH_DECREASED": "note", "PUB_*": "off"}).rules
    applied = rule_levels.apply(items, entries)
    assert applied.off == sum(1 for i in items if i.rule.startswith("PUB_")) > 0
    [depth] = [i for i in applied.items if i.rule == "QOS_DEPTH_DECREASED"]
    assert depth.severity is Severity.NOTE and depth.level_set_by == f"set by rules: in {WHERE}"
    untouched = [i for i in applied.items if i.rule != "QOS_DEPTH_DECREASED"]
    assert all(i.level_set_by is None for i in untouched)
    text = report.render_text(applied.items, threshold=Severity.SAFE)
    assert "(NOTE, set by rules: in contracts/x.yaml: options)" in text
    [as_json] = [i for i in report.to_json(applied.items) if i["rule"] == "QOS_DEPTH_DECREASED"]
    assert as_json["severity"] == "NOTE" and as_json["level_set_by"] == f"set by rules: in {WHERE}"
    outcome = ci_report.ContractOutcome("contracts/x.yaml", applied.items, Severity.SAFE, ["/talker"])
    assert "(NOTE, set by rules: in contracts/x.yaml: options)" in ci_report.drift_markdown([outcome])
    assert "title=QOS_DEPTH_DECREASED (NOTE set by the project)" in ci_report.drift_github([outcome])
    results = sarif.drift_log([outcome], tool_version="0")["runs"][0]["results"]
    [result] = [r for r in results if r["ruleId"] == "QOS_DEPTH_DECREASED"]
    assert result["level"] == "note" and result["properties"]["levelSetBy"] == f"set by rules: in {WHERE}"
    # a pattern that decided is named
    leveled = rule_levels.apply(items, levels({"QOS_DEPTH_*": "breaking"}).rules).items
    assert {i.level_set_by for i in leveled if i.rule == "QOS_DEPTH_DECREASED"} == {
        f"set by rules `QOS_DEPTH_*`: in {WHERE}"}


def test_the_levels_apply_to_system_problems():
    problem = CompatItem("REMAP_UNUSED", Severity.NOTE, "a:=b", ContractEndpoint("p", "/n", "node"), None, "dead")
    applied = rule_levels.apply([problem], levels({"REMAP_*": "breaking", "REMAP_NEAR_MISS": "off"}).rules)
    [raised] = applied.items
    assert raised.severity is Severity.BREAKING and report.fails(applied.items, Severity.BREAKING)
    assert json.loads(json.dumps(report.compat_to_json(applied.items)))[0]["level_set_by"] == (
        f"set by rules `REMAP_*`: in {WHERE}")
    assert "[REMAP_UNUSED] node of /n (p): dead (BREAKING, set by rules `REMAP_*`: in contracts/x.yaml: options)" in (
        report.render_compat_text(applied.items))
    assert rule_levels.turned_off_text(1) == "1 finding turned off by the project's rules"
    assert rule_levels.turned_off_text(3) == "3 findings turned off by the project's rules"


#: upper-case words the code uses that are not rule ids
_NOT_RULES = re.compile(r"^(RMW_|ROS_|LD_|XDG_|AMENT_|OMP_|OPENBLAS_|GOTO_)|^(ACTION|SERVICE)_(CLIENT|SERVER)$"
                        r"|^LEASE_DURATION$")


def test_every_rule_id_the_code_uses_is_in_the_one_list():
    """A string literal of the package that looks like a rule id (upper-case words joined by `_`) is
    one of `rule_levels.known()` (or of SARIF's own rules about contracts that could not be checked),
    unless it is a QoS value, an environment variable or a list label."""
    known = set(rule_levels.known()) | set(sarif.TOOL_RULES)
    found = set()
    for path in PACKAGE.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Constant) and isinstance(node.value, str) \
                    and re.fullmatch(r"[A-Z][A-Z0-9]*(_[A-Z0-9]+)+", node.value):
                found.add(node.value)
    # QoS values: the contract's enums, and rmw's deprecated MANUAL_BY_NODE liveliness
    qos_words = {member.value for values in qos.ENUM_FIELDS.values() for member in values} | {"MANUAL_BY_NODE"}
    missing = sorted(w for w in found - known - qos_words if not _NOT_RULES.search(w))
    assert missing == [], f"rule ids used in the code but not in rule_levels.known(): {missing}"
    assert rule_levels.known()["REMAP_NEAR_MISS"] is Severity.BREAKING
    assert rule_levels.known()["REMAP_UNUSED"] is Severity.NOTE
