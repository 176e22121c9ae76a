"""A recording (``model.recording``) compared with contracts: what ``rmw-introspect check --bag`` finds.

A recording is the publishers of a running system seen from outside: per topic its type, type hash
(where recorded), the QoS profiles its publishers offered and how many messages were recorded, and
not which node published. So it is judged by the rules that already exist, on what it shows:

* each **publisher a contract promises** whose topic was recorded is compared with what was
  recorded by the drift rules (``compare.drift``: ``TYPE_CHANGED``, ``TYPE_HASH_CHANGED``,
  ``QOS_*`` of a publisher), under the contract's node name: the recorded profile that matches it,
  else the closest one. What a recording cannot show is taken from the contract, never drift:
  history and depth (not part of discovery), a policy the recording gives as UNKNOWN, and a policy
  the contract leaves to the middleware (SYSTEM_DEFAULT, BEST_AVAILABLE: the recording shows what
  the middleware chose);
* the recorded publishers are checked against the contracts' **subscriptions** with the
  compatibility rules (``compare.compatibility``: ``TYPE_MISMATCH``, ``TYPE_HASH_MISMATCH``,
  ``QOS_INCOMPATIBLE``, ``QOS_MAYBE_INCOMPATIBLE``), the recording as the provider;
* what the rules of a recording add (:data:`RULES`, system problems judged with ``system_fail_on``):
  a contract's publisher whose topic is not in the recording (RISKY: a recording may be of a subset
  of the topics), one whose topic was recorded without a message (RISKY: the recorder found a
  publisher, nothing was published), a recorded topic no contract declares (RISKY), and a declared
  topic the recorder found more publishers of than the contracts declare (RISKY: a node they do not
  know publishes it too; not judged where a pattern node name of ``unstable_names`` declares it,
  which stands for any number of nodes, nor for an ``external:`` topic).

Infrastructure topics (``/rosout``, ``/parameter_events``) and rosbag2's own
(``/events/write_split``) are left out unless ``include_infrastructure``; an action's hidden topics
(``<action>/_action/feedback``, ``.../status``) are known when a contract has that action.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, cast

from ..model import qos, unstable_names
from ..model.contract_shapes import ContractNode, ContractNodes, InterfaceEntry, QosFields, empty_node
from ..model.recording import RecordedTopic, Recording
from ..model.vocabulary import ACTION_LISTS, INFRASTRUCTURE_TOPICS
from . import compatibility, drift
from .compatibility import CompatItem, ContractEndpoint
from .drift import DriftItem
from .options import ComparisonOptions
from .recording_rules import RULES

#: the node that publishes in a recording: the recording does not say which one
UNKNOWN_NODE = "(unknown node)"
#: what rosbag2's recorder publishes itself
RECORDER_TOPICS = ("/events/write_split",)
#: the compatibility rules a recording's publishers meet a contract's subscriptions with
CONNECTION_RULES = frozenset({"TYPE_MISMATCH", "TYPE_HASH_MISMATCH", "QOS_INCOMPATIBLE", "QOS_MAYBE_INCOMPATIBLE"})
#: every rule a recording can be found to break (an ``accept:`` entry of another rule is not stale here)
CHECKED_RULES = frozenset(
    {"TYPE_CHANGED", "TYPE_HASH_CHANGED", "TYPE_HASH_DISTRIBUTION_CHANGED"} | CONNECTION_RULES | set(RULES)
    | {rule for rule in drift.RULES if rule.startswith("QOS_") and not rule.endswith(("_REQUEST_RAISED",
                                                                                      "_REQUEST_LOWERED"))})
_LEFT_TO_MIDDLEWARE = ("SYSTEM_DEFAULT", "BEST_AVAILABLE")
_UNSEEN = ("UNKNOWN",)


def is_left_out(name: str, options: ComparisonOptions) -> bool:
    """Infrastructure and the recorder's own topics, unless ``include_infrastructure``."""
    return not options.include_infrastructure and (name in INFRASTRUCTURE_TOPICS or name in RECORDER_TOPICS)


def _as_seen(recorded: Mapping[str, Any], promised: QosFields) -> QosFields:
    """A recorded profile in explicit form, with what the recording cannot show taken from the
    promised (contract) profile, so that only what was seen is compared."""
    seen = dict(recorded)
    for policy in ("history", "depth"):
        seen[policy] = promised[policy]
    for policy in ("reliability", "durability", "liveliness"):
        if seen.get(policy) in _UNSEEN or promised[policy] in _LEFT_TO_MIDDLEWARE:  # type: ignore[literal-required]
            seen[policy] = promised[policy]  # type: ignore[literal-required]
    for policy in qos.DURATION_FIELDS:
        if promised[policy] == qos.DURATION_BEST_AVAILABLE or policy not in seen:
            seen[policy] = promised[policy]
    seen.setdefault("avoid_ros_namespace_conventions", promised["avoid_ros_namespace_conventions"])
    return qos.expand(seen)


#: a request that no offer can fail, per policy: what a subscription's SYSTEM_DEFAULT is taken as
_NOT_JUDGED = {"reliability": "BEST_EFFORT", "durability": "VOLATILE", "liveliness": "AUTOMATIC"}


def _unjudged_defaults(entry: InterfaceEntry) -> InterfaceEntry:
    """A contract's subscription whose policies left to the middleware (SYSTEM_DEFAULT) are not
    judged against a recorded offer: the recording shows what the middleware made of the publisher's
    policy, not whether it too was left to the middleware (two such ends agree; see
    ``compatibility``'s shared system defaults)."""
    if "qos" not in entry:
        return entry
    requested = dict(qos.expand(entry["qos"]))
    for policy, weak in _NOT_JUDGED.items():
        if requested[policy] == "SYSTEM_DEFAULT":
            requested[policy] = weak
    return {**entry, "qos": cast(QosFields, requested)}


def _differences(a: QosFields, b: QosFields) -> int:
    return sum(1 for f in qos.FIELDS if a[f] != b[f])


def recorded_entry(promised: InterfaceEntry, topic: RecordedTopic) -> InterfaceEntry:
    """What the recording shows of ``promised`` (a contract's publisher of ``topic``): its type, its
    type hash where both state one, and of the offered profiles the one equal to the promised QoS,
    else the closest (fewest differing policies)."""
    entry: InterfaceEntry = {"name": topic.name, "type": topic.type}
    if topic.type_hash and promised.get("type_hash"):
        entry["type_hash"] = topic.type_hash
    if "qos" in promised and topic.qos_profiles:
        wanted = qos.expand(promised["qos"])
        seen = [_as_seen(profile, wanted) for profile in topic.qos_profiles]
        entry["qos"] = min(seen, key=lambda s: _differences(s, wanted))
    return entry


def provider_entries(recording: Recording) -> list[InterfaceEntry]:
    """The recorded publishers as contract entries: one per offered profile (one per publisher
    the recorder found), one without QoS for a topic recorded without profiles."""
    out: list[InterfaceEntry] = []
    for topic in recording.topics:
        base: InterfaceEntry = {"name": topic.name, "type": topic.type}
        if topic.type_hash:
            base["type_hash"] = topic.type_hash
        if not topic.qos_profiles:
            out.append(base)
        for profile in topic.qos_profiles:
            out.append({**base, "qos": cast(QosFields, dict(profile))})
    return out


@dataclass
class Found:
    """What one contract's nodes meet in a recording: the drift of its publishers, its system
    problems, and how many of its publishers' topics were recorded (with how many messages)."""

    drift_items: list[DriftItem]
    system_items: list[CompatItem]
    #: the contract's publishers (node, topic) whose topic is in the recording, and its count
    recorded: list[tuple[str, str, int | None]]
    #: how many of the contract's subscriptions have their topic in the recording
    subscribed: int = 0


def compare_contract(label: str, nodes: ContractNodes, recording: Recording, options: ComparisonOptions,
                     distribution: str | None = None) -> Found:
    """A contract's nodes (``label``: the contract as shown) against ``recording``; ``distribution``:
    the ROS 2 distribution the contract was captured on (a type hash that differs between it and
    the recording's is ``TYPE_HASH_DISTRIBUTION_CHANGED``, as in any check)."""
    expected: dict[str, ContractNode] = {}
    actual: dict[str, ContractNode] = {}
    system_items: list[CompatItem] = []
    recorded: list[tuple[str, str, int | None]] = []
    for fqn, node in nodes.items():
        for promised in (node or {}).get("publishers") or []:
            name = str(promised.get("name"))
            if is_left_out(name, options):
                continue
            end = ContractEndpoint(label, fqn, "publishers")
            topic = recording.topic(name)
            if topic is None:
                system_items.append(CompatItem(
                    "CONTRACT_TOPIC_NOT_RECORDED", RULES["CONTRACT_TOPIC_NOT_RECORDED"], name, end, None,
                    f"{fqn} promises to publish {name} ({promised.get('type')}), which is not in the recording "
                    f"{recording.shown}: it was not recorded (a recording of other topics), or nothing published it"))
                continue
            recorded.append((fqn, name, topic.message_count))
            if topic.message_count == 0:
                system_items.append(CompatItem(
                    "RECORDED_TOPIC_SILENT", RULES["RECORDED_TOPIC_SILENT"], name, end, None,
                    f"{fqn} promises to publish {name}; the recording {recording.shown} holds the topic (the recorder "
                    f"found {len(topic.qos_profiles) or 'a'} publisher(s)) but no message on it"))
            expected.setdefault(fqn, empty_node())["publishers"].append(promised)
            actual.setdefault(fqn, empty_node())["publishers"].append(recorded_entry(promised, topic))
    drift_items = drift.compare(expected, actual, options) if expected else []
    drift_items = drift.attribute_to_distribution(drift_items, distribution, recording.ros_distro)
    label_of_recording = f"recording {recording.shown}"
    providers: ContractNodes = {UNKNOWN_NODE: empty_node()}
    providers[UNKNOWN_NODE]["publishers"] = provider_entries(recording)
    subscribers: ContractNodes = {}
    for fqn, node in nodes.items():
        subscribers[fqn] = empty_node()
        subscribers[fqn]["subscriptions"] = [_unjudged_defaults(e) for e in (node or {}).get("subscriptions") or []]
    for item in compatibility.check_compatibility({label: subscribers, label_of_recording: providers}):
        if (item.rule in CONNECTION_RULES and item.provider is not None and item.provider.label == label_of_recording
                and not is_left_out(item.name, options)):
            system_items.append(item)
    subscribed = sum(1 for node in nodes.values() for e in (node or {}).get("subscriptions") or []
                     if recording.topic(str(e.get("name"))) is not None)
    return Found(drift_items, system_items, recorded, subscribed)


def _action_of(name: str) -> str | None:
    head, sep, tail = name.rpartition("/_action/")
    return head if sep and tail in ("feedback", "status") else None


def undeclared(recording: Recording, contracts: Sequence[tuple[str, ContractNodes]],
               external: Iterable[Mapping[str, Mapping[str, str]]], options: ComparisonOptions) -> list[CompatItem]:
    """The recorded topics that no contract's publisher declares, nor an ``external:`` block's
    publishers (an action's hidden topics: no contract's action of that name), and the declared
    ones the recorder found more publishers of than the contracts declare."""
    publishers: dict[str, list[tuple[str, str]]] = {}  # topic → (node, contract) of each declared publisher
    subscribed: dict[str, list[str]] = {}
    actions: set[str] = set()
    for label, nodes in contracts:
        for fqn, node in nodes.items():
            for e in (node or {}).get("publishers") or []:
                publishers.setdefault(str(e.get("name")), []).append((fqn, label))
            for e in (node or {}).get("subscriptions") or []:
                subscribed.setdefault(str(e.get("name")), []).append(f"{fqn} ({label})")
            for kind in ACTION_LISTS:
                actions.update(str(e.get("name")) for e in (node or {}).get(kind) or [])
    outside: set[str] = set()
    for block in external:
        outside.update((block or {}).get("publishers") or {})
    published = set(publishers) | outside
    items = []
    for topic in recording.topics:
        if topic.name in published and not is_left_out(topic.name, options) and topic.name not in outside:
            items += _extra_publishers(recording, topic, publishers.get(topic.name, []))
        if topic.name in published or is_left_out(topic.name, options) or _action_of(topic.name) in actions:
            continue
        count = "no message" if topic.message_count == 0 else (
            f"{topic.message_count} message(s)" if topic.message_count is not None else "messages")
        readers = subscribed.get(topic.name)
        tail = (f"; subscribed by {', '.join(readers)}: declare who publishes it (a node's contract, or a system "
                "contract's `external: publishers`)" if readers else
                ": a node the contracts do not know, a remapped name, or a topic to declare in a contract")
        end = ContractEndpoint(f"recording {recording.shown}", UNKNOWN_NODE, "publishers")
        items.append(CompatItem("RECORDED_TOPIC_UNDECLARED", RULES["RECORDED_TOPIC_UNDECLARED"], topic.name, end, None,
                                f"the recording holds {topic.name} ({topic.type}, {count}), which no contract's "
                                f"publisher declares{tail}"))
    return items


def _extra_publishers(recording: Recording, topic: RecordedTopic, declared: list[tuple[str, str]]) -> list[CompatItem]:
    """RECORDED_TOPIC_EXTRA_PUBLISHER when the recorder found more publishers of ``topic`` (one
    offered QoS profile each) than ``declared`` ((node, contract) of each publisher the contracts
    declare). Fewer is no finding: rosbag2 keeps the profiles of the publishers it found when it
    subscribed, not of those that came later. A pattern node name stands for any number of nodes."""
    if (not declared or len(topic.qos_profiles) <= len(declared)
            or any(unstable_names.is_pattern_key(fqn) for fqn, _ in declared)):
        return []
    end = ContractEndpoint(f"recording {recording.shown}", UNKNOWN_NODE, "publishers")
    named = ", ".join(f"{fqn} ({label})" for fqn, label in declared)
    return [CompatItem(
        "RECORDED_TOPIC_EXTRA_PUBLISHER", RULES["RECORDED_TOPIC_EXTRA_PUBLISHER"], topic.name, end, None,
        f"the recorder found {len(topic.qos_profiles)} publishers of {topic.name} ({topic.type}); the contracts declare "
        f"{len(declared)}: {named}. A node they do not know publishes it too (a node started by hand, a "
        "second instance, a remapping onto this name): give it a contract, or declare it in a system contract's "
        "`external: publishers`")]
