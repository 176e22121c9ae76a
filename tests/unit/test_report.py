"""report: the text for people, JSON for machines, thresholds."""

import json

import pytest

from pytest_rmw_introspect.compare import report
from pytest_rmw_introspect.compare.drift import compare
from pytest_rmw_introspect.compare.options import ComparisonOptions as CompareOptions
from pytest_rmw_introspect.errors import OptionError
from pytest_rmw_introspect.model.vocabulary import Severity, parse_threshold

H1 = "RIHS01_" + "1" * 64
H2 = "RIHS01_" + "2" * 64


def entry(name, qos="default", type_hash=H1, type_="std_msgs/msg/String"):
    value = {"name": name, "type": type_, "type_hash": type_hash}
    if qos is not None:
        value["qos"] = qos
    return value


EXPECTED = {
    "/talker": {
        "publishers": [entry("/chatter", qos="default"), entry("/old")],
        "subscriptions": [entry("/cmd", qos="default")],
        "service_servers": [entry("/reset", qos=None, type_="std_srvs/srv/Trigger")],
    },
}
ACTUAL = {
    "/talker": {
        "publishers": [entry("/chatter", qos="sensor_data", type_hash=H2),
                       entry("/scan", qos="sensor_data", type_="sensor_msgs/msg/LaserScan")],  # not a rename of /old
        "subscriptions": [entry("/cmd", qos={"reliability": "BEST_EFFORT"})],
        "service_servers": [entry("/reset", qos=None, type_="std_srvs/srv/Trigger")],
    },
}


@pytest.fixture
def items():
    return compare(EXPECTED, ACTUAL)


def test_render_text_full_report(items):
    text = report.render_text(items, contract_path="contracts/talker.yaml",
                              threshold=Severity.RISKY,
                              accept_command="pytest tests/test_talker.py --update-golden")
    assert text.splitlines() == [
        "Interface drift against contracts/talker.yaml: 6 changes (3 breaking, 1 risky, 2 safe)",
        "Result: FAIL (fail on: risky)",
        "",
        "BREAKING (3)",
        "  /talker",
        "    publisher /chatter",
        "      [TYPE_HASH_CHANGED] message definition of std_msgs/msg/String changed "
        "(RIHS01_1111111...1111 -> RIHS01_2222222...2222)",
        "      [QOS_RELIABILITY_WEAKENED] publisher offers weaker reliability RELIABLE -> "
        "BEST_EFFORT: subscriptions requesting more no longer match",
        "    publisher /old",
        "      [PUB_REMOVED] publisher removed: subscriptions to /old (std_msgs/msg/String) no "
        "longer receive data (qos default)",
        "",
        "RISKY (1)",
        "  /talker",
        "    publisher /chatter",
        "      [QOS_DEPTH_DECREASED] depth 10 -> 5: fewer samples are queued (or replayed to late "
        "joiners); bursts may drop messages",
        "",
        "SAFE (2) - below the fail threshold (risky), not failing",
        "  /talker",
        "    publisher /scan",
        "      [PUB_ADDED] new publisher on /scan (sensor_msgs/msg/LaserScan): nothing existing depends "
        "on it (qos sensor_data)",
        "    subscription /cmd",
        "      [QOS_RELIABILITY_REQUEST_LOWERED] subscription requests less reliability RELIABLE "
        "-> BEST_EFFORT: every publisher that matched still matches",
        "",
        "To accept these changes as the new contract, run:",
        "  pytest tests/test_talker.py --update-golden",
    ]
    assert text.endswith("\n")


def test_every_item_line_carries_its_rule_id(items):
    text = report.render_text(items)
    for item in items:
        assert sum(f"[{item.rule}]" in line for line in text.splitlines()) >= 1


@pytest.mark.parametrize(
    ("threshold", "marked", "verdict"),
    [
        (Severity.SAFE, [], "Result: FAIL (fail on: any)"),
        (Severity.RISKY, ["SAFE"], "Result: FAIL (fail on: risky)"),
        (Severity.BREAKING, ["RISKY", "SAFE"], "Result: FAIL (fail on: breaking)"),
    ],
)
def test_threshold_marks_sections_below_it(items, threshold, marked, verdict):
    lines = report.render_text(items, threshold=threshold).splitlines()
    assert lines[1] == verdict
    headers = [line for line in lines if line.split(" ")[0] in ("BREAKING", "RISKY", "SAFE")]
    assert [h.split(" ")[0] for h in headers] == ["BREAKING", "RISKY", "SAFE"]
    assert [h.split(" ")[0] for h in headers if "not failing" in h] == marked


def test_passing_report_says_pass():
    safe_only = compare({"/n": {}}, {"/n": {"publishers": [entry("/new")]}})
    text = report.render_text(safe_only, threshold=Severity.RISKY)
    assert text.splitlines()[1] == "Result: pass (fail on: risky)"
    assert "SAFE (1) - below the fail threshold (risky), not failing" in text


def test_no_accept_command_no_accept_section(items):
    assert "To accept" not in report.render_text(items)


def test_title_replaces_heading(items):
    assert report.render_text(items, title="talker contract").startswith("talker contract: 6 ")


def test_empty_report():
    assert report.render_text([], contract_path="c.yaml") == "Interface drift: no drift against c.yaml.\n"
    assert report.render_text([]) == "Interface drift: no drift.\n"


def test_node_level_items_and_explicit_qos_rendering():
    items = compare({"/gone": {"publishers": [entry("/p", qos={"depth": 3})]}}, {})
    lines = report.render_text(items).splitlines()
    assert lines[3:] == [
        "BREAKING (2)",
        "  /gone",
        "    [NODE_REMOVED] node removed: anything addressing /gone by name (parameters, "
        "remappings, launch files) breaks",
        "    publisher /p",
        "      [PUB_REMOVED] publisher removed: subscriptions to /p (std_msgs/msg/String) no "
        "longer receive data (qos {history: KEEP_LAST, depth: 3, reliability: RELIABLE, "
        "durability: VOLATILE})",
    ]


# --------------------------------------------------------------------------- JSON


def test_to_json(items):
    data = report.to_json(items)
    assert json.loads(json.dumps(data)) == data  # plain JSON types only
    assert [list(d) for d in data] == [
        ["node", "kind", "name", "change", "rule", "severity", "old", "new", "message"]
    ] * len(items)
    assert data[0] == {
        "node": "/talker", "kind": "publishers", "name": "/chatter", "change": "type_hash",
        "rule": "TYPE_HASH_CHANGED", "severity": "BREAKING", "old": H1, "new": H2,
        "message": "message definition of std_msgs/msg/String changed",
    }
    assert [d["severity"] for d in data] == ["BREAKING"] * 3 + ["RISKY"] + ["SAFE"] * 2
    removed = next(d for d in data if d["change"] == "removed")
    assert removed["old"] == entry("/old") and removed["new"] is None


def test_to_json_empty():
    assert report.to_json([]) == []


# --------------------------------------------------------------------------- thresholds


@pytest.mark.parametrize(
    ("text", "severity"),
    [("any", Severity.SAFE), ("ANY", Severity.SAFE), ("risky", Severity.RISKY),
     ("Risky", Severity.RISKY), ("breaking", Severity.BREAKING), (" BREAKING ", Severity.BREAKING)],
)
def test_parse_threshold(text, severity):
    assert parse_threshold(text) is severity


@pytest.mark.parametrize("text", ["safe", "all", "", "warning", None, 1])
def test_parse_threshold_rejects_other_values(text):
    with pytest.raises(OptionError, match="invalid fail threshold .*expected one of any, risky, "
                                         "breaking"):
        parse_threshold(text)


@pytest.mark.parametrize(
    ("severities", "threshold", "expected"),
    [
        ([], Severity.SAFE, False),
        ([Severity.SAFE], Severity.SAFE, True),
        ([Severity.SAFE], Severity.RISKY, False),
        ([Severity.SAFE, Severity.RISKY], Severity.RISKY, True),
        ([Severity.RISKY], Severity.BREAKING, False),
        ([Severity.BREAKING], Severity.BREAKING, True),
    ],
)
def test_fails(severities, threshold, expected):
    class Item:
        def __init__(self, severity):
            self.severity = severity

    assert report.fails([Item(s) for s in severities], threshold) is expected


def test_fails_with_real_items(items):
    assert report.fails(items, Severity.BREAKING)
    only_safe = compare(EXPECTED, ACTUAL, CompareOptions(ignore_qos=True, ignore_type_hash=True,
                                                         allow_extra=True))
    assert [i.rule for i in only_safe] == ["PUB_REMOVED"]
    assert report.fails(only_safe, Severity.BREAKING)


# --------------------------------------------------------------------------- parameters and lifecycle

PARAM_OLD = {"/cam": {"lifecycle": "active", "parameters": [
    {"name": "rate", "type": "double", "default_value": 10.0},
    {"name": "frame", "type": "string", "default_value": "cam", "read_only": True},
    {"name": "gain", "type": "double", "default_value": float("nan")}]}}
PARAM_NEW = {"/cam": {"lifecycle": "inactive", "parameters": [
    {"name": "rate", "type": "integer", "default_value": 10},
    {"name": "gain", "type": "double", "default_value": float("inf")},
    {"name": "exposure", "type": "double", "default_value": 0.5, "floating_point_range": {
        "from_value": 0.0, "to_value": 1.0, "step": 0.0}}]}}


def test_parameter_and_lifecycle_drift_in_the_text_report():
    text = report.render_text(compare(PARAM_OLD, PARAM_NEW), contract_path="cam.interfaces.yaml")
    assert "    [LIFECYCLE_STATE_CHANGED] the contract describes /cam active, the capture reached inactive" in text
    assert "    parameter frame\n      [PARAM_REMOVED] parameter removed: launch files, parameter files and -p " \
           "overrides that set frame are silently ignored, and `ros2 param set` of it fails (was: string, " \
           "default 'cam', read only)" in text
    assert "    parameter rate\n      [PARAM_TYPE_CHANGED] type changed from double to integer" in text
    assert "      [PARAM_DEFAULT_CHANGED] default value .nan -> .inf" in text
    assert "      [PARAM_ADDED] new parameter exposure (double, default 0.5): nothing sets it yet" in text
    assert text.index("BREAKING (2)") < text.index("RISKY (2)") < text.index("SAFE (1)")


def test_parameter_values_are_strict_json():
    data = report.to_json(compare(PARAM_OLD, PARAM_NEW))
    text = json.dumps(data, allow_nan=False)  # no NaN / Infinity tokens
    gain = next(i for i in data if i["name"] == "gain")
    assert (gain["old"], gain["new"]) == ("nan", "inf")
    assert json.loads(text)[0]["severity"] == "BREAKING"
