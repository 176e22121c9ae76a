"""Node names that change on every run, and the stable contract key each one gets.

Some programs name a node differently every time they start: tf2_ros's ``TransformListener``
after its own address, ``static_transform_publisher`` with 16 random characters, ros2cli with
the process id, user code with a uuid, a timestamp or ``time_ns()``. A contract that wrote such
a name would drift on every check of an unchanged program, so the contract writes a **pattern**
instead (``/transform_listener_impl_*``: ``*`` stands for any run of characters but ``/``) and
says why in the node's ``unstable_name:`` key. docs/contract-format.md lists the rules with the
upstream code that makes each name.

Where a pattern comes from, strongest first:

- the contract's own ``unstable_names:`` list (``{pattern, reason}``, written by people);
- a node key of the contract that is a pattern (hand-written, or written by an earlier capture);
- the built-in rules (:data:`RULES`, and a ``_<pid>`` token equal to the capture's process id).

A name the contract states literally, and a name the launch file gave (``stable``), is never
turned into a pattern. Several nodes that match one pattern are compared as a set: the contract
keys them ``PATTERN``, ``PATTERN#2``, ... and each captured node is paired with the key whose
entry it resembles most (:func:`contract_keys`). An interface under such a node (``~/reset``)
is written under the pattern (``/static_transform_publisher_*/reset``) and compared as usual.
"""

from __future__ import annotations

import json
import re
from collections.abc import Collection, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, cast

from .contract_shapes import ContractNode, InterfaceEntry
from .name_patterns import name_matches
from .vocabulary import LISTS, PARAMETERS

#: the top-level contract key of the declared patterns, and the node key of the reason
SECTION_KEY = "unstable_names"
NODE_KEY = "unstable_name"
#: the separator of a pattern's second, third, ... node (``/static_transform_publisher_*#2``)
INSTANCE_MARK = "#"
#: a pattern as a contract may write it: a fully qualified name with at least one ``*`` (in any
#: segment); the schema (``unstable_names`` and the ``nodes`` keys) spells the same expressions
PATTERN_SYNTAX = r"^(?=.*\*)/([A-Za-z0-9_*]+/)*[A-Za-z0-9_*]+$"
#: a node key of a contract: a name, or a pattern with an optional ``#N`` (N >= 2)
NODE_KEY_SYNTAX = (r"^/([A-Za-z_][A-Za-z0-9_]*/)*[A-Za-z_][A-Za-z0-9_]*$"
                   r"|^(?=[^#]*\*)/([A-Za-z0-9_*]+/)*[A-Za-z0-9_*]+(#[2-9]|#[1-9][0-9]+)?$")


@dataclass(frozen=True)
class NamePattern:
    """A pattern of fully qualified node names and why names matching it are unstable."""

    pattern: str
    reason: str | None = None

    def matches(self, fqn: str) -> bool:
        return name_matches(self.pattern, fqn)  # in linear time (issue 50, N17)


def too_broad(pattern: str) -> str | None:
    """Why ``pattern`` is refused, or None: a base name of only ``*`` (``/*``, ``/*/*``,
    ``/ns/*``) matches every node of its namespace, so a node that was renamed would still
    match it and a check would say the contract matches (issue 50, N18)."""
    base = pattern_of_key(pattern).rpartition("/")[2]
    if base.strip("*"):
        return None
    return (f"the pattern {pattern_of_key(pattern)} matches every node name in its namespace, so a renamed node "
            "would still match it and the check could not see the rename; keep the part of the name that does "
            "not change (`/worker_*`, `/transform_listener_impl_*`)")


def refused(data: Mapping[str, Any]) -> tuple[list[str | int], str] | None:
    """The first pattern of a schema-valid contract document that is too broad
    (:func:`too_broad`): its place in the document and why, or None."""
    for index, entry in enumerate(data.get(SECTION_KEY) or ()):
        reason = too_broad(str(entry["pattern"]))
        if reason is not None:
            return [SECTION_KEY, index, "pattern"], reason
    for key in data.get("nodes") or {}:
        if is_pattern_key(str(key)):
            reason = too_broad(str(key))
            if reason is not None:
                return ["nodes", str(key)], reason
    return None


def is_pattern_key(key: str) -> bool:
    """A contract node key that is a pattern (``/x_*``, ``/x_*#2``), not a node name."""
    return "*" in key


def pattern_of_key(key: str) -> str:
    """``/x_*#2`` → ``/x_*``."""
    return key.split(INSTANCE_MARK, 1)[0]


def instance_key(pattern: str, number: int) -> str:
    """The key of a pattern's ``number``-th node: the pattern, then ``PATTERN#2``, ..."""
    return pattern if number == 1 else f"{pattern}{INSTANCE_MARK}{number}"


# ---------------------------------------------------------------------------- built-in rules


@dataclass(frozen=True)
class NameRule:
    """A kind of name that changes every run: ``token`` matches the changing part of a node's
    base name (each rule's lookarounds say where in the name it may stand)."""

    id: str
    token: re.Pattern[str]
    reason: str


# Each rule's reason names the code that makes such names; docs/contract-format.md has the list.
RULES: tuple[NameRule, ...] = (
    NameRule("tf2_transform_listener", re.compile(r"(?<=^transform_listener_impl_)[0-9a-f]+$"),
         "tf2_ros::TransformListener names its node transform_listener_impl_<its own address> "
         "(tf2_ros/src/transform_listener.cpp)"),
    NameRule("tf2_static_transform_publisher", re.compile(r"(?<=^static_transform_publisher_)[0-9A-Za-z]{16}$"),
         "static_transform_publisher appends 16 random characters to its node name "
         "(tf2_ros/src/static_transform_broadcaster_node.cpp)"),
    NameRule("uuid", re.compile(r"(?<=_)[0-9a-f]{8}_[0-9a-f]{4}_[0-9a-f]{4}_[0-9a-f]{4}_[0-9a-f]{12}(?=_|$)"),
         "a uuid in the name (a new one every run)"),
    NameRule("date_time", re.compile(r"(?<=_)(\d{8}[_T]?\d{6}|\d{4}(_\d{2}){5})(?=_|$)"),
         "a date and time in the name (the start of the run)"),
    NameRule("random_hex", re.compile(r"(?<=_)(?=[0-9a-f]*[0-9])(?=[0-9a-f]*[a-f])[0-9a-f]{8,}(?=_|$)"),
         "a hexadecimal suffix of 8 or more digits (a random token, uuid4().hex, an address): "
         "a new one every run"),
    NameRule("long_number", re.compile(r"(?<=_)\d{8,}(?=_|$)"),
         "a number of 8 or more digits in the name (a timestamp, time_ns(), a random integer): "
         "a new one every run"),
)
#: a smaller process id is not looked for (``/worker_7`` is more likely a name than a pid)
MIN_PID = 100
PID_REASON = "the process id in the name (as ros2cli's _ros2cli_<pid>): a new one every run"


def recognise(fqn: str, pid: int | None = None) -> NamePattern | None:
    """The built-in pattern of ``fqn`` when its base name is one that changes every run
    (:data:`RULES`, or a ``_``-separated piece equal to ``pid``), else None."""
    namespace, _, base = fqn.rpartition("/")
    reasons: list[str] = []
    for rule in RULES:
        base, count = rule.token.subn("*", base)
        if count:
            reasons.append(rule.reason)
    if pid is not None and pid >= MIN_PID:
        base, count = re.subn(rf"(?<=_){pid}(?=_|$)", "*", base)
        if count:
            reasons.append(PID_REASON)
    if not reasons:
        return None
    return NamePattern(f"{namespace}/{base}", "; ".join(reasons))


# ---------------------------------------------------------------------------- contract keys


@dataclass(frozen=True)
class NameRules:
    """What decides the contract key of a captured node: the contract's declared patterns
    (``unstable_names:`` first, then its pattern keys), the contract's nodes (the names it
    states literally are kept; a pattern's instances are paired with them), and the names a
    launch file gave (never a pattern)."""

    declared: tuple[NamePattern, ...] = ()
    expected: Mapping[str, ContractNode] = field(default_factory=dict)
    stable: frozenset[str] = frozenset()

    @classmethod
    def of_contract(cls, declared: Iterable[NamePattern] = (), nodes: Mapping[str, ContractNode] | None = None,
                    *, stable: Collection[str] = ()) -> NameRules:
        nodes = nodes or {}
        keyed = [NamePattern(pattern_of_key(k), nodes[k].get("unstable_name")) for k in sorted(nodes) if is_pattern_key(k)]
        seen: set[str] = set()
        unique = []
        for pattern in [*declared, *keyed]:
            if pattern.pattern not in seen:
                seen.add(pattern.pattern)
                unique.append(pattern)
        return cls(tuple(unique), nodes, frozenset(stable))

    @classmethod
    def literal(cls, names: Iterable[str]) -> NameRules:
        """Rules that keep ``names`` as they are (a NoDL document names its node literally)."""
        return cls(stable=frozenset(names))

    def pattern_for(self, fqn: str, pid: int | None) -> NamePattern | None:
        """The pattern ``fqn`` is written as, or None when it is written as it is."""
        if fqn in self.expected or fqn in self.stable:
            return None
        for declared in self.declared:
            if declared.matches(fqn):
                return declared
        return recognise(fqn, pid)


def contract_keys(named: Sequence[tuple[str, ContractNode, int | None]],
                  rules: NameRules | None = None) -> list[tuple[str, ContractNode]]:
    """Each ``(fqn, node, pid of its process)`` with the key the contract writes it under, in
    the order given.

    A stable name keeps its node as it is. A node whose name changes every run gets its
    pattern's key (interface names under the node rewritten to the pattern, ``unstable_name``
    set to the reason); several nodes of one pattern are paired with the contract's keys of
    that pattern by likeness (equal entries first), the rest numbered on in a fixed order."""
    rules = rules or NameRules()
    out: list[tuple[str, ContractNode]] = [(fqn, node) for fqn, node, _pid in named]
    groups: dict[str, list[int]] = {}
    for index, (fqn, node, pid) in enumerate(named):
        found = rules.pattern_for(fqn, pid)
        if found is not None:
            out[index] = (found.pattern, _under_pattern(fqn, node, found))
            groups.setdefault(found.pattern, []).append(index)
    for pattern, indices in groups.items():
        for index, key in zip(indices, _paired(pattern, [out[i][1] for i in indices], rules.expected), strict=True):
            out[index] = (key, out[index][1])
    return out


def _under_pattern(fqn: str, node: ContractNode, found: NamePattern) -> ContractNode:
    """``node`` as the contract writes it under ``found``: its own names (``fqn/...``) moved
    under the pattern, the reason recorded."""
    out = cast(ContractNode, dict(node))
    out.pop("unstable_name", None)
    for list_name in LISTS:
        if list_name in node:
            out[list_name] = [cast(InterfaceEntry, dict(e, name=_renamed(e["name"], fqn, found.pattern)))
                              for e in node[list_name]]
    if found.reason:
        out["unstable_name"] = found.reason
    return out


def _renamed(name: str, fqn: str, pattern: str) -> str:
    if name == fqn:
        return pattern
    if name.startswith(fqn + "/"):
        return pattern + name[len(fqn):]
    return name


def _entries(node: Mapping[str, Any]) -> set[str]:
    """A node's entries as comparable strings (what pairing counts as alike)."""
    return {f"{key}:{json.dumps(entry, sort_keys=True)}" for key in (*LISTS, PARAMETERS) for entry in node.get(key) or []}


def _paired(pattern: str, nodes: list[ContractNode], expected: Mapping[str, ContractNode]) -> list[str]:
    """The key of each of ``nodes`` (all of ``pattern``): the contract's keys of the pattern
    go to the nodes most like their entries, the other nodes get the next free numbers (in the
    order of their contents, so that an unchanged program gets the same keys every run)."""
    order = sorted(range(len(nodes)), key=lambda n: json.dumps(nodes[n], sort_keys=True))
    keys = sorted((k for k in expected if pattern_of_key(k) == pattern), key=_instance_number)
    wanted = [_entries(expected[k]) for k in keys]
    have = [_entries(n) for n in nodes]
    pairs = sorted((len(wanted[k] ^ have[n]), k, order.index(n), n) for k in range(len(keys)) for n in order)
    key_of: dict[int, str] = {}
    taken: set[int] = set()
    for _distance, k, _rank, n in pairs:
        if n not in key_of and k not in taken:
            key_of[n] = keys[k]
            taken.add(k)
    used = set(key_of.values())
    number = 1
    for n in order:
        if n in key_of:
            continue
        while instance_key(pattern, number) in used:
            number += 1
        key_of[n] = instance_key(pattern, number)
        used.add(key_of[n])
    return [key_of[n] for n in range(len(nodes))]


def _instance_number(key: str) -> int:
    _pattern, mark, number = key.partition(INSTANCE_MARK)
    return int(number) if mark else 1


def from_entries(entries: Sequence[Mapping[str, Any]] | None) -> tuple[NamePattern, ...]:
    """The entries of a schema-valid ``unstable_names:`` list."""
    return tuple(NamePattern(str(e["pattern"]), str(e["reason"]).strip()) for e in entries or ())
