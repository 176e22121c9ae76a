"""Consumers decide: a node contract's drift judged by who uses the changed interface in the
system contracts at hand (``rmw-introspect diff --against REF --system robot.system.yaml``).

For each changed or removed topic, service or action of a node contract, the peers are the
endpoints of the other side with the same name in the systems' nodes (the node contract's own
nodes left out: a system contract lists them as they were). The new interface is checked against
each peer with the compatibility rules (``compare.compatibility``): a peer it no longer fits
(type, type hash, QoS that rmw would refuse) adds a BREAKING ``CONSUMER_INCOMPATIBLE`` finding
that names the peer's node and the system; a removed provider whose consumers nobody else
serves adds one too. The drift item itself keeps its rule and severity and says what was found:
``no consumer in robot.system.yaml``, or which peers still fit. Nothing is ever downgraded.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any, cast

from ..model.contract_shapes import ContractNodes, InterfaceEntry
from ..model.vocabulary import LABELS, LISTS, PROVIDER_OF, ListName, Severity
from .compatibility import check_compatibility
from .drift import RULES, DriftItem

RULE = "CONSUMER_INCOMPATIBLE"
#: providing list → the list that uses what it provides
CONSUMER_OF = {provider: requester for requester, provider in PROVIDER_OF.items()}


def _judged_change(item: DriftItem) -> bool:
    return item.kind in LISTS and (item.change in ("removed", "renamed", "type", "type_hash") or item.change.startswith("qos."))


def _entry(nodes: ContractNodes, node: str, kind: str, name: str) -> InterfaceEntry | None:
    for entry in cast(Mapping[str, Any], nodes.get(node) or {}).get(kind) or []:
        if entry.get("name") == name:
            return cast(InterfaceEntry, entry)
    return None


def _peers(systems: Mapping[str, ContractNodes], own: set[str], kind: str,
           name: str) -> list[tuple[str, str, InterfaceEntry]]:
    """(system, node, entry) of every endpoint of ``kind`` named ``name`` outside ``own``."""
    found = []
    for label, nodes in systems.items():
        for node in sorted(nodes):
            if node in own:
                continue
            entry = _entry(nodes, node, kind, name)
            if entry is not None:
                found.append((label, node, entry))
    return found


def judge(items: Sequence[DriftItem], new_nodes: ContractNodes, old_nodes: ContractNodes,
          systems: Mapping[str, ContractNodes], rmw: str | None = None) -> list[DriftItem]:
    """``items`` with what the systems say of each, and the ``CONSUMER_INCOMPATIBLE`` findings
    (once per interface and peer, after the interface's first item); QoS judged for the
    middleware ``rmw`` (the ``rmw`` option; None: the DDS rules)."""
    if not systems:
        return list(items)
    own = set(new_nodes) | set(old_nodes)
    where = ", ".join(systems)
    judged: dict[tuple[str, str, str], tuple[str, list[DriftItem]]] = {}
    out: list[DriftItem] = []
    for item in items:
        if not _judged_change(item):
            out.append(item)
            continue
        key = (item.node, item.kind, item.name)
        first = key not in judged
        if first:
            judged[key] = _interface(item, new_nodes, own, systems, where, rmw)
        said, findings = judged[key]
        out.append(replace(item, message=f"{item.message} ({said})"))
        if first:
            out += findings
    return out


def _interface(item: DriftItem, new_nodes: ContractNodes, own: set[str], systems: Mapping[str, ContractNodes],
               where: str, rmw: str | None = None) -> tuple[str, list[DriftItem]]:
    """What the systems say of the changed interface of ``item``, and the findings of peers it no
    longer fits."""
    provides = item.kind in CONSUMER_OF
    peer_kind: str = CONSUMER_OF[cast(ListName, item.kind)] if provides else PROVIDER_OF[item.kind]
    peers = _peers(systems, own, peer_kind, item.name)
    if not peers:
        return f"no {'consumer' if provides else 'provider'} in {where}", []
    peer_words = ", ".join(f"{LABELS[peer_kind]} of {node} in {label}" for label, node, _ in peers)
    new_entry = _entry(new_nodes, item.node, item.kind, item.name)
    findings: list[DriftItem] = []
    if new_entry is None:  # removed (or renamed away): a consumer nobody else serves loses it
        if provides and not _peers(systems, own, item.kind, item.name):
            findings = [_finding(item, label, node, peer_kind, f"the {LABELS[peer_kind]} of {node} in {label} loses "
                                 f"its only {LABELS[item.kind]}") for label, node, _ in peers]
        return f"used by the {peer_words}", findings
    for label, node, entry in peers:
        ends: dict[str, Any] = {"contract": {item.node: {item.kind: [new_entry]}}, label: {node: {peer_kind: [entry]}}}
        pair = check_compatibility(ends, rmw=rmw)  # QoS for the middleware the gate is given (--rmw)
        findings += [_finding(item, label, node, peer_kind, f"the {LABELS[peer_kind]} of {node} in {label} no longer "
                              f"fits: [{problem.rule}] {problem.message}")
                     for problem in pair if problem.provider is not None and problem.severity is Severity.BREAKING]
    return (f"used by the {peer_words}" if findings else f"still fits the {peer_words}"), findings


def _finding(item: DriftItem, label: str, node: str, peer_kind: str, message: str) -> DriftItem:
    return DriftItem(node=item.node, kind=item.kind, name=item.name, change="consumer", old=None,
                     new={"system": label, "node": node, "kind": peer_kind}, rule=RULE,
                     severity=RULES[RULE].severity, message=message)
