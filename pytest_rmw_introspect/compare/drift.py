"""Compare expected (contract) and actual (capture) contract nodes → classified DriftItems.

The structural diff is DeepDiff's; this module prepares both sides so that equal interfaces
compare equal (QoS expanded, interfaces keyed by name) and then judges every difference from the
side of the node's peers: publishers and servers *offer*, subscriptions and clients *request*.
Parameters and lifecycle states are judged in ``compare.parameter_drift`` (from the side of
whoever sets the parameters and drives the node). The rule table, with the reasoning behind each
severity, is docs/drift-rules.md.
"""

from __future__ import annotations

import dataclasses
import json
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from ..errors import OptionError
from ..model import middlewares, qos, tally, untrusted
from ..model import types as type_model
from ..model.contract_shapes import ContractNode, InterfaceEntry
from ..model.vocabulary import (
    ACTION_HASHED_PARTS,
    DESTROYED_AT,
    LABELS,
    LISTS,
    PARAMETERS,
    PROVIDER_OF,
    SERVICE_LISTS,
    TOPIC_LISTS,
    Severity,
)
from . import destruction_drift, parameter_drift, type_drift
from .options import ComparisonOptions

if TYPE_CHECKING:
    from deepdiff import DeepDiff


@dataclass(frozen=True)
class DriftItem:
    node: str  # fully qualified node name
    kind: str  # one of LISTS, "parameters", or "node"
    name: str  # interface or parameter name (node fqn for kind == "node")
    # "added" | "removed" | "renamed" | "type" | "type_hash" | "qos.<field>" | "type:<type name>" | "types";
    # a parameter's attribute (parameter_drift.ATTRIBUTES); "lifecycle" or "parameters" (kind "node");
    # "destroyed_at" (when the program destroys it: kind "node" or a list; destruction_drift)
    change: str
    old: Any  # contract side (None for added)
    new: Any  # capture side (None for removed)
    rule: str  # stable rule id, see RULES
    severity: Severity
    message: str  # one line for people
    #: where the project set this rule's level (``compare.rule_levels``: the option ``rules``); None: its default
    level_set_by: str | None = None

    def __post_init__(self) -> None:
        tally.note("rule", self.rule)  # the test suite's exercised set (model.tally; issue 48)


@dataclass(frozen=True)
class Rule:
    id: str
    severity: Severity
    summary: str  # what changed, for the docs and --help texts


def _rules(*rules: Rule) -> dict[str, Rule]:
    return {rule.id: rule for rule in rules}


_B, _R, _S = Severity.BREAKING, Severity.RISKY, Severity.SAFE

# Presence rules: (kind, "added"/"removed") → rule id.
_PRESENCE: dict[tuple[str, str], str] = {
    ("node", "removed"): "NODE_REMOVED",
    ("node", "added"): "NODE_ADDED",
    ("publishers", "removed"): "PUB_REMOVED",
    ("publishers", "added"): "PUB_ADDED",
    ("subscriptions", "removed"): "SUB_REMOVED",
    ("subscriptions", "added"): "SUB_ADDED",
    ("service_servers", "removed"): "SERVICE_SERVER_REMOVED",
    ("service_servers", "added"): "SERVICE_SERVER_ADDED",
    ("service_clients", "removed"): "SERVICE_CLIENT_REMOVED",
    ("service_clients", "added"): "SERVICE_CLIENT_ADDED",
    ("action_servers", "removed"): "ACTION_SERVER_REMOVED",
    ("action_servers", "added"): "ACTION_SERVER_ADDED",
    ("action_clients", "removed"): "ACTION_CLIENT_REMOVED",
    ("action_clients", "added"): "ACTION_CLIENT_ADDED",
}

# QoS policies that decide matching, with the rule-id stem and a word for people.
_MATCHING_POLICIES: dict[str, tuple[str, str]] = {
    "reliability": ("RELIABILITY", "reliability"),
    "durability": ("DURABILITY", "durability"),
    "deadline_ns": ("DEADLINE", "deadline"),
    "liveliness": ("LIVELINESS", "liveliness"),
    "liveliness_lease_duration_ns": ("LEASE_DURATION", "liveliness lease duration"),
}

RULES: dict[str, Rule] = _rules(
    Rule("NODE_REMOVED", _B, "node removed"),
    Rule("NODE_ADDED", _S, "node added"),
    Rule("PUB_REMOVED", _B, "publisher removed"),
    Rule("PUB_ADDED", _S, "publisher added"),
    Rule("SUB_REMOVED", _R, "subscription removed"),
    Rule("SUB_ADDED", _R, "subscription added"),
    Rule("SERVICE_SERVER_REMOVED", _B, "service server removed"),
    Rule("SERVICE_SERVER_ADDED", _S, "service server added"),
    Rule("SERVICE_CLIENT_REMOVED", _R, "service client removed"),
    Rule("SERVICE_CLIENT_ADDED", _R, "service client added"),
    Rule("ACTION_SERVER_REMOVED", _B, "action server removed"),
    Rule("ACTION_SERVER_ADDED", _S, "action server added"),
    Rule("ACTION_CLIENT_REMOVED", _R, "action client removed"),
    Rule("ACTION_CLIENT_ADDED", _R, "action client added"),
    *(Rule(f"{stem}_RENAMED", _B, f"{LABELS[kind]} renamed (one removed, one of the same type added)")
      for kind, stem in (("publishers", "PUB"), ("subscriptions", "SUB"), ("service_servers", "SERVICE_SERVER"),
                         ("service_clients", "SERVICE_CLIENT"), ("action_servers", "ACTION_SERVER"),
                         ("action_clients", "ACTION_CLIENT"))),
    Rule("TYPE_CHANGED", _B, "interface type name changed"),
    Rule("TYPE_HASH_CHANGED", _B, "type definition changed under the same type name"),
    Rule("TYPE_HASH_DISTRIBUTION_CHANGED", _R,
         "type hash differs, and the two sides were captured on different ROS 2 distributions"),
    *(
        rule
        for stem, word in _MATCHING_POLICIES.values()
        for rule in (
            Rule(f"QOS_{stem}_WEAKENED", _B, f"publisher offers weaker {word}"),
            Rule(f"QOS_{stem}_STRENGTHENED", _S, f"publisher offers stronger {word}"),
            Rule(f"QOS_{stem}_REQUEST_RAISED", _B, f"subscription requests stronger {word}"),
            Rule(f"QOS_{stem}_REQUEST_LOWERED", _S, f"subscription requests weaker {word}"),
        )
    ),
    # only enum policies have a SYSTEM_DEFAULT / UNKNOWN that can resolve either way
    *(
        Rule(f"QOS_{_MATCHING_POLICIES[f][0]}_UNCERTAIN", _R,
             f"{_MATCHING_POLICIES[f][1]} changed to or from SYSTEM_DEFAULT / UNKNOWN")
        for f in ("reliability", "durability", "liveliness")
    ),
    Rule("QOS_HISTORY_CHANGED", _R, "history kind changed"),
    Rule("QOS_DEPTH_DECREASED", _R, "queue depth decreased"),
    Rule("QOS_DEPTH_INCREASED", _S, "queue depth increased"),
    Rule("QOS_DEPTH_UNCERTAIN", _R, "queue depth changed to or from the system default (0)"),
    Rule("QOS_LIFESPAN_SHORTENED", _R, "publisher lifespan shortened"),
    Rule("QOS_LIFESPAN_EXTENDED", _S, "publisher lifespan extended or unset"),
    Rule("QOS_LIFESPAN_NO_EFFECT", _S, "subscription lifespan changed (a publisher-only policy)"),
    Rule("QOS_NAMESPACE_CONVENTIONS_CHANGED", _B, "avoid_ros_namespace_conventions changed"),
    Rule("SERVICE_QOS_CHANGED", _B, "a service server's or client's reliability, durability, deadline or liveliness "
         "changed"),
    Rule("TYPE_DESCRIPTION_MISSING", _S, "the contract's types: section lacks a type the interface uses"),
    Rule("TYPE_LOCK_CHANGED", _B, "a type an interface uses, or one it nests, differs from the package's type lock"),
    Rule("TYPE_NOT_LOCKED", _R, "an interface uses a type the package's type lock does not list"),
    *(Rule(rule_id, severity, summary) for rule_id, (severity, summary) in type_drift.RULES.items()),
    *(Rule(rule_id, severity, summary) for rule_id, (severity, summary) in parameter_drift.RULES.items()),
    *(Rule(rule_id, severity, summary) for rule_id, (severity, summary) in destruction_drift.RULES.items()),
    # the gate of `diff --against REF`: interface versions (compare.versioning), consumers (compare.consumers)
    Rule("INTERFACE_VERSION_BUMP_MISSING", _B, "a BREAKING change without a MAJOR bump of `interface_version`, or a "
         "RISKY change without at least a MINOR bump"),
    Rule("INTERFACE_VERSION_DECREASED", _B, "`interface_version` is lower than at the base revision"),
    Rule("CONSUMER_INCOMPATIBLE", _B, "a changed interface no longer fits a node of a system contract that uses it"),
)

#: ``DriftItem.change`` of a field-level item: the prefix, then the type it is about
TYPE_CHANGE_PREFIX = "type:"


# --------------------------------------------------------------------------- comparison


def compare(
    expected_nodes: Mapping[str, ContractNode] | None,
    actual_nodes: Mapping[str, ContractNode] | None,
    options: ComparisonOptions | None = None,
    *,
    expected_types: Mapping[str, type_model.TypeDescription] | None = None,
    actual_types: Mapping[str, type_model.TypeDescription] | None = None,
    require_types: bool = False,
) -> list[DriftItem]:
    """Classified differences between the contract's nodes and the captured nodes.

    Both sides are ``nodes`` mappings of contracts (design.md section 2); QoS may be in contract
    form or explicit. Missing lists or keys are tolerated: a key absent on either side of an
    interface (e.g. no ``type_hash`` in a hand-written contract) is not compared.
    ``expected_types`` / ``actual_types``: the type descriptions of each side (a contract's
    ``types:`` section, a capture's table; None: not stated). When both describe the types of
    an interface present on both sides with one type name, every difference in them is an item
    of that interface (``compare.type_drift``: fields, constants, nested types included), and
    its ``TYPE_HASH_CHANGED`` message says whether the descriptions explain it. ``require_types``
    (``include_types``): an interface whose types the expected side does not describe, while
    the actual side does, is drift (``TYPE_DESCRIPTION_MISSING``), so that updating the golden
    writes them.
    Items come most severe first, then by node, kind, name and change.
    """
    options = options or ComparisonOptions()
    ignored_qos = _ignored_qos_fields(options.ignore_qos)
    # Indexing and diffing make many objects and no cycles (see untrusted.gc_paused).
    with untrusted.gc_paused():
        expected = _index(expected_nodes)
        actual = _index(actual_nodes)
        _drop_one_sided_keys(expected, actual)

        expected_differing, actual_differing = _differing(expected, actual)
        # the common case, nothing differs, needs no structural diff (nor deepdiff's import)
        items = ([] if expected_differing == actual_differing else
                 _translate(_deep_diff(expected_differing, actual_differing), expected, actual))
    items = _with_type_items(items, expected, actual, expected_types, actual_types, require_types)
    items += _parameter_and_lifecycle_items(expected_nodes or {}, actual_nodes or {}, options)
    items += _destruction_items(expected_nodes or {}, actual_nodes or {}, expected, actual)

    def wanted(item: DriftItem) -> bool:
        if options.allow_extra and item.change == "added":
            return False
        if options.ignore_type_hash and item.change == "type_hash":
            return False
        if item.change.startswith("qos.") and item.change[4:] in ignored_qos:
            return False
        return True

    # a rename brings the other changes of the endpoint along: the options apply to them too
    items = _pair_renames(list(filter(wanted, items)))
    return sorted(_for_middleware(filter(wanted, items), options.rmw), key=_sort_key)


def attribute_to_distribution(items: list[DriftItem], expected: str | None, actual: str | None) -> list[DriftItem]:
    """``items`` with each ``TYPE_HASH_CHANGED`` said to be ``TYPE_HASH_DISTRIBUTION_CHANGED``
    when the two sides were captured on different ROS 2 distributions (``expected``: the
    contract's ``ros_distribution``, ``actual``: the capture's; either None: unknown, nothing
    changes). A distribution may redefine a message (a field added to a standard type): the hash
    then differs for every package, not because of this one. The item stays visible (RISKY:
    peers on the two distributions cannot exchange that type), and its message says which
    distributions and how to tell the two causes apart."""
    if not expected or not actual or expected == actual:
        return items
    out = [
        dataclasses.replace(
            item, rule="TYPE_HASH_DISTRIBUTION_CHANGED", severity=RULES["TYPE_HASH_DISTRIBUTION_CHANGED"].severity,
            message=(f"{item.message} between ROS 2 {expected} (the contract) and {actual} (this run): the "
                     f"{actual} definition differs from {expected}'s; a change of the type in your own packages "
                     f"looks the same, so check on {expected} to tell them apart"))
        if item.rule == "TYPE_HASH_CHANGED" else item
        for item in items
    ]
    return sorted(out, key=_sort_key)


_RENAME_RULE = {
    "publishers": "PUB_RENAMED", "subscriptions": "SUB_RENAMED", "service_servers": "SERVICE_SERVER_RENAMED",
    "service_clients": "SERVICE_CLIENT_RENAMED", "action_servers": "ACTION_SERVER_RENAMED",
    "action_clients": "ACTION_CLIENT_RENAMED", PARAMETERS: "PARAM_RENAMED",
}
_RENAME_EFFECT = {
    "publishers": "subscribers of {old} stop receiving data",
    "subscriptions": "the node no longer receives what is published on {old}",
    "service_servers": "clients of {old} get no answer",
    "service_clients": "the node no longer calls the server of {old}",
    "action_servers": "action clients of {old} get no answer",
    "action_clients": "the node no longer sends goals to {old}",
    PARAMETERS: "launch files, parameter files and -p overrides of {old} are silently ignored",
}


def _pair_renames(items: list[DriftItem]) -> list[DriftItem]:
    """One interface removed and one of the same kind and type added in the same node read as a
    rename: one item naming both (still BREAKING), plus every other change between the two
    entries (type hash, QoS) under the new name, so that the rename hides nothing. When a node
    lost exactly one requesting interface of a kind (subscription, client) and gained exactly
    one of another type, that is a rename and a retype: the rename item and ``TYPE_CHANGED`` (a subscription renamed and retyped
    is as severe as one only renamed). Ambiguous cases (two removed or two added of that type)
    stay separate items."""
    slots: dict[tuple[str, str, Any], dict[str, list[DriftItem]]] = {}
    for item in items:
        if item.kind == "node" or item.change not in ("removed", "added"):
            continue
        entry = item.old if item.change == "removed" else item.new
        type_name = entry.get("type") if isinstance(entry, Mapping) else None
        if type_name:
            slots.setdefault((item.node, item.kind, type_name), {"removed": [], "added": []})[item.change].append(item)
    pairs: list[tuple[DriftItem, DriftItem]] = []
    for sides in slots.values():
        if len(sides["removed"]) == 1 and len(sides["added"]) == 1:
            pairs.append((sides["removed"][0], sides["added"][0]))
    paired_ids = {id(i) for pair in pairs for i in pair}
    # what is left per node and interface list: one removed and one added of other types
    left: dict[tuple[str, str], dict[str, list[DriftItem]]] = {}
    for item in items:
        # requesters only: a removed offer is BREAKING already, a removed and an added request
        # are RISKY each, though together they are a rename (BREAKING) and a retype
        if item.kind in PROVIDER_OF and item.change in ("removed", "added") and id(item) not in paired_ids:
            left.setdefault((item.node, item.kind), {"removed": [], "added": []})[item.change].append(item)
    for sides in left.values():
        if len(sides["removed"]) == 1 and len(sides["added"]) == 1:
            pairs.append((sides["removed"][0], sides["added"][0]))
    out = [i for i in items if id(i) not in {id(i) for pair in pairs for i in pair}]
    for removed, added in pairs:
        out += _renamed(removed, added)
    return out


def _renamed(removed: DriftItem, added: DriftItem) -> list[DriftItem]:
    node, kind = removed.node, removed.kind
    rule = RULES[_RENAME_RULE[kind]]
    effect = _RENAME_EFFECT[kind].format(old=removed.name)
    old_type, new_type = removed.old.get("type"), added.new.get("type")
    same = f"same type {old_type}" if old_type == new_type else f"and retyped from {old_type} to {new_type}"
    items = [DriftItem(
        node=node, kind=kind, name=removed.name, change="renamed", old=removed.old, new=added.new,
        rule=rule.id, severity=rule.severity,
        message=f"{LABELS[kind]} {removed.name} looks renamed to {added.name} ({same}): {effect}",
    )]
    if kind not in LISTS:
        return items
    old, new = _compared(node, kind, removed.old), _compared(node, kind, added.new)
    attributes: set[str] = {key for key in ("type", "type_hash") if key in old and key in new and old[key] != new[key]}
    if "qos" in old and "qos" in new:
        attributes |= {f"qos.{f}" for f in old["qos"] if old["qos"][f] != new["qos"].get(f)}
    if "type" in attributes:
        attributes.discard("type_hash")
    if "qos.history" in attributes:
        attributes.discard("qos.depth")
    items += [_change_item(node, kind, added.name, attribute, old, new) for attribute in sorted(attributes)]
    return items


def _ignored_qos_fields(ignore_qos: bool | Iterable[str]) -> frozenset[str]:
    if ignore_qos is True:
        return frozenset(qos.FIELDS)
    if ignore_qos is False or ignore_qos is None:
        return frozenset()
    fields = frozenset(ignore_qos)
    unknown = sorted(fields - set(qos.FIELDS))
    if unknown:
        raise OptionError(
            f"ignore_qos: unknown QoS field(s) {', '.join(unknown)}; "
            f"expected some of {', '.join(qos.FIELDS)}"
        )
    return fields


@dataclass
class _Interface:
    original: InterfaceEntry  # the entry as given, for added/removed items
    compared: dict[str, Any] = field(default_factory=dict)  # type, type_hash, qos (explicit)


# node → kind → key → _Interface
_Index = dict[str, dict[str, dict[str, _Interface]]]


def _index(nodes: Mapping[str, ContractNode] | None) -> _Index:
    index: _Index = {}
    for node_name, node in (nodes or {}).items():
        node = node or ContractNode()
        index[node_name] = {
            kind: _keyed_interfaces(node_name, kind, node.get(kind) or []) for kind in LISTS
        }
    return index


def _keyed_interfaces(node: str, kind: str, entries: Iterable[InterfaceEntry]) -> dict[str, _Interface]:
    by_name: dict[str | None, list[_Interface]] = {}
    for entry in entries:
        by_name.setdefault(entry.get("name"), []).append(_Interface(entry, _compared(node, kind, entry)))
    keyed: dict[Any, _Interface] = {}  # a nameless entry (a hand-written contract) is keyed None
    for name, interfaces in by_name.items():
        # The same name twice in one list (e.g. two publishers on one topic) stays visible:
        # "/chatter", "/chatter [2]", ... in a deterministic order.
        interfaces.sort(key=lambda i: json.dumps(i.compared, sort_keys=True, default=str))
        for number, interface in enumerate(interfaces, start=1):
            keyed[name if number == 1 else f"{name} [{number}]"] = interface
    return keyed


def _compared(node: str, kind: str, entry: InterfaceEntry) -> dict[str, Any]:
    """What is compared of an entry, as plain data for DeepDiff: ``type``, ``type_hash`` and the
    explicit ``qos``, those the entry states."""
    compared: dict[str, Any] = {}
    if entry.get("type") is not None:
        compared["type"] = entry["type"]
    if entry.get("type_hash") is not None:
        compared["type_hash"] = entry["type_hash"]
    if kind in TOPIC_LISTS and entry.get("qos") is not None:
        try:
            compared["qos"] = qos.expand(entry["qos"])
        except ValueError as error:
            raise ValueError(f"{node} {LABELS[kind]} {entry.get('name')}: {error}") from None
    elif kind in SERVICE_LISTS:
        compared["qos"] = _service_qos(node, kind, entry)
    return compared


def _drop_one_sided_keys(expected: _Index, actual: _Index) -> None:
    """What one side does not state is not compared (hand-written contracts, older distros)."""
    for node, kinds in expected.items():
        for kind, interfaces in kinds.items():
            for key, interface in interfaces.items():
                other = actual.get(node, {}).get(kind, {}).get(key)
                if other is None:
                    continue
                for attribute in set(interface.compared) ^ set(other.compared):
                    interface.compared.pop(attribute, None)
                    other.compared.pop(attribute, None)


def _deep_diff(expected_differing: dict, actual_differing: dict) -> DeepDiff:
    # Imported here, not at the top: deepdiff costs ~0.1-0.2 s (with numpy, which it imports
    # when it is installed, and numpy's BLAS threads) and only a difference needs it.
    from deepdiff import DeepDiff

    return DeepDiff(
        expected_differing,
        actual_differing,
        view="tree",
        # compare every level however different: the default reports a whole mapping as
        # changed when few keys are shared, which would hide the per-interface changes
        threshold_to_diff_deeper=0,
    )


def _differing(expected: _Index, actual: _Index) -> tuple[dict, dict]:
    """Both sides as plain data for DeepDiff, without the interfaces that compare equal: they
    cannot produce an item, and leaving them out keeps a diff of large contracts linear in
    what changed rather than in their size (DeepDiff copies a path object per level)."""
    left: dict = {}
    right: dict = {}
    for node in _union(expected, actual):
        if node not in expected or node not in actual:
            (left if node in expected else right)[node] = _plain((expected if node in expected else actual)[node])
            continue
        left[node], right[node] = {}, {}
        for kind in _union(expected[node], actual[node]):
            mine, theirs = expected[node].get(kind, {}), actual[node].get(kind, {})
            left[node][kind] = {k: i.compared for k, i in mine.items()
                                if k not in theirs or theirs[k].compared != i.compared}
            right[node][kind] = {k: i.compared for k, i in theirs.items()
                                 if k not in mine or mine[k].compared != i.compared}
    return left, right


def _union(first: Mapping[str, Any], second: Mapping[str, Any]) -> list[str]:
    """The keys of both, in order (DeepDiff reports in the order it meets them)."""
    return list(first) + [key for key in second if key not in first]


def _plain(kinds: Mapping[str, Mapping[str, _Interface]]) -> dict:
    return {kind: {key: interface.compared for key, interface in interfaces.items()}
            for kind, interfaces in kinds.items()}


def _translate(diff: DeepDiff, expected: _Index, actual: _Index) -> list[DriftItem]:
    """DeepDiff's report → DriftItems. Paths are [node, kind, key, attribute, detail...]."""
    items: list[DriftItem] = []
    changed: dict[tuple[str, str, str], set[str]] = {}  # interface → changed attributes
    for report_type in diff:
        for level in diff[report_type]:
            path = level.path(output_format="list")
            if len(path) == 1:
                items += _node_presence_items(path[0], expected, actual)
            elif len(path) == 3:
                node, kind, key = path
                if key in actual.get(node, {}).get(kind, {}):
                    entry = actual[node][kind][key].original
                    items.append(_presence_item(node, kind, key, "added", entry))
                else:
                    entry = expected[node][kind][key].original
                    items.append(_presence_item(node, kind, key, "removed", entry))
            elif len(path) >= 4:
                node, kind, key, attribute = path[:4]
                detail = f"qos.{path[4]}" if attribute == "qos" and len(path) > 4 else attribute
                changed.setdefault((node, kind, key), set()).add(detail)

    for (node, kind, key), attributes in changed.items():
        old = expected[node][kind][key].compared
        new = actual[node][kind][key].compared
        # consequences of a bigger change are not separate drift
        if "type" in attributes:
            attributes.discard("type_hash")
        if "qos.history" in attributes:
            attributes.discard("qos.depth")
        for attribute in attributes:
            items.append(_change_item(node, kind, key, attribute, old, new))
    return items


def _with_type_items(
    items: list[DriftItem],
    expected: _Index,
    actual: _Index,
    expected_types: Mapping[str, type_model.TypeDescription] | None,
    actual_types: Mapping[str, type_model.TypeDescription] | None,
    require_types: bool,
) -> list[DriftItem]:
    """``items`` plus what the type descriptions say about the interfaces both sides have with
    one type name; a ``TYPE_HASH_CHANGED`` message says whether the descriptions explain it."""
    out = list(items)
    hash_items = {(i.node, i.kind, i.name): n for n, i in enumerate(out) if i.rule == "TYPE_HASH_CHANGED"}
    for node, kinds in expected.items():
        for kind, interfaces in kinds.items():
            for key, interface in interfaces.items():
                other = actual.get(node, {}).get(kind, {}).get(key)
                type_name = interface.original.get("type")
                if other is None or not type_name or other.original.get("type") != type_name:
                    continue
                roots = type_model.interface_roots(kind, type_name)
                if require_types and actual_types is not None:
                    missing = [n for n in type_model.closure(actual_types, roots) if n not in (expected_types or {})]
                    if missing:
                        out.append(_item(
                            node, kind, key, "types", None, missing, "TYPE_DESCRIPTION_MISSING",
                            f"the contract's types: section does not describe {', '.join(missing)} "
                            "(include_types is on): updating the golden writes it"))
                if expected_types is None or actual_types is None:
                    continue
                described = all(r in expected_types and r in actual_types for r in roots)
                changes = type_drift.compare_tables(expected_types, actual_types, roots) if described else []
                out += [_item(node, kind, key, TYPE_CHANGE_PREFIX + c.type_name, c.old, c.new, c.rule, c.message)
                        for c in changes]
                index = hash_items.get((node, kind, key))
                if index is not None and described:
                    hash_item = out[index]
                    explained = (f"; the types: section shows how ({len(changes)} field-level "
                                 f"change{'s' if len(changes) != 1 else ''} listed under this interface)"
                                 if changes else
                                 "; the recorded type descriptions show no difference (a change they do not "
                                 "hold, or a types: section older than the type hash)")
                    out[index] = dataclasses.replace(hash_item, message=hash_item.message + explained)
    return out


def _node_presence_items(node: str, expected: _Index, actual: _Index) -> list[DriftItem]:
    """A node added or removed, followed by each of its interfaces."""
    change, side = ("added", actual) if node in actual else ("removed", expected)
    node_entry = {kind: [i.original for i in side[node][kind].values()] for kind in LISTS}
    items = [_presence_item(node, "node", node, change, node_entry)]
    for kind in LISTS:
        for key, interface in side[node][kind].items():
            items.append(_presence_item(node, kind, key, change, interface.original))
    return items


def _parameter_and_lifecycle_items(expected_nodes: Mapping[str, ContractNode], actual_nodes: Mapping[str, ContractNode],
                                   options: ComparisonOptions) -> list[DriftItem]:
    """``compare.parameter_drift`` on the nodes both sides have. The parameters of a node added
    or removed are not items of their own: they have no peers, and setting them goes with
    launching the node (consequences of a bigger change are not separate drift)."""
    items = []
    for node in sorted(set(expected_nodes) & set(actual_nodes)):
        old, new = expected_nodes[node] or ContractNode(), actual_nodes[node] or ContractNode()
        changes = [*parameter_drift.compare_lifecycle(node, old, new),
                   *parameter_drift.compare_parameters(node, old, new, options)]
        items += [_item(node, c.kind, c.name, c.change, c.old, c.new, c.rule, c.message) for c in changes]
    return items


def _destruction_items(expected_nodes: Mapping[str, ContractNode], actual_nodes: Mapping[str, ContractNode],
                       expected: _Index, actual: _Index) -> list[DriftItem]:
    """``compare.destruction_drift`` on the nodes, and their interfaces, both sides have."""
    items = []
    for node in sorted(set(expected) & set(actual)):
        both = ((kind, key, interface.original, actual[node][kind][key].original)
                for kind in LISTS for key, interface in expected[node][kind].items()
                if key in actual[node][kind])
        changes = destruction_drift.compare_node(node, expected_nodes[node] or ContractNode(),
                                                 actual_nodes[node] or ContractNode(), both)
        items += [_item(node, c.kind, c.name, DESTROYED_AT, c.old, c.new, c.rule, c.message) for c in changes]
    return items


_PRESENCE_MESSAGES: dict[str, str] = {
    "NODE_REMOVED": "node removed: anything addressing {name} by name (parameters, remappings, "
    "launch files) breaks",
    "NODE_ADDED": "new node {name}",
    "PUB_REMOVED": "publisher removed: subscriptions to {name} ({type}) no longer receive data",
    "PUB_ADDED": "new publisher on {name} ({type}): nothing existing depends on it",
    "SUB_REMOVED": "subscription removed: publishers still work, but the node no longer "
    "reacts to {name}",
    "SUB_ADDED": "new subscription to {name}: the node now needs a publisher of {type}",
    "SERVICE_SERVER_REMOVED": "service server removed: clients of {name} ({type}) get no answer",
    "SERVICE_SERVER_ADDED": "new service {name} ({type}): nothing existing depends on it",
    "SERVICE_CLIENT_REMOVED": "service client removed: the server still works, but the node "
    "no longer calls {name}",
    "SERVICE_CLIENT_ADDED": "new service client of {name}: the node now needs a server of {type}",
    "ACTION_SERVER_REMOVED": "action server removed: clients of {name} ({type}) get no answer",
    "ACTION_SERVER_ADDED": "new action server {name} ({type}): nothing existing depends on it",
    "ACTION_CLIENT_REMOVED": "action client removed: the server still works, but the node no "
    "longer sends goals to {name}",
    "ACTION_CLIENT_ADDED": "new action client of {name}: the node now needs an action server "
    "of {type}",
}


def _presence_item(node: str, kind: str, key: str, change: str, entry: Any) -> DriftItem:
    rule = RULES[_PRESENCE[(kind, change)]]
    type_name = (entry.get("type") if kind != "node" else None) or "an unstated type"
    message = _PRESENCE_MESSAGES[rule.id].format(name=key, type=type_name)
    return DriftItem(
        node=node,
        kind=kind,
        name=key,
        change=change,
        old=entry if change == "removed" else None,
        new=entry if change == "added" else None,
        rule=rule.id,
        severity=rule.severity,
        message=message,
    )


def _item(node, kind, name, change, old, new, rule_id, message) -> DriftItem:
    rule = RULES[rule_id]
    return DriftItem(node, kind, name, change, old, new, rule.id, rule.severity, message)


def _change_item(node: str, kind: str, key: str, attribute: str, old: dict, new: dict) -> DriftItem:
    if attribute == "type":
        return _item(node, kind, key, "type", old["type"], new["type"], "TYPE_CHANGED",
                     f"type changed from {old['type']} to {new['type']}: peers of the old "
                     "type no longer match")
    if attribute == "type_hash":
        return _item(node, kind, key, "type_hash", old["type_hash"], new["type_hash"],
                     "TYPE_HASH_CHANGED", _type_hash_message(new.get("type", old.get("type")),
                                                             old["type_hash"], new["type_hash"]))
    if attribute.startswith("qos."):
        field_name = attribute[4:]
        return _qos_item(node, kind, key, field_name, old["qos"][field_name],
                         new["qos"][field_name])
    raise AssertionError(f"unexpected drift path {attribute!r}")  # pragma: no cover


def _type_hash_message(type_name: str | None, old: Any, new: Any) -> str:
    type_name = type_name or "the interface type"
    if isinstance(old, Mapping) and isinstance(new, Mapping):
        parts = sorted(
            (key for key in set(old) | set(new) if old.get(key) != new.get(key)),
            key=lambda key: (list(ACTION_HASHED_PARTS).index(key) if key in ACTION_HASHED_PARTS
                             else len(ACTION_HASHED_PARTS), key),
        )
        described = ", ".join(
            f"{ACTION_HASHED_PARTS[p]} ({p})" if p in ACTION_HASHED_PARTS else p for p in parts
        )
        return f"action definition of {type_name} changed: {described}"
    return f"message definition of {type_name} changed"


# --------------------------------------------------------------------------- QoS judgement

_ENUM_RANKS: dict[str, dict[str, int]] = {
    "reliability": {"BEST_EFFORT": 0, "RELIABLE": 1},
    "durability": {"VOLATILE": 0, "TRANSIENT_LOCAL": 1},
    "liveliness": {"AUTOMATIC": 0, "MANUAL_BY_TOPIC": 1},
}
_INF = float("inf")


def _strength(field_name: str, value: Any, offering: bool) -> tuple[float, float]:
    """How much a value offers (publisher) or demands (subscription), as an interval.

    SYSTEM_DEFAULT / UNKNOWN may resolve to any value: the whole range. BEST_AVAILABLE adapts to
    the peers at creation, so it is the strongest offer and the weakest demand. Durations:
    shorter = stronger, unset = weakest.
    """
    if value == "BEST_AVAILABLE" or value == qos.DURATION_BEST_AVAILABLE:
        return (_INF, _INF) if offering else (-_INF, -_INF)
    if field_name in _ENUM_RANKS:
        ranks = _ENUM_RANKS[field_name]
        if value in ranks:
            return ranks[value], ranks[value]
        return min(ranks.values()), max(ranks.values())
    if value in (qos.DURATION_UNSPECIFIED, qos.DURATION_INFINITE):
        return -_INF, -_INF
    return -value, -value


def _qos_item(node: str, kind: str, key: str, field_name: str, old: Any, new: Any) -> DriftItem:
    change = f"qos.{field_name}"
    old_text, new_text = qos.format_value(field_name, old), qos.format_value(field_name, new)
    offering = kind == "publishers"

    def item(rule_id: str, message: str) -> DriftItem:
        return _item(node, kind, key, change, old, new, rule_id, message)

    if kind in SERVICE_LISTS:
        word = _MATCHING_POLICIES[field_name][1]
        return item("SERVICE_QOS_CHANGED", f"service {word} {old_text} -> {new_text}: a DDS middleware serves a "
                    f"client only when its {word} and the server's agree (requests one way, responses the other): "
                    f"peers with the old {word} are no longer served")
    if field_name in _MATCHING_POLICIES:
        stem, word = _MATCHING_POLICIES[field_name]
        old_low, old_high = _strength(field_name, old, offering)
        new_low, new_high = _strength(field_name, new, offering)
        transition = f"{word} {old_text} -> {new_text}"
        if offering and new_low >= old_high:
            return item(f"QOS_{stem}_STRENGTHENED", f"publisher offers stronger {transition}: "
                        "every subscription that matched still matches")
        if offering and new_high < old_low:
            return item(f"QOS_{stem}_WEAKENED", f"publisher offers weaker {transition}: "
                        "subscriptions requesting more no longer match")
        if not offering and new_high <= old_low:
            return item(f"QOS_{stem}_REQUEST_LOWERED", f"subscription requests less {transition}: "
                        "every publisher that matched still matches")
        if not offering and new_low > old_high:
            return item(f"QOS_{stem}_REQUEST_RAISED", f"subscription requests more {transition}: "
                        "publishers offering less no longer match")
        return item(f"QOS_{stem}_UNCERTAIN", f"{transition}: depends on the middleware's system "
                    "default; peers may match differently")

    if field_name == "history":
        return item("QOS_HISTORY_CHANGED", f"history {old_text} -> {new_text}: queueing "
                    "behaviour changes (KEEP_ALL can block or grow without bound)")
    if field_name == "depth":
        if 0 in (old, new):
            return item("QOS_DEPTH_UNCERTAIN", f"depth {old_text} -> {new_text}: 0 means the "
                        "middleware's default depth")
        if new < old:
            return item("QOS_DEPTH_DECREASED", f"depth {old_text} -> {new_text}: fewer samples "
                        "are queued (or replayed to late joiners); bursts may drop messages")
        return item("QOS_DEPTH_INCREASED", f"depth {old_text} -> {new_text}: more samples are "
                    "queued; matching is unaffected")
    if field_name == "lifespan_ns":
        if not offering:
            return item("QOS_LIFESPAN_NO_EFFECT", f"lifespan {old_text} -> {new_text}: lifespan "
                        "only acts on publishers")
        if _strength(field_name, new, True)[0] > _strength(field_name, old, True)[0]:
            return item("QOS_LIFESPAN_SHORTENED", f"lifespan {old_text} -> {new_text}: samples "
                        "expire sooner, late joiners may get fewer")
        return item("QOS_LIFESPAN_EXTENDED", f"lifespan {old_text} -> {new_text}: samples stay "
                    "available longer")
    if field_name == "avoid_ros_namespace_conventions":
        return item("QOS_NAMESPACE_CONVENTIONS_CHANGED", "avoid_ros_namespace_conventions "
                    f"{old_text} -> {new_text}: the name on the wire changes, existing peers no "
                    "longer match")
    raise AssertionError(f"unexpected QoS field {field_name!r}")  # pragma: no cover


# --------------------------------------------------------------- QoS per middleware (issue 49)

def _service_qos(node: str, kind: str, entry: InterfaceEntry) -> dict[str, Any]:
    """What is compared of a service's QoS: the policies that decide whether a client is served
    (a DDS middleware matches requests and responses like topics), ``services_default`` when the
    entry states none (a capture writes a service's QoS only when these differ from it)."""
    try:
        explicit = qos.expand(entry.get("qos") or "services_default")
    except ValueError as error:
        raise ValueError(f"{node} {LABELS[kind]} {entry.get('name')}: {error}") from None
    return {field_name: explicit[field_name] for field_name in qos.MATCHING_FIELDS}


#: the rules that are BREAKING because a DDS middleware refuses the match
_REFUSED_MATCH = frozenset({rule for rule in RULES if rule.startswith("QOS_")
                            and rule.endswith(("_WEAKENED", "_REQUEST_RAISED"))} | {"SERVICE_QOS_CHANGED"})


def _for_middleware(items: Iterable[DriftItem], rmw: str | None) -> list[DriftItem]:
    """``items`` judged for the middleware ``rmw`` (``ComparisonOptions.rmw``): on one that matches
    any QoS (rmw_zenoh_cpp) a QoS change refuses no peer, so what a DDS middleware would refuse
    is RISKY there (what the peers get still changes: a weaker reliability loses messages)."""
    middleware = middlewares.get(rmw)
    if middleware is None or middleware.refuses:
        return list(items)
    return [dataclasses.replace(item, severity=Severity.RISKY,
                                message=f"{item.message} (under DDS; {middleware.name} matches any QoS: nothing is "
                                        "refused there, but what the peers get changes)")
            if item.rule in _REFUSED_MATCH and item.severity >= Severity.BREAKING else item
            for item in items]


# --------------------------------------------------------------------------- ordering

_KIND_ORDER = {kind: index for index, kind in enumerate(("node", *LISTS, PARAMETERS))}
_CHANGE_ORDER = {
    change: index
    for index, change in enumerate(
        ("added", "removed", "renamed", parameter_drift.LIFECYCLE_CHANGE, PARAMETERS, "type", "type_hash",
         *(f"qos.{f}" for f in qos.FIELDS), *(a for a in parameter_drift.ATTRIBUTES if a != "type"))
    )
}


def sort_items(items: list[DriftItem]) -> list[DriftItem]:
    """``items`` in report order: most severe first, then by node, kind, name and change."""
    return sorted(items, key=_sort_key)


def _sort_key(item: DriftItem) -> tuple:
    if item.change.startswith(TYPE_CHANGE_PREFIX) or item.change == "types":
        # right after the interface's type hash, in the order they were found (the interface's
        # own type first, then what it nests; fields in declaration order): sorted() is stable
        change_key: tuple = (_CHANGE_ORDER["type_hash"], 1, "")
    else:
        change_key = (_CHANGE_ORDER.get(item.change, len(_CHANGE_ORDER)), 0, item.change)
    return (
        -item.severity,
        item.node,
        _KIND_ORDER.get(item.kind, len(_KIND_ORDER)),
        item.name,
        *change_key,
    )
