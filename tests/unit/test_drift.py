"""drift.compare: every rule, the options, tolerance of partial input and deterministic order."""

import random
import subprocess
import sys

import pytest

from pytest_rmw_introspect.compare import drift
from pytest_rmw_introspect.compare.drift import DriftItem, compare
from pytest_rmw_introspect.compare.options import ComparisonOptions as CompareOptions
from pytest_rmw_introspect.errors import OptionError
from pytest_rmw_introspect.model.vocabulary import LISTS, Severity

S = 1_000_000_000
H1 = "RIHS01_" + "1" * 64
H2 = "RIHS01_" + "2" * 64

BREAKING, RISKY, SAFE = Severity.BREAKING, Severity.RISKY, Severity.SAFE


def entry(name="/chatter", type_="std_msgs/msg/String", type_hash=H1, qos="default"):
    value = {"name": name, "type": type_, "type_hash": type_hash}
    if qos is not None:
        value["qos"] = qos
    return value


def nodes(kind=None, *entries, node="/talker"):
    return {node: {kind: list(entries)} if kind else {}}


def only(items):
    assert len(items) == 1, items
    return items[0]


# --------------------------------------------------------------------------- presence


PRESENCE_ROWS = [
    ("publishers", "removed", "PUB_REMOVED", BREAKING),
    ("publishers", "added", "PUB_ADDED", SAFE),
    ("subscriptions", "removed", "SUB_REMOVED", RISKY),
    ("subscriptions", "added", "SUB_ADDED", RISKY),
    ("service_servers", "removed", "SERVICE_SERVER_REMOVED", BREAKING),
    ("service_servers", "added", "SERVICE_SERVER_ADDED", SAFE),
    ("service_clients", "removed", "SERVICE_CLIENT_REMOVED", RISKY),
    ("service_clients", "added", "SERVICE_CLIENT_ADDED", RISKY),
    ("action_servers", "removed", "ACTION_SERVER_REMOVED", BREAKING),
    ("action_servers", "added", "ACTION_SERVER_ADDED", SAFE),
    ("action_clients", "removed", "ACTION_CLIENT_REMOVED", RISKY),
    ("action_clients", "added", "ACTION_CLIENT_ADDED", RISKY),
]


@pytest.mark.parametrize(("kind", "change", "rule", "severity"), PRESENCE_ROWS)
def test_interface_presence(kind, change, rule, severity):
    present = nodes(kind, entry("/thing", "pkg/msg/T", qos=None))
    absent = nodes(kind)
    expected, actual = (present, absent) if change == "removed" else (absent, present)
    item = only(compare(expected, actual))
    assert (item.node, item.kind, item.name, item.change) == ("/talker", kind, "/thing", change)
    assert (item.rule, item.severity) == (rule, severity)
    assert "/thing" in item.message
    side = present["/talker"][kind][0]
    assert (item.old, item.new) == ((side, None) if change == "removed" else (None, side))


@pytest.mark.parametrize(
    ("change", "rule", "severity"),
    [("removed", "NODE_REMOVED", BREAKING), ("added", "NODE_ADDED", SAFE)],
)
def test_node_presence_reports_node_then_each_interface(change, rule, severity):
    node = {"publishers": [entry("/out")], "subscriptions": [entry("/in")]}
    expected, actual = ({"/n": node}, {}) if change == "removed" else ({}, {"/n": node})
    items = compare(expected, actual)
    node_item = next(i for i in items if i.kind == "node")
    assert (node_item.name, node_item.change, node_item.rule, node_item.severity) == (
        "/n", change, rule, severity)
    assert sorted((i.kind, i.name, i.change) for i in items if i.kind != "node") == [
        ("publishers", "/out", change), ("subscriptions", "/in", change)]
    snapshot = node_item.old if change == "removed" else node_item.new
    assert snapshot["publishers"] == [entry("/out")]


def test_no_drift_for_identical_nodes():
    both = {"/talker": {"publishers": [entry()], "action_servers": [
        {"name": "/fib", "type": "test_msgs/action/Fibonacci",
         "type_hash": {"send_goal": H1, "get_result": H1, "feedback": H1}}]}}
    assert compare(both, both) == []


def test_whole_node_rewritten_is_reported_per_interface():
    # every interface of the node differs: still per-interface items, not one big change
    expected = nodes("publishers", entry("/a"), entry("/b"))
    actual = nodes("publishers", entry("/c"))
    assert sorted((i.name, i.rule) for i in compare(expected, actual)) == [
        ("/a", "PUB_REMOVED"), ("/b", "PUB_REMOVED"), ("/c", "PUB_ADDED")]


# --------------------------------------------------------------------------- renames

RENAME_RULES = {"publishers": "PUB_RENAMED", "subscriptions": "SUB_RENAMED",
                "service_servers": "SERVICE_SERVER_RENAMED", "service_clients": "SERVICE_CLIENT_RENAMED",
                "action_servers": "ACTION_SERVER_RENAMED", "action_clients": "ACTION_CLIENT_RENAMED"}


@pytest.mark.parametrize("kind", LISTS)
def test_one_removed_and_one_added_of_the_same_type_read_as_a_rename(kind):
    item = only(compare(nodes(kind, entry("/chatter"), entry("/kept", type_="std_msgs/msg/Int32")),
                        nodes(kind, entry("/speech"), entry("/kept", type_="std_msgs/msg/Int32"))))
    assert (item.change, item.rule, item.severity) == ("renamed", RENAME_RULES[kind], BREAKING)
    assert (item.name, item.old["name"], item.new["name"]) == ("/chatter", "/chatter", "/speech")
    assert "/chatter looks renamed to /speech (same type std_msgs/msg/String)" in item.message


@pytest.mark.parametrize("kind", ["subscriptions", "service_clients", "action_clients"])
def test_renamed_and_retyped_is_a_rename_and_a_type_change(kind):
    # as severe as a rename alone (a subscription removed and added was RISKY, renamed BREAKING)
    items = compare(nodes(kind, entry("/a")), nodes(kind, entry("/b", type_="std_msgs/msg/Int32", type_hash=H2)))
    assert sorted((i.rule, i.name, i.severity) for i in items) == sorted([
        (RENAME_RULES[kind], "/a", BREAKING), ("TYPE_CHANGED", "/b", BREAKING)])
    renamed = [i for i in items if i.change == "renamed"][0]
    assert "/a looks renamed to /b (and retyped from std_msgs/msg/String to std_msgs/msg/Int32)" in renamed.message


def test_a_rename_does_not_hide_other_changes_of_the_endpoint():
    deeper = compare(nodes("publishers", entry("/a")),
                     nodes("publishers", entry("/b", type_hash=H2, qos={"profile": "default", "depth": 5,
                                                                         "reliability": "BEST_EFFORT"})))
    assert sorted((i.rule, i.name) for i in deeper) == [
        ("PUB_RENAMED", "/a"), ("QOS_DEPTH_DECREASED", "/b"), ("QOS_RELIABILITY_WEAKENED", "/b"),
        ("TYPE_HASH_CHANGED", "/b")]
    # the comparison options apply to them as to any change
    ignoring = compare(nodes("publishers", entry("/a")),
                       nodes("publishers", entry("/b", type_hash=H2, qos={"profile": "default", "depth": 5})),
                       CompareOptions(ignore_type_hash=True, ignore_qos=["depth"]))
    assert [i.rule for i in ignoring] == ["PUB_RENAMED"]


def test_no_rename_across_kinds_or_ambiguity():
    # an offer removed is BREAKING already: a publisher of another type is not read as a rename
    other_type = compare(nodes("publishers", entry("/a")),
                         nodes("publishers", entry("/b", type_="std_msgs/msg/Int32", type_hash=H2)))
    assert sorted(i.rule for i in other_type) == ["PUB_ADDED", "PUB_REMOVED"]
    other_kind = compare({"/n": {"publishers": [entry("/a")]}}, {"/n": {"subscriptions": [entry("/b")]}})
    assert sorted(i.rule for i in other_kind) == ["PUB_REMOVED", "SUB_ADDED"]
    ambiguous = compare(nodes("publishers", entry("/a")), nodes("publishers", entry("/b"), entry("/c")))
    assert sorted(i.rule for i in ambiguous) == ["PUB_ADDED", "PUB_ADDED", "PUB_REMOVED"]


def test_with_allow_extra_a_rename_is_a_removal():
    items = compare(nodes("publishers", entry("/a")), nodes("publishers", entry("/b")),
                    CompareOptions(allow_extra=True))
    assert [i.rule for i in items] == ["PUB_REMOVED"]


# --------------------------------------------------------------------------- type and hash


@pytest.mark.parametrize("kind", LISTS)
def test_type_changed(kind):
    item = only(compare(nodes(kind, entry(type_="std_msgs/msg/String", qos=None)),
                        nodes(kind, entry(type_="std_msgs/msg/Int32", type_hash=H2, qos=None))))
    assert (item.change, item.rule, item.severity) == ("type", "TYPE_CHANGED", BREAKING)
    assert (item.old, item.new) == ("std_msgs/msg/String", "std_msgs/msg/Int32")
    assert "std_msgs/msg/String" in item.message and "std_msgs/msg/Int32" in item.message


def test_type_hash_changed_names_the_type():
    item = only(compare(nodes("publishers", entry()), nodes("publishers", entry(type_hash=H2))))
    assert (item.change, item.rule, item.severity) == ("type_hash", "TYPE_HASH_CHANGED", BREAKING)
    assert (item.old, item.new) == (H1, H2)
    assert item.message == "message definition of std_msgs/msg/String changed"


@pytest.mark.parametrize(
    ("changed_parts", "text"),
    [
        ({"send_goal"}, "goal (send_goal)"),
        ({"get_result"}, "result (get_result)"),
        ({"feedback"}, "feedback (feedback)"),
        ({"feedback", "send_goal"}, "goal (send_goal), feedback (feedback)"),
    ],
)
def test_action_type_hash_names_the_changed_parts(changed_parts, text):
    old = {"send_goal": H1, "get_result": H1, "feedback": H1}
    new = {part: (H2 if part in changed_parts else H1) for part in old}
    action = {"name": "/fib", "type": "test_msgs/action/Fibonacci"}
    item = only(compare(nodes("action_servers", {**action, "type_hash": old}),
                        nodes("action_servers", {**action, "type_hash": new})))
    assert item.rule == "TYPE_HASH_CHANGED" and item.severity is BREAKING
    assert (item.old, item.new) == (old, new)
    assert item.message == f"action definition of test_msgs/action/Fibonacci changed: {text}"


def test_type_change_implies_the_hash_change():
    items = compare(nodes("publishers", entry()),
                    nodes("publishers", entry(type_="std_msgs/msg/Int32", type_hash=H2)))
    assert [i.rule for i in items] == ["TYPE_CHANGED"]


# --------------------------------------------------------------------------- QoS

# (kind, field, old, new, rule, severity)
QOS_ROWS = [
    # reliability: publisher offers, subscription requests
    ("publishers", "reliability", "RELIABLE", "BEST_EFFORT", "QOS_RELIABILITY_WEAKENED", BREAKING),
    ("publishers", "reliability", "BEST_EFFORT", "RELIABLE", "QOS_RELIABILITY_STRENGTHENED", SAFE),
    ("subscriptions", "reliability", "BEST_EFFORT", "RELIABLE",
     "QOS_RELIABILITY_REQUEST_RAISED", BREAKING),
    ("subscriptions", "reliability", "RELIABLE", "BEST_EFFORT",
     "QOS_RELIABILITY_REQUEST_LOWERED", SAFE),
    ("publishers", "reliability", "RELIABLE", "SYSTEM_DEFAULT", "QOS_RELIABILITY_UNCERTAIN", RISKY),
    ("publishers", "reliability", "SYSTEM_DEFAULT", "BEST_EFFORT",
     "QOS_RELIABILITY_UNCERTAIN", RISKY),
    ("publishers", "reliability", "BEST_EFFORT", "SYSTEM_DEFAULT",
     "QOS_RELIABILITY_STRENGTHENED", SAFE),  # nothing is weaker than BEST_EFFORT
    ("publishers", "reliability", "SYSTEM_DEFAULT", "RELIABLE",
     "QOS_RELIABILITY_STRENGTHENED", SAFE),
    ("subscriptions", "reliability", "BEST_EFFORT", "SYSTEM_DEFAULT",
     "QOS_RELIABILITY_UNCERTAIN", RISKY),
    ("subscriptions", "reliability", "RELIABLE", "UNKNOWN",
     "QOS_RELIABILITY_REQUEST_LOWERED", SAFE),
    ("publishers", "reliability", "BEST_EFFORT", "BEST_AVAILABLE",
     "QOS_RELIABILITY_STRENGTHENED", SAFE),
    ("publishers", "reliability", "BEST_AVAILABLE", "BEST_EFFORT",
     "QOS_RELIABILITY_WEAKENED", BREAKING),
    ("subscriptions", "reliability", "RELIABLE", "BEST_AVAILABLE",
     "QOS_RELIABILITY_REQUEST_LOWERED", SAFE),
    # durability
    ("publishers", "durability", "TRANSIENT_LOCAL", "VOLATILE", "QOS_DURABILITY_WEAKENED", BREAKING),
    ("publishers", "durability", "VOLATILE", "TRANSIENT_LOCAL", "QOS_DURABILITY_STRENGTHENED", SAFE),
    ("subscriptions", "durability", "VOLATILE", "TRANSIENT_LOCAL",
     "QOS_DURABILITY_REQUEST_RAISED", BREAKING),
    ("subscriptions", "durability", "TRANSIENT_LOCAL", "VOLATILE",
     "QOS_DURABILITY_REQUEST_LOWERED", SAFE),
    ("subscriptions", "durability", "VOLATILE", "SYSTEM_DEFAULT", "QOS_DURABILITY_UNCERTAIN", RISKY),
    # deadline: shorter offered period = stronger promise; unset = none
    ("publishers", "deadline_ns", S, 2 * S, "QOS_DEADLINE_WEAKENED", BREAKING),
    ("publishers", "deadline_ns", S, 0, "QOS_DEADLINE_WEAKENED", BREAKING),
    ("publishers", "deadline_ns", S, -1, "QOS_DEADLINE_WEAKENED", BREAKING),
    ("publishers", "deadline_ns", 2 * S, S, "QOS_DEADLINE_STRENGTHENED", SAFE),
    ("publishers", "deadline_ns", 0, S, "QOS_DEADLINE_STRENGTHENED", SAFE),
    ("subscriptions", "deadline_ns", 2 * S, S, "QOS_DEADLINE_REQUEST_RAISED", BREAKING),
    ("subscriptions", "deadline_ns", 0, S, "QOS_DEADLINE_REQUEST_RAISED", BREAKING),
    ("subscriptions", "deadline_ns", S, 2 * S, "QOS_DEADLINE_REQUEST_LOWERED", SAFE),
    ("subscriptions", "deadline_ns", S, 0, "QOS_DEADLINE_REQUEST_LOWERED", SAFE),
    # liveliness
    ("publishers", "liveliness", "MANUAL_BY_TOPIC", "AUTOMATIC", "QOS_LIVELINESS_WEAKENED", BREAKING),
    ("publishers", "liveliness", "AUTOMATIC", "MANUAL_BY_TOPIC", "QOS_LIVELINESS_STRENGTHENED", SAFE),
    ("subscriptions", "liveliness", "AUTOMATIC", "MANUAL_BY_TOPIC",
     "QOS_LIVELINESS_REQUEST_RAISED", BREAKING),
    ("subscriptions", "liveliness", "MANUAL_BY_TOPIC", "AUTOMATIC",
     "QOS_LIVELINESS_REQUEST_LOWERED", SAFE),
    ("publishers", "liveliness", "SYSTEM_DEFAULT", "AUTOMATIC", "QOS_LIVELINESS_UNCERTAIN", RISKY),
    # liveliness lease duration
    ("publishers", "liveliness_lease_duration_ns", S, 3 * S,
     "QOS_LEASE_DURATION_WEAKENED", BREAKING),
    ("publishers", "liveliness_lease_duration_ns", 3 * S, S,
     "QOS_LEASE_DURATION_STRENGTHENED", SAFE),
    ("subscriptions", "liveliness_lease_duration_ns", 3 * S, S,
     "QOS_LEASE_DURATION_REQUEST_RAISED", BREAKING),
    ("subscriptions", "liveliness_lease_duration_ns", S, 0,
     "QOS_LEASE_DURATION_REQUEST_LOWERED", SAFE),
    # never part of matching
    ("publishers", "history", "KEEP_LAST", "KEEP_ALL", "QOS_HISTORY_CHANGED", RISKY),
    ("subscriptions", "history", "KEEP_ALL", "KEEP_LAST", "QOS_HISTORY_CHANGED", RISKY),
    ("publishers", "depth", 10, 5, "QOS_DEPTH_DECREASED", RISKY),
    ("subscriptions", "depth", 10, 1, "QOS_DEPTH_DECREASED", RISKY),
    ("publishers", "depth", 5, 10, "QOS_DEPTH_INCREASED", SAFE),
    ("subscriptions", "depth", 0, 10, "QOS_DEPTH_UNCERTAIN", RISKY),
    ("publishers", "lifespan_ns", 10 * S, S, "QOS_LIFESPAN_SHORTENED", RISKY),
    ("publishers", "lifespan_ns", 0, S, "QOS_LIFESPAN_SHORTENED", RISKY),
    ("publishers", "lifespan_ns", S, 10 * S, "QOS_LIFESPAN_EXTENDED", SAFE),
    ("publishers", "lifespan_ns", S, 0, "QOS_LIFESPAN_EXTENDED", SAFE),
    ("subscriptions", "lifespan_ns", 10 * S, S, "QOS_LIFESPAN_NO_EFFECT", SAFE),
    ("publishers", "avoid_ros_namespace_conventions", False, True,
     "QOS_NAMESPACE_CONVENTIONS_CHANGED", BREAKING),
    ("subscriptions", "avoid_ros_namespace_conventions", True, False,
     "QOS_NAMESPACE_CONVENTIONS_CHANGED", BREAKING),
]


@pytest.mark.parametrize(("kind", "field", "old", "new", "rule", "severity"), QOS_ROWS,
                         ids=[f"{r[0]}-{r[1]}-{r[2]}-{r[3]}" for r in QOS_ROWS])
def test_qos_rules(kind, field, old, new, rule, severity):
    # history KEEP_LAST unless the row is about history, so depth stays meaningful
    base = {"history": "KEEP_LAST", "liveliness": "AUTOMATIC", "depth": 10}
    item = only(compare(nodes(kind, entry(qos={**base, field: old})),
                        nodes(kind, entry(qos={**base, field: new}))))
    assert (item.change, item.rule, item.severity) == (f"qos.{field}", rule, severity)
    # infinite and unset durations are the same thing in contracts
    expected_old, expected_new = (0 if v == -1 else v for v in (old, new))
    if field == "history" or item.change != "qos.depth":
        assert (item.old, item.new) == (expected_old, expected_new)
    assert item.message


def test_every_rule_has_a_test_row():
    from test_destruction_drift import TESTED_RULES as DESTRUCTION_RULES  # what the program destroys
    from test_gate import TESTED_RULES as GATE_RULES  # diff --against: versions and consumers
    from test_parameter_drift import TESTED_RULES as PARAMETER_RULES  # parameters and lifecycle
    from test_type_drift import TESTED_RULES as TYPE_DESCRIPTION_RULES  # rules of the types: section
    from test_type_lock import TESTED_RULES as TYPE_LOCK_RULES  # the package's type lock

    tested = {row[2] for row in PRESENCE_ROWS} | {row[4] for row in QOS_ROWS} | {
        "NODE_ADDED", "NODE_REMOVED", "TYPE_CHANGED", "TYPE_HASH_CHANGED", "TYPE_HASH_DISTRIBUTION_CHANGED",
        "SERVICE_QOS_CHANGED"} \
        | set(RENAME_RULES.values()) \
        | TYPE_DESCRIPTION_RULES | PARAMETER_RULES | TYPE_LOCK_RULES | DESTRUCTION_RULES | GATE_RULES
    assert tested == set(drift.RULES)


HASH_A = "RIHS01_" + "a" * 64
HASH_B = "RIHS01_" + "b" * 64


def test_a_type_hash_that_differs_between_distributions_is_said_to_be_the_distribution_s():
    items = compare(nodes("publishers", entry(type_hash=HASH_A)), nodes("publishers", entry(type_hash=HASH_B)))
    assert [i.rule for i in items] == ["TYPE_HASH_CHANGED"]
    attributed = only(drift.attribute_to_distribution(items, "jazzy", "kilted"))
    assert (attributed.rule, attributed.severity, attributed.change) == ("TYPE_HASH_DISTRIBUTION_CHANGED", RISKY, "type_hash")
    assert "jazzy" in attributed.message and "kilted" in attributed.message
    assert "check on jazzy" in attributed.message
    # the same distribution, or one side unknown: the change is the package's
    for expected, actual in (("jazzy", "jazzy"), (None, "kilted"), ("jazzy", None)):
        assert drift.attribute_to_distribution(items, expected, actual) == items


def test_only_type_hash_items_are_attributed_to_the_distribution():
    old = nodes("publishers", entry(type_hash=HASH_A, qos="default"))
    new = nodes("publishers", entry(type_hash=HASH_B, qos="sensor_data"))
    attributed = drift.attribute_to_distribution(compare(old, new), "jazzy", "kilted")
    rules = [i.rule for i in attributed]
    assert "TYPE_HASH_DISTRIBUTION_CHANGED" in rules and "TYPE_HASH_CHANGED" not in rules
    assert "QOS_RELIABILITY_WEAKENED" in rules  # a QoS change stays what it is
    assert rules[0] == "QOS_RELIABILITY_WEAKENED"  # most severe first, as compare sorts them


def test_qos_profile_names_compare_equal_to_their_explicit_form():
    explicit = {"history": "KEEP_LAST", "depth": 5, "reliability": "BEST_EFFORT",
                "durability": "VOLATILE", "liveliness": "SYSTEM_DEFAULT", "deadline_ns": -1,
                "lifespan_ns": 0, "liveliness_lease_duration_ns": 0,
                "avoid_ros_namespace_conventions": False}
    assert compare(nodes("publishers", entry(qos="sensor_data")),
                   nodes("publishers", entry(qos=explicit))) == []
    assert compare(nodes("publishers", entry(qos={"profile": "sensor_data", "depth": 5})),
                   nodes("publishers", entry(qos={"reliability": "BEST_EFFORT", "depth": 5})
                         )) == []


def test_profile_change_reports_each_field():
    items = compare(nodes("publishers", entry(qos="default")),
                    nodes("publishers", entry(qos="sensor_data")))
    assert [(i.change, i.rule) for i in items] == [
        ("qos.reliability", "QOS_RELIABILITY_WEAKENED"), ("qos.depth", "QOS_DEPTH_DECREASED")]


def test_history_change_implies_the_depth_change():
    items = compare(nodes("publishers", entry(qos={"history": "KEEP_LAST", "depth": 10})),
                    nodes("publishers", entry(qos={"history": "KEEP_ALL"})))
    assert [i.rule for i in items] == ["QOS_HISTORY_CHANGED"]


def test_invalid_qos_is_reported_with_its_location():
    with pytest.raises(ValueError, match=r"^/talker publisher /chatter: invalid QoS reliability"):
        compare(nodes("publishers", entry(qos={"reliability": "MAYBE"})), {})


def test_a_service_qos_is_compared_on_the_policies_that_decide_whether_a_client_is_served():
    # issue 49 item 4: depth and history never decide it (default and sensor_data differ in depth too)
    item = only(compare(nodes("service_servers", entry("/srv", "std_srvs/srv/Trigger", qos="default")),
                        nodes("service_servers", entry("/srv", "std_srvs/srv/Trigger", qos="sensor_data"))))
    assert (item.rule, item.change, item.old, item.new) == ("SERVICE_QOS_CHANGED", "qos.reliability", "RELIABLE",
                                                            "BEST_EFFORT")
    assert item.severity is Severity.BREAKING and "no longer served" in item.message
    assert compare(nodes("service_clients", entry("/srv", "std_srvs/srv/Trigger", qos="default")),
                   nodes("service_clients", entry("/srv", "std_srvs/srv/Trigger", qos={"depth": 1}))) == []


def test_a_service_entry_without_qos_has_the_services_default():
    # a capture writes a service's QoS only where it differs from services_default, and contracts
    # written before that have none: both mean the services default
    plain = nodes("service_clients", entry("/srv", "std_srvs/srv/Trigger"))
    assert compare(plain, nodes("service_clients", entry("/srv", "std_srvs/srv/Trigger", qos="services_default"))) == []
    item = only(compare(plain, nodes("service_clients", entry("/srv", "std_srvs/srv/Trigger",
                                                               qos={"durability": "TRANSIENT_LOCAL"}))))
    assert (item.rule, item.change) == ("SERVICE_QOS_CHANGED", "qos.durability")


def test_actions_have_no_qos_comparison():
    assert compare(nodes("action_servers", entry("/fib", "test_msgs/action/Fibonacci")),
                   nodes("action_servers", entry("/fib", "test_msgs/action/Fibonacci"))) == []


def test_on_a_middleware_that_matches_any_qos_a_refused_match_is_risky():
    # issue 49 item 3: rmw_zenoh_cpp connects whatever the QoS; what the peers get still changes
    old = nodes("publishers", entry(qos="default"))
    new = nodes("publishers", entry(qos="sensor_data"))
    dds = [i for i in compare(old, new) if i.rule == "QOS_RELIABILITY_WEAKENED"]
    zenoh = [i for i in compare(old, new, CompareOptions(rmw="rmw_zenoh_cpp")) if i.rule == "QOS_RELIABILITY_WEAKENED"]
    assert [i.severity for i in dds] == [Severity.BREAKING]
    assert [i.severity for i in zenoh] == [Severity.RISKY] and "rmw_zenoh_cpp matches any QoS" in zenoh[0].message
    service = compare(nodes("service_servers", entry("/srv", "std_srvs/srv/Trigger")),
                      nodes("service_servers", entry("/srv", "std_srvs/srv/Trigger", qos={"reliability": "BEST_EFFORT"})),
                      CompareOptions(rmw="rmw_zenoh_cpp"))
    assert [(i.rule, i.severity) for i in service] == [("SERVICE_QOS_CHANGED", Severity.RISKY)]
    # a DDS middleware refuses as the DDS rules say
    assert [i.severity for i in compare(old, new, CompareOptions(rmw="rmw_cyclonedds_cpp"))
            if i.rule == "QOS_RELIABILITY_WEAKENED"] == [Severity.BREAKING]


# --------------------------------------------------------------------------- partial input


@pytest.mark.parametrize(
    ("expected", "actual"),
    [
        ({}, {}),
        (None, None),
        ({"/n": {}}, {"/n": {"publishers": []}}),
        ({"/n": None}, {"/n": {"subscriptions": None}}),
        # a key one side leaves out is not compared
        (nodes("publishers", {"name": "/chatter", "type": "std_msgs/msg/String"}),
         nodes("publishers", entry(qos="sensor_data"))),
        (nodes("publishers", entry()), nodes("publishers", entry(type_hash=None, qos=None))),
    ],
)
def test_missing_lists_and_keys_are_tolerated(expected, actual):
    assert compare(expected, actual) == []


def test_duplicate_names_in_one_list_stay_visible():
    expected = nodes("publishers", entry(qos="default"))
    actual = nodes("publishers", entry(qos="default"), entry(qos="default"))
    item = only(compare(expected, actual))
    assert (item.name, item.rule) == ("/chatter [2]", "PUB_ADDED")


# --------------------------------------------------------------------------- options


def mixed_change():
    expected = nodes("publishers", entry("/a"), entry("/b", qos="default"))
    actual = nodes("publishers", entry("/a", type_hash=H2), entry("/b", qos="sensor_data"),
                   entry("/c"))
    return expected, actual


@pytest.mark.parametrize(
    ("options", "remaining"),
    [
        (CompareOptions(), {"TYPE_HASH_CHANGED", "QOS_RELIABILITY_WEAKENED",
                            "QOS_DEPTH_DECREASED", "PUB_ADDED"}),
        (CompareOptions(ignore_type_hash=True),
         {"QOS_RELIABILITY_WEAKENED", "QOS_DEPTH_DECREASED", "PUB_ADDED"}),
        (CompareOptions(ignore_qos=True), {"TYPE_HASH_CHANGED", "PUB_ADDED"}),
        (CompareOptions(ignore_qos=frozenset({"depth"})),
         {"TYPE_HASH_CHANGED", "QOS_RELIABILITY_WEAKENED", "PUB_ADDED"}),
        (CompareOptions(ignore_qos=["reliability", "depth"]),  # a list from YAML works too
         {"TYPE_HASH_CHANGED", "PUB_ADDED"}),
        (CompareOptions(allow_extra=True),
         {"TYPE_HASH_CHANGED", "QOS_RELIABILITY_WEAKENED", "QOS_DEPTH_DECREASED"}),
    ],
)
def test_options(options, remaining):
    assert {i.rule for i in compare(*mixed_change(), options)} == remaining


def test_allow_extra_drops_added_nodes_but_keeps_removals():
    items = compare({"/old": {}}, {"/new": {"publishers": [entry()]}},
                    CompareOptions(allow_extra=True))
    assert [(i.rule, i.name) for i in items] == [("NODE_REMOVED", "/old")]


def test_ignore_qos_rejects_unknown_fields():
    with pytest.raises(OptionError, match="ignore_qos: unknown QoS field.*reliabilty"):
        compare({}, {}, CompareOptions(ignore_qos=frozenset({"reliabilty"})))


# --------------------------------------------------------------------------- ordering


def big_change():
    expected = {
        "/b": {"publishers": [entry("/z"), entry("/y")], "subscriptions": [entry("/s")]},
        "/a": {"service_clients": [entry("/cli", "std_srvs/srv/Empty", qos=None)],
               "publishers": [entry("/p", qos="default")]},
        "/gone": {},
    }
    actual = {
        "/b": {"publishers": [entry("/y", type_hash=H2)], "subscriptions": [entry("/s", qos={
            "reliability": "BEST_EFFORT", "durability": "TRANSIENT_LOCAL"})]},
        "/a": {"publishers": [entry("/p", qos="sensor_data"), entry("/new")]},
        "/c": {},
    }
    return expected, actual


def test_items_sorted_by_severity_node_kind_name_change():
    items = compare(*big_change())
    assert [(i.severity.name, i.node, i.kind, i.name, i.change) for i in items] == [
        ("BREAKING", "/a", "publishers", "/p", "qos.reliability"),
        ("BREAKING", "/b", "publishers", "/y", "type_hash"),
        ("BREAKING", "/b", "publishers", "/z", "removed"),
        ("BREAKING", "/b", "subscriptions", "/s", "qos.durability"),
        ("BREAKING", "/gone", "node", "/gone", "removed"),
        ("RISKY", "/a", "publishers", "/p", "qos.depth"),
        ("RISKY", "/a", "service_clients", "/cli", "removed"),
        ("SAFE", "/a", "publishers", "/new", "added"),
        ("SAFE", "/b", "subscriptions", "/s", "qos.reliability"),
        ("SAFE", "/c", "node", "/c", "added"),
    ]


def test_order_is_deterministic_whatever_the_input_order():
    expected, actual = big_change()
    reference = compare(expected, actual)
    rng = random.Random(7)
    for _ in range(20):
        shuffled = []
        for side in (expected, actual):
            node_names = list(side)
            rng.shuffle(node_names)
            copy = {}
            for node in node_names:
                copy[node] = {kind: rng.sample(entries, len(entries))
                              for kind, entries in side[node].items()}
            shuffled.append(copy)
        assert compare(*shuffled) == reference


def test_drift_item_fields_follow_design():
    item = only(compare(nodes("publishers", entry()), {"/talker": {}}))
    assert item == DriftItem(node="/talker", kind="publishers", name="/chatter", change="removed",
                             old=entry(), new=None, rule="PUB_REMOVED", severity=BREAKING,
                             message=item.message)


def test_docs_list_every_rule_with_its_severity():
    import pathlib
    import re

    text = (pathlib.Path(__file__).parents[2] / "docs" / "drift-rules.md").read_text()
    documented = dict(re.findall(r"^\| `([A-Z_]+)` \|[^|]*\| (BREAKING|RISKY|SAFE) \|", text,
                                 flags=re.MULTILINE))
    for rule in drift.RULES.values():
        assert documented.get(rule.id) == rule.severity.name, rule.id


def test_a_comparison_without_differences_does_not_load_deepdiff():
    # deepdiff imports numpy (and its BLAS threads) when installed: a run whose contracts all
    # match should pay for neither (docs/performance.md)
    probe = (
        "import sys\n"
        "from pytest_rmw_introspect.compare import drift\n"
        "nodes = {'/n': {'publishers': [{'name': '/t', 'type': 'std_msgs/msg/String'}]}}\n"
        "assert drift.compare(nodes, nodes) == []\n"
        "print('deepdiff' in sys.modules, 'numpy' in sys.modules)\n"
        "changed = {'/n': {'publishers': [{'name': '/t', 'type': 'std_msgs/msg/Int32'}]}}\n"
        "assert [i.change for i in drift.compare(nodes, changed)] == ['type']\n"
        "print('deepdiff' in sys.modules)\n"
    )
    result = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert result.stdout.split() == ["False", "False", "True"]
