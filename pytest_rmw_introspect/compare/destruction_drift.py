"""Drift of *when the program destroys* a node or an interface (``destroyed_at``).

A contract keeps what the program itself destroyed while it ran (a demo that makes a publisher
die after 8 s) with its virtual age at destruction, in seconds; an entry without it lives to the
end. This module compares those ages on the nodes and interfaces both sides have, judged like
the presence rules from the side of the peers: an offer (a node, a publisher, a service or action
server) that now goes away during the run, or earlier, breaks the peers that use it after that
moment; a request (a subscription, a client) that goes away is a behaviour change. Rule table and
reasoning: docs/drift-rules.md, "Destruction rules".

An interface without ``destroyed_at`` of a node that has one goes with its node: it is compared
at the node's age, and a change it shares with its node is the node's item alone (consequences
of a bigger change are not separate drift).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from ..model.contract_shapes import ContractNode, InterfaceEntry
from ..model.vocabulary import DESTROYED_AT, DESTROYED_AT_TOLERANCE_S, LABELS, OFFERING_LISTS, Severity

RULES: dict[str, tuple[Severity, str]] = {
    "NEWLY_DESTROYED": (Severity.BREAKING,
                        "a node or offer that lived to the end is now destroyed by the program while it runs"),
    "REQUEST_NEWLY_DESTROYED": (Severity.RISKY,
                                "a subscription or client that lived to the end is now destroyed while the program runs"),
    "DESTROYED_EARLIER": (Severity.BREAKING, "a node or offer is now destroyed earlier in the run"),
    "REQUEST_DESTROYED_EARLIER": (Severity.RISKY, "a subscription or client is now destroyed earlier in the run"),
    "NO_LONGER_DESTROYED": (Severity.SAFE, "a node or interface the program destroyed now lives to the end"),
    "DESTROYED_LATER": (Severity.SAFE, "a node or interface is now destroyed later in the run"),
}


@dataclass(frozen=True)
class DestructionChange:
    kind: str  # "node" or one of LISTS
    name: str  # the node's fqn, or the interface's key
    old: float | None  # seconds of virtual age (None: alive to the end)
    new: float | None
    rule: str
    message: str


def _age(value: Any) -> float | None:
    return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else None


def classify(kind: str, name: str, old: float | None, new: float | None) -> DestructionChange | None:
    """The item for ``kind`` ``name`` destroyed at ``old`` in the contract and ``new`` now
    (seconds of virtual age, None: alive to the end), or None when that is the same."""
    if old is None and new is None:
        return None
    if old is not None and new is not None and abs(old - new) <= DESTROYED_AT_TOLERANCE_S:
        return None
    offer = kind == "node" or kind in OFFERING_LISTS
    what = f"{LABELS[kind]} {name}"
    if old is None:
        rule = "NEWLY_DESTROYED" if offer else "REQUEST_NEWLY_DESTROYED"
        consequence = ("peers that use it after that lose it" if offer
                       else "the node stops taking part after that")
        message = f"{what} is now destroyed by the program at {new:g} s (it lived to the end): {consequence}"
    elif new is None:
        rule = "NO_LONGER_DESTROYED"
        message = f"{what} now lives to the end (the program destroyed it at {old:g} s)"
    elif new < old:
        rule = "DESTROYED_EARLIER" if offer else "REQUEST_DESTROYED_EARLIER"
        message = (f"{what} is now destroyed at {new:g} s, earlier than the {old:g} s of the contract: "
                   + ("peers that use it in between lose it" if offer else "the node stops taking part earlier"))
    else:
        rule = "DESTROYED_LATER"
        message = f"{what} is now destroyed at {new:g} s, later than the {old:g} s of the contract"
    return DestructionChange(kind, name, old, new, rule, message)


def compare_node(fqn: str, old_node: ContractNode, new_node: ContractNode,
                 interfaces: Iterator[tuple[str, str, InterfaceEntry, InterfaceEntry]]) -> list[DestructionChange]:
    """The destruction items of node ``fqn`` (present on both sides) and of its ``interfaces``
    present on both sides: ``(list name, key, old entry, new entry)``."""
    old_node_age, new_node_age = _age(old_node.get(DESTROYED_AT)), _age(new_node.get(DESTROYED_AT))
    changes = []
    node_change = classify("node", fqn, old_node_age, new_node_age)
    if node_change is not None:
        changes.append(node_change)
    for kind, key, old_entry, new_entry in interfaces:
        old_age = _age(old_entry.get(DESTROYED_AT))
        new_age = _age(new_entry.get(DESTROYED_AT))
        old_age = old_node_age if old_age is None else old_age
        new_age = new_node_age if new_age is None else new_age
        if (old_age, new_age) == (old_node_age, new_node_age):
            continue  # goes with its node: the node's item (or nothing changed)
        change = classify(kind, key, old_age, new_age)
        if change is not None:
            changes.append(change)
    return changes
