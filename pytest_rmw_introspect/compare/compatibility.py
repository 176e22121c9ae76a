"""Compatibility checks across contracts: do the nodes of several contracts fit together?

All nodes of all contracts form one system. Per topic, every publisher × subscription pair is
checked (type, type hash, QoS with ``qos.profile_compatibility``); per service and action, every
client × server pair (type, type hash). Requesting endpoints without any provider are reported.
The services the client libraries give every node (its parameter services, a lifecycle node's
lifecycle services and transition events: :func:`implied_endpoints`) are left out of captures as
infrastructure, yet other nodes call them (a lifecycle manager): they count as present, with their
types, for every node of the contracts.
The rules and their severities are in docs/drift-rules.md ("Compatibility rules").
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

from ..model import middlewares, qos, tally
from ..model.contract_shapes import ContractNode, InterfaceEntry, QosFields
from ..model.vocabulary import (
    LABELS,
    LIFECYCLE,
    LIFECYCLE_SERVICE_TYPES,
    LIFECYCLE_TOPIC_TYPES,
    LISTS,
    PARAMETER_SERVICE_TYPES,
    PROVIDER_OF,
    ListName,
    Severity,
)
from . import launch_given, recording_rules, wiring

_WITHOUT_PROVIDER = {
    "subscriptions": "SUBSCRIPTION_WITHOUT_PUBLISHER",
    "service_clients": "CLIENT_WITHOUT_SERVER",
    "action_clients": "ACTION_CLIENT_WITHOUT_SERVER",
}
# requesting list → providing list, and the rule for a requester without any provider
_PAIRS: dict[ListName, tuple[ListName, str]] = {
    requester: (PROVIDER_OF[requester], _WITHOUT_PROVIDER[requester]) for requester in LISTS if requester in PROVIDER_OF
}

#: rule id → severity
RULES: dict[str, Severity] = {
    "TYPE_MISMATCH": Severity.BREAKING,
    "TYPE_HASH_MISMATCH": Severity.BREAKING,
    "QOS_INCOMPATIBLE": Severity.BREAKING,
    "QOS_MAYBE_INCOMPATIBLE": Severity.RISKY,
    # a note, not a finding (``NOTES``): the system runs on a middleware that matches any QoS
    "QOS_DDS_WOULD_REFUSE": Severity.NOTE,
    "SUBSCRIPTION_WITHOUT_PUBLISHER": Severity.RISKY,
    "CLIENT_WITHOUT_SERVER": Severity.RISKY,
    "ACTION_CLIENT_WITHOUT_SERVER": Severity.RISKY,
    # system contracts (a launch file's processes): check_launched
    "DUPLICATE_NODE_NAME": Severity.BREAKING,
    "SERVICE_MULTIPLE_SERVERS": Severity.BREAKING,
    "ACTION_MULTIPLE_SERVERS": Severity.BREAKING,
    "LAUNCHED_NODE_NOT_CREATED": Severity.BREAKING,
    # dangling endpoints, the declared outside world, mis-wired names (compare.wiring)
    **wiring.RULES,
    # what the launch file gives a node and the node ignores (compare.launch_given)
    **launch_given.RULES,
    # what a recording shows (check --bag: compare.recordings)
    **recording_rules.RULES,
}

#: rule id → what it reports, for the docs and SARIF's rule descriptions (the "what" column of
#: docs/drift-rules.md, "Compatibility rules")
SUMMARIES: dict[str, str] = {
    "TYPE_MISMATCH": "the two ends use different type names",
    "TYPE_HASH_MISMATCH": "same type name, different hash (or action hash mapping)",
    "QOS_INCOMPATIBLE": (
        "the QoS rules of the system's middleware (`qos.profile_compatibility`) say ERROR: a topic's publisher and "
        "subscription, or a service's client and server (requests or responses)"
    ),
    "QOS_MAYBE_INCOMPATIBLE": (
        "the QoS rules of the system's middleware (`qos.profile_compatibility`) say WARNING (topics and services)"
    ),
    "QOS_DDS_WOULD_REFUSE": (
        "the system runs on a middleware that matches any QoS (rmw_zenoh_cpp), and the DDS rules would refuse "
        "the pair (a note)"
    ),
    "SUBSCRIPTION_WITHOUT_PUBLISHER": "nobody publishes a subscribed topic",
    "CLIENT_WITHOUT_SERVER": "nobody serves a called service",
    "ACTION_CLIENT_WITHOUT_SERVER": "nobody serves an action with a client",
    "DUPLICATE_NODE_NAME": "two nodes of one system have the same fully qualified name",
    "SERVICE_MULTIPLE_SERVERS": "more than one server for one service",
    "ACTION_MULTIPLE_SERVERS": "more than one server for one action",
    "LAUNCHED_NODE_NOT_CREATED": "a process the launch file starts created no node, or not the node the launch file names",
    "DANGLING_SUBSCRIPTION": (
        "in a system contract, nobody in the system publishes a subscribed topic and `external:` does not "
        "declare who does"
    ),
    "TOPIC_NAME_MISMATCH": (
        "a subscription nobody publishes and a publisher nobody subscribes to (nor a declared outside "
        "subscriber), of one type, whose names are near misses"
    ),
    "DANGLING_SERVICE_CLIENT": (
        "in a system contract, nobody serves a called service (nor is it one of the services every node of the system "
        "serves) and `external:` does not declare who does"
    ),
    "SERVICE_NAME_MISMATCH": "the same for a service client nobody serves and a service server nobody calls",
    "DANGLING_ACTION_CLIENT": "in a system contract, nobody serves an action with a client and `external:` does not declare who does",
    "ACTION_NAME_MISMATCH": "the same for an action client and an action server",
    "EXTERNAL_UNUSED": "an `external:` declaration that no endpoint of the system uses",
    "PARAM_NOT_DECLARED": (
        "a parameter the launch file gives a node (`<param>`, `<set_parameter>`/`SetParameter` and "
        "`<set_parameters_from_file>` in the node's scope, a parameters file section that matches the node, "
        "`-p` in `ros_args`) that the node does not declare; in a process of several nodes, that no node it reaches "
        "declares"
    ),
    "PARAMS_FILE_SECTION_UNMATCHED": (
        "a parameters file given to processes has a node section that matches none of the nodes it is given "
        "to"
    ),
    "PARAM_NAME_INVALID": (
        "a parameter name the launch file gives a node (a parameters file key, `<param>`, `-p`) that cannot be a "
        "ROS parameter name: a space, a parenthesis, a colon, a comma"
    ),
    "REMAP_NEAR_MISS": (
        "a remapping the launch file gives a node changed none of its names, and its `from` is a near miss of a "
        "name the node does create (a typo: the node stays unwired)"
    ),
    "REMAP_UNUSED": (
        "a remapping the launch file gives a node changed none of its names (its `from` is no near miss), and "
        "another node of the system uses its target: a note"
    ),
    "REMAP_UNUSED_UNCONNECTED": (
        "a remapping the launch file gives a node changed none of its names, no other node uses its target and "
        "its `from` is no near miss: a note; identity remappings are not judged"
    ),
    "PARAM_PATH_MISSING": (
        "a node's string parameter (as captured, overrides applied) points at a file of a package that is missing:"
        " `package://PACKAGE/...`, `$(find-pkg-share PACKAGE)/...` (also inside `file://`), an absolute path "
        "inside a ROS prefix, or a package that is not installed"
    ),
    "PARAM_PATH_MACHINE_LOCAL": (
        "a node's string parameter points at a missing file outside every ROS prefix (a home directory, `/tmp`, "
        "`/mnt`, `/data`: an absolute path whose top directory exists, or `$(env HOME)/...`), and the parameter "
        "is not one the node writes (`output_*`, `save_*`, `log_*`, `*_dir`, ...)"
    ),
    "PARAM_DEVICE_ABSENT": (
        "a node's string parameter names a hardware device the capture machine lacks: `/dev/...` (with or "
        "without a `:baud` suffix), `serial:///dev/...`"
    ),
    **recording_rules.SUMMARIES,
}


#: rules whose items are notes (shown once per run, never failing: the front ends take them out
#: of the findings), the launch file's (``launch_given.NOTES``) and the middleware's
NOTES = launch_given.NOTES | {"QOS_DDS_WOULD_REFUSE"}


@dataclass(frozen=True, order=True)
class ContractEndpoint:
    label: str  # which contract (e.g. its file path)
    node: str  # fully qualified node name
    kind: str  # one of the six contract list names

    def __str__(self) -> str:
        return f"{LABELS[self.kind]} of {self.node} ({self.label})"


@dataclass(frozen=True)
class CompatItem:
    rule: str
    severity: Severity
    name: str  # topic, service or action name
    requester: ContractEndpoint  # subscription / service client / action client
    provider: ContractEndpoint | None  # publisher / service server / action server; None if missing
    message: str
    #: the provider's name when it differs from ``name`` (a mis-wired name: ``*_NAME_MISMATCH``)
    other_name: str | None = None
    #: where the project set this rule's level (``compare.rule_levels``: the option ``rules``); None: its default
    level_set_by: str | None = None

    def __post_init__(self) -> None:
        tally.note("rule", self.rule)  # the test suite's exercised set (model.tally; issue 48)


@dataclass(frozen=True)
class _Found:
    endpoint: ContractEndpoint
    entry: InterfaceEntry
    #: why the endpoint is present though no contract lists it (an implied endpoint), else None
    implied: str | None = None


#: what the client libraries give a node, by list: ``<node>/<leaf>`` → type, and why it is there
_IMPLIED: tuple[tuple[ListName, dict[str, str], bool, str], ...] = (
    ("service_servers", PARAMETER_SERVICE_TYPES, False, "every node serves its parameter services"),
    ("service_servers", LIFECYCLE_SERVICE_TYPES, True, "every lifecycle node serves its lifecycle services"),
    ("publishers", LIFECYCLE_TOPIC_TYPES, True, "every lifecycle node publishes its transition events"),
)


def implied_endpoints(fqn: str, node: ContractNode) -> list[tuple[ListName, InterfaceEntry, str]]:
    """The endpoints the ROS client library creates in the node ``fqn`` by itself, which a
    capture leaves out as infrastructure: ``(list, entry, why)`` for its parameter services and
    type description service, and for a lifecycle node (one with a ``lifecycle`` state) its
    lifecycle services and transition event publisher; not those its contract lists already
    (a capture with infrastructure)."""
    listed = {(kind, str(entry.get("name"))) for kind in LISTS for entry in (node or {}).get(kind) or []}
    managed = LIFECYCLE in (node or {})
    out: list[tuple[ListName, InterfaceEntry, str]] = []
    for kind, types, lifecycle_only, why in _IMPLIED:
        if lifecycle_only and not managed:
            continue
        for leaf, type_name in types.items():
            name = f"{fqn.rstrip('/')}/{leaf}"
            if (kind, name) not in listed:
                out.append((kind, {"name": name, "type": type_name}, why))
    return out


def check_compatibility(
    contracts: Mapping[str, Mapping[str, ContractNode]], *, strict_system_default: bool = False,
    rmw: str | None = None,
) -> list[CompatItem]:
    """Incompatibilities between the nodes of several contracts, most severe first.

    ``contracts`` maps a label (e.g. the contract path) to that contract's ``nodes`` mapping.
    A policy left at SYSTEM_DEFAULT on *both* ends resolves to the same middleware default and is
    not reported (every rmw profile leaves liveliness there, so rmw would warn about nearly every
    pair); ``strict_system_default=True`` reports exactly what rmw_dds_common answers.
    ``rmw``: the middleware the system runs on (``model.middlewares``; None: the DDS rules of
    rmw_dds_common); on one that matches any QoS, a pair the DDS rules refuse is a
    ``QOS_DDS_WOULD_REFUSE`` note.
    """
    endpoints: dict[str, dict[str, list[_Found]]] = {}  # kind → name → endpoints
    for label, nodes in contracts.items():
        for node_name, node in (nodes or {}).items():
            for kind in (*_PAIRS, *(provider for provider, _ in _PAIRS.values())):
                for entry in (node or {}).get(kind) or []:
                    found = _Found(ContractEndpoint(label, node_name, kind), entry)
                    endpoints.setdefault(kind, {}).setdefault(entry.get("name"), []).append(found)
            for kind, entry, why in implied_endpoints(node_name, node):
                found = _Found(ContractEndpoint(label, node_name, kind), entry, implied=why)
                endpoints.setdefault(kind, {}).setdefault(entry.get("name"), []).append(found)

    items: list[CompatItem] = []
    for requesting_kind, (providing_kind, missing_rule) in _PAIRS.items():
        providers_by_name = endpoints.get(providing_kind, {})
        for name, requesters in endpoints.get(requesting_kind, {}).items():
            providers = providers_by_name.get(name, [])
            for requester in requesters:
                if not providers:
                    items.append(_missing_peer(missing_rule, name, requester))
                for provider in providers:
                    items += _check_pair(name, provider, requester, strict_system_default, rmw)
    return sorted(items, key=_sort_key)


def _item(rule: str, name: str, requester: _Found, provider: _Found | None, message: str):
    return CompatItem(rule, RULES[rule], name, requester.endpoint,
                      provider.endpoint if provider else None, message)


def _missing_peer(rule: str, name: str, requester: _Found) -> CompatItem:
    missing = {"SUBSCRIPTION_WITHOUT_PUBLISHER": "no publisher",
               "CLIENT_WITHOUT_SERVER": "no service server",
               "ACTION_CLIENT_WITHOUT_SERVER": "no action server"}[rule]
    return _item(rule, name, requester, None, f"{missing} in these contracts")


def _check_pair(name: str, provider: _Found, requester: _Found, strict: bool,
                rmw: str | None = None) -> list[CompatItem]:
    offered, requested = provider.entry, requester.entry
    if offered.get("type") and requested.get("type") and offered["type"] != requested["type"]:
        # nothing else matters between endpoints of different types
        implied = f" ({provider.implied})" if provider.implied else ""
        return [_item("TYPE_MISMATCH", name, requester, provider,
                      f"{offered['type']} offered{implied}, {requested['type']} requested")]
    items = []
    offered_hash, requested_hash = offered.get("type_hash"), requested.get("type_hash")
    if offered_hash and requested_hash and offered_hash != requested_hash:
        items.append(_item("TYPE_HASH_MISMATCH", name, requester, provider,
                           "the two ends were built from different definitions of "
                           f"{offered.get('type') or requested.get('type')}"))
    return items + _check_qos(name, provider, requester, strict, rmw)


# ------------------------------------------------------------- QoS per middleware (issue 49)

def _check_qos(name: str, provider: _Found, requester: _Found, strict: bool, rmw: str | None) -> list[CompatItem]:
    """The QoS of a pair judged for the middleware ``rmw``: a topic's publisher and subscription
    (when both state a QoS), a service's server and client (``qos.service_compatibility``; a
    service entry without ``qos`` has the services default, the only one a capture leaves
    unwritten). Actions are not judged (their QoS is not in contracts)."""
    offered, requested = provider.entry, requester.entry
    if requester.endpoint.kind == "subscriptions":
        if "qos" not in offered or "qos" not in requested:
            return []
        pub_qos, sub_qos = qos.expand(offered["qos"]), qos.expand(requested["qos"])
        judge: Callable[[Any, Any, str | None], tuple[qos.Compatibility, str]] = qos.profile_compatibility
    elif requester.endpoint.kind == "service_clients":
        pub_qos = qos.expand(offered.get("qos") or "services_default")
        sub_qos = qos.expand(requested.get("qos") or "services_default")
        judge = qos.service_compatibility
    else:
        return []
    if not strict:
        pub_qos, sub_qos = _settle_shared_system_defaults(pub_qos, sub_qos)
    middleware = middlewares.get(rmw)
    compatibility, reason = judge(pub_qos, sub_qos, None if strict and middleware and middleware.refuses else rmw)
    if compatibility is qos.Compatibility.ERROR:
        return [_item("QOS_INCOMPATIBLE", name, requester, provider, _strip_levels(reason))]
    if compatibility is qos.Compatibility.WARNING:
        return [_item("QOS_MAYBE_INCOMPATIBLE", name, requester, provider, _strip_levels(reason))]
    if middleware is not None and not middleware.refuses:
        dds, dds_reason = judge(pub_qos, sub_qos, None)
        if dds is qos.Compatibility.ERROR:
            return [_item("QOS_DDS_WOULD_REFUSE", name, requester, provider,
                          f"{middleware.name} connects these whatever their QoS, a DDS middleware would refuse the "
                          f"match ({_strip_levels(dds_reason)}): it matters if the system moves to DDS")]
    return []


# Identical weak values: neither an error nor a warning under any rule.
_SETTLED: dict[Literal["reliability", "durability", "liveliness"], str] = {
    "reliability": "BEST_EFFORT", "durability": "VOLATILE", "liveliness": "AUTOMATIC"}


def _settle_shared_system_defaults(pub: QosFields, sub: QosFields) -> tuple[QosFields, QosFields]:
    pub, sub = pub.copy(), sub.copy()
    for policy, settled in _SETTLED.items():
        if pub[policy] == sub[policy] == "SYSTEM_DEFAULT":
            pub[policy] = sub[policy] = settled
    return pub, sub


def _strip_levels(reason: str) -> str:
    return "; ".join(part.split(": ", 1)[-1] for part in reason.split("; "))


def _sort_key(item: CompatItem) -> tuple:
    provider = item.provider or ContractEndpoint("", "", "")
    return (-item.severity, item.name, item.rule, item.requester, provider)


# ---------------------------------------------------------------------------- launched systems


@dataclass(frozen=True)
class LaunchedProcess:
    """One process of a system (a launch file's node): ``label`` names it in reports,
    ``expected`` is the fully qualified node name the launch file gives it (None: the program
    chooses), ``nodes`` the contract entries of the nodes it created."""

    label: str
    expected: str | None
    nodes: Mapping[str, ContractNode]
    #: node names held by more than one node of this one process (its capture lists them once)
    duplicates: tuple[str, ...] = ()
    #: a process the launch file starts (False: a node contract checked along, which promises no node)
    launched: bool = True
    #: where the launch file starts it (``robot.launch.xml:12``), when known
    where: str | None = None
    #: what the launch file gives it (parameters, parameters files, remappings), when known
    given: launch_given.Given | None = None
    #: components the launch file loads into it (a component container) that it did not
    #: create: (the component's node name or plugin, why)
    unloaded: tuple[tuple[str, str], ...] = ()
    #: per component node of a container (its fully qualified name): what its LoadNode request
    #: gives it (``launch_given`` judges it instead of the container's ``given``)
    component_given: Mapping[str, launch_given.Given] = field(default_factory=dict)


_MULTIPLE: dict[ListName, str] = {"service_servers": "SERVICE_MULTIPLE_SERVERS", "action_servers": "ACTION_MULTIPLE_SERVERS"}


def check_launched(processes: Sequence[LaunchedProcess], *, external: Mapping[str, Mapping[str, str]] | None = None,
                   missing_path: launch_given.MissingPath | None = None,
                   strict_system_default: bool = False, rmw: str | None = None) -> list[CompatItem]:
    """Every compatibility rule over the processes a launch file starts: the connections between all
    their nodes (:func:`check_compatibility`, one label per process), with requesters nobody provides
    judged against the declared outside world ``external`` (``compare.wiring``: declared, a
    mis-wired name, or dangling), plus node names held by more than one node, services and
    actions with more than one server, processes that did not create the node the launch file
    names (or created none), and what the launch file gives a node that it ignores
    (``compare.launch_given``; with ``missing_path``, parameter values that point at files that
    do not exist). ``rmw``: the middleware the system runs on (:func:`check_compatibility`).
    Most severe first."""
    connections = check_compatibility({p.label: p.nodes for p in processes}, strict_system_default=strict_system_default,
                                      rmw=rmw)
    missing = set(_WITHOUT_PROVIDER.values())
    items = [item for item in connections if item.rule not in missing]
    items += _judge_dangling(processes, [item for item in connections if item.rule in missing], external)
    items += [CompatItem(f.rule, RULES[f.rule], f.name, ContractEndpoint(f.label, f.node, "node"), None, f.message)
              for f in launch_given.given_findings(processes, missing_path)]
    holders: dict[str, list[str]] = {}
    for process in processes:
        for fqn in process.nodes:
            holders.setdefault(fqn, []).append(process.label)
        if process.launched and (not process.nodes or (process.expected is not None
                                                       and process.expected not in process.nodes)):
            created = ", ".join(sorted(process.nodes)) or "no node at all"
            wanted = f"node {process.expected}" if process.expected else "a node"
            at = f" at {process.where}" if process.where else " here"
            items.append(CompatItem(
                "LAUNCHED_NODE_NOT_CREATED", RULES["LAUNCHED_NODE_NOT_CREATED"], process.expected or process.label,
                ContractEndpoint(process.label, process.expected or "(unnamed)", "node"), None,
                f"the launch file starts {wanted}{at}, but the process created {created}"))
        for component, why in process.unloaded:
            items.append(CompatItem(
                "LAUNCHED_NODE_NOT_CREATED", RULES["LAUNCHED_NODE_NOT_CREATED"], component,
                ContractEndpoint(process.label, component, "node"), None, why))
    for process in processes:
        for fqn in process.duplicates:
            holders[fqn].append(process.label)
    for fqn, labels in holders.items():
        for label in labels[1:]:
            items.append(CompatItem(
                "DUPLICATE_NODE_NAME", RULES["DUPLICATE_NODE_NAME"], fqn,
                ContractEndpoint(label, fqn, "node"), ContractEndpoint(labels[0], fqn, "node"),
                f"{len(labels)} nodes are named {fqn}: ROS 2 cannot tell them apart (parameter services, "
                "logging and `ros2 node` address nodes by name); give each a name of its own"))
    for kind, rule in _MULTIPLE.items():
        servers: dict[str, list[ContractEndpoint]] = {}
        for process in processes:
            for fqn, node in process.nodes.items():
                for entry in (node or {}).get(kind) or []:
                    servers.setdefault(entry.get("name"), []).append(ContractEndpoint(process.label, fqn, kind))
        for name, found in servers.items():
            for other in found[1:]:
                items.append(CompatItem(
                    rule, RULES[rule], name, other, found[0],
                    f"{len(found)} {LABELS[kind]}s for {name}: every request reaches each of them and is executed "
                    "by each; the client takes whichever answer comes first"))
    return sorted(items, key=_sort_key)


def _judge_dangling(processes: Sequence[LaunchedProcess], missing: Sequence[CompatItem],
                    external: Mapping[str, Mapping[str, str]] | None) -> list[CompatItem]:
    """The requesters without provider of a launched system, judged by ``compare.wiring``."""
    dangling = [d for d in dangling_requesters(processes, missing)
                if wiring.declared(external, PROVIDER_OF[d.kind], d.name) is None]
    items = []
    for rule, item, offer, message in wiring.judge(dangling, wiring.unconsumed_offers(processes, external)):
        provider = ContractEndpoint(offer.label, offer.node, offer.kind) if offer is not None else None
        items.append(CompatItem(rule, RULES[rule], item.name, ContractEndpoint(item.label, item.node, item.kind), provider,
                                message, other_name=offer.name if offer is not None else None))
    for kind, name, who in wiring.unused_declarations(processes, external):
        wanted = LABELS[wiring.REQUESTER_OF.get(kind) or PROVIDER_OF[kind]]
        items.append(CompatItem("EXTERNAL_UNUSED", RULES["EXTERNAL_UNUSED"], name,
                                ContractEndpoint(wiring.EXTERNAL_LABEL, who, kind), None,
                                f"`external:` declares {who} as a {LABELS[kind]} of {name}, but no {wanted} of the "
                                "system uses that name: remove the declaration, or check the name on both sides"))
    return items


def dangling_requesters(processes: Sequence[LaunchedProcess], missing: Sequence[CompatItem]) -> list[wiring.Dangling]:
    """The requesters of ``missing`` (items without provider) with their types."""
    types: dict[tuple[str, str, str, str], str | None] = {}
    for process in processes:
        for fqn, node in process.nodes.items():
            for kind in _PAIRS:
                for entry in (node or {}).get(kind) or []:
                    types[(process.label, fqn, kind, str(entry.get("name")))] = entry.get("type")
    return [wiring.Dangling(i.requester.label, i.requester.node, i.requester.kind, i.name,
                            types.get((i.requester.label, i.requester.node, i.requester.kind, i.name)))
            for i in missing]


def propose_external(processes: Sequence[LaunchedProcess]) -> str:
    """A commented-out ``external:`` block for a new system contract: every requester nobody in
    the system provides for, except the near misses (mis-wirings to fix, not outside inputs)."""
    missing = [item for item in check_compatibility({p.label: p.nodes for p in processes})
               if item.rule in _WITHOUT_PROVIDER.values()]
    dangling = dangling_requesters(processes, missing)
    paired = [item for rule, item, offer, _ in wiring.judge(dangling, wiring.unconsumed_offers(processes, None))
              if offer is not None]
    return wiring.proposal(dangling, paired)
