"""compatibility.check_compatibility: pairs across contracts, missing peers, rendering."""

import json

import pytest

from pytest_rmw_introspect.compare import compatibility, report
from pytest_rmw_introspect.compare.compatibility import ContractEndpoint, check_compatibility
from pytest_rmw_introspect.model.vocabulary import Severity

H1 = "RIHS01_" + "1" * 64
H2 = "RIHS01_" + "2" * 64


def entry(name="/chatter", type_="std_msgs/msg/String", type_hash=H1, qos="default"):
    value = {"name": name, "type": type_, "type_hash": type_hash}
    if qos is not None:
        value["qos"] = qos
    return value


def system(provider_kind, provider_entry, requester_kind, requester_entry):
    return {
        "a.yaml": {"/talker": {provider_kind: [provider_entry]}},
        "b.yaml": {"/listener": {requester_kind: [requester_entry]}},
    }


PUB = ContractEndpoint("a.yaml", "/talker", "publishers")
SUB = ContractEndpoint("b.yaml", "/listener", "subscriptions")


# (publisher entry, subscription entry, rules expected)
TOPIC_ROWS = [
    ("compatible", entry(), entry(), []),
    ("profile-names", entry(qos="map"), entry(qos={"profile": "map", "depth": 5}), []),
    ("type", entry(), entry(type_="std_msgs/msg/Int32", type_hash=H2, qos="sensor_data"),
     ["TYPE_MISMATCH"]),
    ("hash", entry(), entry(type_hash=H2), ["TYPE_HASH_MISMATCH"]),
    ("hash-and-qos", entry(qos="sensor_data"), entry(type_hash=H2),
     ["QOS_INCOMPATIBLE", "TYPE_HASH_MISMATCH"]),
    ("reliability", entry(qos="sensor_data"), entry(qos="default"), ["QOS_INCOMPATIBLE"]),
    ("best-effort-sub-ok", entry(qos="default"), entry(qos="sensor_data"), []),
    ("durability", entry(qos="default"), entry(qos="map"), ["QOS_INCOMPATIBLE"]),
    ("deadline", entry(), entry(qos={"deadline_ns": 100}), ["QOS_INCOMPATIBLE"]),
    ("liveliness", entry(qos={"liveliness": "AUTOMATIC"}),
     entry(qos={"liveliness": "MANUAL_BY_TOPIC"}), ["QOS_INCOMPATIBLE"]),
    ("system-default-pub-reliable-sub", entry(qos="system_default"), entry(qos="default"),
     ["QOS_MAYBE_INCOMPATIBLE"]),
    ("unknown-vs-unknown", entry(qos={"reliability": "UNKNOWN"}),
     entry(qos={"reliability": "UNKNOWN"}), ["QOS_MAYBE_INCOMPATIBLE"]),
    ("weak-pub-system-default-sub", entry(qos="sensor_data"),
     entry(qos={"reliability": "SYSTEM_DEFAULT"}), ["QOS_MAYBE_INCOMPATIBLE"]),
    # both ends at SYSTEM_DEFAULT get the same middleware default: not reported by default
    ("system-default-both", entry(qos="system_default"), entry(qos="system_default"), []),
    ("no-hash-one-side", entry(type_hash=None), entry(), []),
    ("no-qos-one-side", entry(qos="sensor_data"), entry(qos=None), []),
]


@pytest.mark.parametrize(("case", "pub", "sub", "rules"), TOPIC_ROWS,
                         ids=[row[0] for row in TOPIC_ROWS])
def test_topic_pairs(case, pub, sub, rules):
    items = check_compatibility(system("publishers", pub, "subscriptions", sub))
    assert sorted(i.rule for i in items) == sorted(rules)
    for item in items:
        assert (item.name, item.requester, item.provider) == ("/chatter", SUB, PUB)
        assert item.severity is compatibility.RULES[item.rule]


def test_strict_reports_what_rmw_reports():
    contracts = system("publishers", entry(), "subscriptions", entry())
    # rmw's default profile leaves liveliness at SYSTEM_DEFAULT on both ends
    item, = check_compatibility(contracts, strict_system_default=True)
    assert item.rule == "QOS_MAYBE_INCOMPATIBLE" and item.severity is Severity.RISKY
    assert "liveliness" in item.message


def test_qos_error_message_gives_the_reason():
    item, = check_compatibility(system("publishers", entry(qos="sensor_data"),
                                "subscriptions", entry()))
    assert item.message == "BEST_EFFORT publisher and RELIABLE subscription"
    assert item.severity is Severity.BREAKING


@pytest.mark.parametrize(
    ("server_kind", "client_kind", "type_"),
    [("service_servers", "service_clients", "std_srvs/srv/Trigger"),
     ("action_servers", "action_clients", "test_msgs/action/Fibonacci")],
)
@pytest.mark.parametrize(
    ("client_changes", "rules"),
    [({}, []), ({"type": "other/srv/X"}, ["TYPE_MISMATCH"]),
     ({"type_hash": H2}, ["TYPE_HASH_MISMATCH"])],
)
def test_service_and_action_pairs(server_kind, client_kind, type_, client_changes, rules):
    server = entry("/do", type_, qos=None)
    client = {**server, **client_changes}
    items = check_compatibility(system(server_kind, server, client_kind, client))
    assert [i.rule for i in items] == rules
    for item in items:
        assert item.provider == ContractEndpoint("a.yaml", "/talker", server_kind)
        assert item.requester == ContractEndpoint("b.yaml", "/listener", client_kind)


def test_action_hash_mappings_compared():
    hashes = {"send_goal": H1, "get_result": H1, "feedback": H1}
    server = {"name": "/fib", "type": "test_msgs/action/Fibonacci", "type_hash": hashes}
    client = {**server, "type_hash": {**hashes, "feedback": H2}}
    item, = check_compatibility(system("action_servers", server, "action_clients", client))
    assert item.rule == "TYPE_HASH_MISMATCH"


@pytest.mark.parametrize(
    ("kind", "rule", "text"),
    [("subscriptions", "SUBSCRIPTION_WITHOUT_PUBLISHER", "no publisher in these contracts"),
     ("service_clients", "CLIENT_WITHOUT_SERVER", "no service server in these contracts"),
     ("action_clients", "ACTION_CLIENT_WITHOUT_SERVER", "no action server in these contracts")],
)
def test_missing_peers(kind, rule, text):
    item, = check_compatibility({"b.yaml": {"/listener": {kind: [entry("/lonely", qos=None)]}}})
    assert (item.rule, item.severity, item.name) == (rule, Severity.RISKY, "/lonely")
    assert item.requester == ContractEndpoint("b.yaml", "/listener", kind) and item.provider is None
    assert item.message == text


def test_providers_without_requesters_are_fine():
    assert check_compatibility({"a.yaml": {"/t": {"publishers": [entry()],
                                                 "service_servers": [entry("/s", qos=None)],
                                                 "action_servers": [entry("/a", qos=None)]}}}) == []


def test_peers_in_the_same_contract_and_node_count():
    contracts = {"one.yaml": {"/n": {"publishers": [entry()], "subscriptions": [entry()]}}}
    assert check_compatibility(contracts) == []


def test_every_pair_is_checked_and_sorted():
    contracts = {
        "a.yaml": {"/fast": {"publishers": [entry(qos="sensor_data")]},
                   "/slow": {"publishers": [entry(qos="default")]}},
        "b.yaml": {"/r1": {"subscriptions": [entry(qos="default")]},
                   "/r2": {"subscriptions": [entry(qos="map"), entry("/missing")]}},
    }
    items = check_compatibility(contracts)
    assert [(i.rule, i.requester.node, i.provider.node if i.provider else None)
            for i in items] == [
        ("QOS_INCOMPATIBLE", "/r1", "/fast"),
        ("QOS_INCOMPATIBLE", "/r2", "/fast"),  # reliability and durability
        ("QOS_INCOMPATIBLE", "/r2", "/slow"),  # durability
        ("SUBSCRIPTION_WITHOUT_PUBLISHER", "/r2", None),
    ]
    assert "TRANSIENT_LOCAL" in items[1].message and "BEST_EFFORT" in items[1].message
    assert check_compatibility(dict(reversed(contracts.items()))) == items


def test_tolerates_missing_lists():
    assert check_compatibility({"a.yaml": {"/n": None, "/m": {"subscriptions": None}}, "b": None}) == []


def test_rules_table_is_complete():
    assert set(compatibility.RULES) == {row for rows in (
        ["TYPE_MISMATCH", "TYPE_HASH_MISMATCH", "QOS_INCOMPATIBLE", "QOS_MAYBE_INCOMPATIBLE", "QOS_DDS_WOULD_REFUSE",
         "SUBSCRIPTION_WITHOUT_PUBLISHER", "CLIENT_WITHOUT_SERVER",
         "ACTION_CLIENT_WITHOUT_SERVER"],
        # system contracts only (check_launched)
        ["DUPLICATE_NODE_NAME", "SERVICE_MULTIPLE_SERVERS", "ACTION_MULTIPLE_SERVERS",
         "LAUNCHED_NODE_NOT_CREATED", "DANGLING_SUBSCRIPTION", "DANGLING_SERVICE_CLIENT", "DANGLING_ACTION_CLIENT",
         "TOPIC_NAME_MISMATCH", "SERVICE_NAME_MISMATCH", "ACTION_NAME_MISMATCH", "EXTERNAL_UNUSED",
         "PARAM_NOT_DECLARED", "PARAM_NAME_INVALID", "PARAMS_FILE_SECTION_UNMATCHED", "REMAP_NEAR_MISS",
         "REMAP_UNUSED", "REMAP_UNUSED_UNCONNECTED", "PARAM_PATH_MISSING", "PARAM_PATH_MACHINE_LOCAL", "PARAM_DEVICE_ABSENT"],
        # recordings only (check --bag: compare.recordings)
        ["CONTRACT_TOPIC_NOT_RECORDED", "RECORDED_TOPIC_SILENT", "RECORDED_TOPIC_UNDECLARED",
         "RECORDED_TOPIC_EXTRA_PUBLISHER"])
        for row in rows}


# --------------------------------------------------------------------------- rendering


def sample_items():
    return check_compatibility({
        "a.yaml": {"/talker": {"publishers": [entry(qos="sensor_data")]}},
        "b.yaml": {"/listener": {"subscriptions": [entry(), entry("/other")]}},
    })


def test_render_compat_text():
    assert report.render_compat_text(sample_items(), threshold=Severity.BREAKING).splitlines() == [
        "Compatibility check: 2 problems (1 breaking, 1 risky, 0 safe)",
        "Result: FAIL (fail on: breaking)",
        "",
        "BREAKING (1)",
        "  /chatter",
        "    [QOS_INCOMPATIBLE] publisher of /talker (a.yaml) -> subscription of /listener "
        "(b.yaml): BEST_EFFORT publisher and RELIABLE subscription",
        "",
        "RISKY (1) - below the fail threshold (breaking), not failing",
        "  /other",
        "    [SUBSCRIPTION_WITHOUT_PUBLISHER] subscription of /listener (b.yaml): no publisher "
        "in these contracts",
    ]


def test_render_compat_text_empty():
    assert report.render_compat_text([]) == "Compatibility check: all contracts fit together.\n"


def test_compat_to_json():
    data = report.compat_to_json(sample_items())
    assert json.loads(json.dumps(data)) == data
    assert data == [
        {"name": "/chatter", "rule": "QOS_INCOMPATIBLE", "severity": "BREAKING",
         "requester": {"label": "b.yaml", "node": "/listener", "kind": "subscriptions"},
         "provider": {"label": "a.yaml", "node": "/talker", "kind": "publishers"},
         "message": "BEST_EFFORT publisher and RELIABLE subscription"},
        {"name": "/other", "rule": "SUBSCRIPTION_WITHOUT_PUBLISHER", "severity": "RISKY",
         "requester": {"label": "b.yaml", "node": "/listener", "kind": "subscriptions"},
         "provider": None, "message": "no publisher in these contracts"},
    ]


def test_fails_works_for_compat_items():
    assert report.fails(sample_items(), Severity.BREAKING)
    assert not report.fails(sample_items()[1:], Severity.BREAKING)


def test_docs_list_every_system_rule_with_its_severity():
    import pathlib
    import re

    text = (pathlib.Path(__file__).parents[2] / "docs" / "drift-rules.md").read_text()
    documented = dict(re.findall(r"^\| `([A-Z_]+)` \|[^|]*\| (BREAKING|RISKY|SAFE|NOTE) \|", text,
                                 flags=re.MULTILINE))
    for rule, severity in compatibility.RULES.items():
        assert documented.get(rule) == severity.name, rule


def test_every_system_rule_has_the_summary_the_docs_give_it():
    import pathlib
    import re

    text = (pathlib.Path(__file__).parents[2] / "docs" / "drift-rules.md").read_text()
    section = text[text.index("## Compatibility rules"):]
    documented = dict(re.findall(r"^\| `([A-Z_]+)` \| ([^|]*) \|", section, flags=re.MULTILINE))
    assert set(compatibility.SUMMARIES) == set(compatibility.RULES)
    for rule, summary in compatibility.SUMMARIES.items():
        assert documented.get(rule) == summary, rule
