"""Dangling endpoints of a launched system: the declared outside world and mis-wired names.

A system contract is a whole robot, so a subscription nobody in it publishes (a client nobody
serves, an action client nobody serves) is either fed from outside the launch files (rviz, a
teleop, a driver started elsewhere: the contract declares it under ``external:``) or a
mis-wiring. :func:`judge` turns the requesters without provider that ``compare.compatibility`` found
into what they are:

* declared under ``external:``: nothing to report;
* a near miss of a provider nobody requests, of the same type (the same last segment in
  another namespace, ``/scan`` vs ``/camera/scan``; a small edit distance, ``/scan_raw`` vs
  ``/scan_row``): one BREAKING ``*_NAME_MISMATCH`` naming both ends and the remapping or
  namespace that joins them;
* anything else: a BREAKING ``DANGLING_*`` (declare who provides it, or fix the wiring).

A declaration under ``external:`` that no endpoint of the system uses is reported
(``EXTERNAL_UNUSED``): it is stale, or it hides a typo on one side. Rules and severities:
docs/drift-rules.md ("Compatibility rules").
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from ..model.vocabulary import LABELS, LISTS, OFFERING_LISTS, PROVIDER_OF, Severity
from .similarity import typo_distance

#: requesting list → the rule for a dangling requester nobody declared, and for a near miss
DANGLING = {
    "subscriptions": ("DANGLING_SUBSCRIPTION", "TOPIC_NAME_MISMATCH"),
    "service_clients": ("DANGLING_SERVICE_CLIENT", "SERVICE_NAME_MISMATCH"),
    "action_clients": ("DANGLING_ACTION_CLIENT", "ACTION_NAME_MISMATCH"),
}
RULES: dict[str, Severity] = {
    **{rule: Severity.BREAKING for pair in DANGLING.values() for rule in pair},
    "EXTERNAL_UNUSED": Severity.RISKY,
}
#: providing list → requesting list
REQUESTER_OF: dict[str, str] = {provider: requester for requester, provider in PROVIDER_OF.items()}
_WHAT = {"subscriptions": "topic", "service_clients": "service", "action_clients": "action"}
#: the label of endpoints declared under ``external:``
EXTERNAL_LABEL = "external"


@dataclass(frozen=True)
class Dangling:
    """A requester nobody in the system provides to (``label``: its process)."""

    label: str
    node: str
    kind: str
    name: str
    type: str | None


@dataclass(frozen=True)
class _Offer:
    label: str
    node: str
    kind: str
    name: str
    type: str | None


def declared(external: Mapping[str, Mapping[str, str]] | None, kind: str, name: str) -> str | None:
    """Who ``external:`` says provides (or requests) ``name`` as a ``kind`` (None: not declared)."""
    return ((external or {}).get(kind) or {}).get(name)


def unconsumed_offers(processes: Iterable[Any], external: Mapping[str, Mapping[str, str]] | None) -> list[_Offer]:
    """Publishers, service servers and action servers nobody in the system (nor a declared
    outside requester) uses: the other half of a mis-wired name."""
    requested: set[tuple[str, str]] = set()
    offers: list[_Offer] = []
    for process in processes:
        for fqn, node in process.nodes.items():
            for kind in LISTS:
                for entry in (node or {}).get(kind) or []:
                    if kind in OFFERING_LISTS:
                        offers.append(_Offer(process.label, fqn, kind, str(entry.get("name")), entry.get("type")))
                    else:
                        requested.add((kind, str(entry.get("name"))))
    return [o for o in offers if (REQUESTER_OF[o.kind], o.name) not in requested
            and declared(external, REQUESTER_OF[o.kind], o.name) is None]


def _split(name: str) -> tuple[str, str]:
    namespace, _, last = name.rpartition("/")
    return namespace or "/", last


def near_miss(wanted: str, offered: str) -> tuple[int, str] | None:
    """How close two names are (lower is closer) and why they look like one, or None."""
    if wanted == offered:
        return None
    (wanted_ns, wanted_last), (offered_ns, offered_last) = _split(wanted), _split(offered)
    if wanted_last == offered_last:
        return 0, f"the same name in another namespace ({wanted_ns} vs {offered_ns})"
    # short names are a letter apart by chance (/a, /b): the last segments decide what is short
    distance = typo_distance(wanted, offered, shortest=min(len(wanted_last), len(offered_last)))
    if distance is not None:
        return distance, f"{distance} character{'s' if distance > 1 else ''} apart"
    return None


def _types_fit(a: str | None, b: str | None) -> bool:
    return a is None or b is None or a == b


def _hint(dangling: Dangling, offer: _Offer) -> str:
    remap = (f'remap it for {dangling.node}: <remap from="{dangling.name}" to="{offer.name}"/>, '
             f'or the other end for {offer.node}: <remap from="{offer.name}" to="{dangling.name}"/>')
    (wanted_ns, wanted_last), (offered_ns, offered_last) = _split(dangling.name), _split(offer.name)
    if wanted_last == offered_last:
        node_ns = _split(dangling.node)[0]
        if node_ns == wanted_ns:
            return (f"{remap}; or, if {dangling.node} is started in the wrong namespace, start it in {offered_ns} "
                    "(<push_ros_namespace>, `namespace=`)")
    return remap


def judge(dangling: Sequence[Dangling], offers: Sequence[_Offer]) -> list[tuple[str, Dangling, _Offer | None, str]]:
    """Each dangling requester as ``(rule, dangling, paired offer or None, message)``."""
    out: list[tuple[str, Dangling, _Offer | None, str]] = []
    for item in dangling:
        dangling_rule, mismatch_rule = DANGLING[item.kind]
        scored = []
        for offer in offers:
            if offer.kind != PROVIDER_OF[item.kind] or not _types_fit(item.type, offer.type):
                continue
            near = near_miss(item.name, offer.name)
            if near is not None:
                scored.append((near[0], offer, near[1]))
        if not scored:
            provider = LABELS[PROVIDER_OF[item.kind]]
            out.append((dangling_rule, item, None,
                        f"no {provider} in the system and `external:` does not declare one: if something outside "
                        f"the launch files provides it, declare it (external: {{{PROVIDER_OF[item.kind]}: "
                        f"{{{item.name}: WHO}}}}); otherwise its remapping or namespace is wrong"))
            continue
        best = min(score for score, _, _ in scored)
        for _, offer, why in (s for s in scored if s[0] == best):
            type_text = f" ({item.type or offer.type})" if item.type or offer.type else ""
            out.append((mismatch_rule, item, offer,
                        f"nobody provides {item.name} and nobody requests {offer.name}{type_text}: one "
                        f"{_WHAT[item.kind]} wired under two names, {why}; {_hint(item, offer)}"))
    return out


def unused_declarations(processes: Iterable[Any], external: Mapping[str, Mapping[str, str]] | None
                        ) -> list[tuple[str, str, str]]:
    """``(kind, name, who)`` of every ``external:`` declaration no endpoint of the system uses
    (an outside publisher of a topic nobody subscribes to, ...)."""
    used: set[tuple[str, str]] = set()
    for process in processes:
        for node in process.nodes.values():
            for kind in LISTS:
                for entry in (node or {}).get(kind) or []:
                    used.add((kind, str(entry.get("name"))))
    counterpart: dict[str, str] = {**PROVIDER_OF, **REQUESTER_OF}
    return [(kind, name, str(who)) for kind in LISTS for name, who in ((external or {}).get(kind) or {}).items()
            if (counterpart[kind], name) not in used]


def proposal(dangling: Sequence[Dangling], paired: Iterable[Dangling] = ()) -> str:
    """A commented-out ``external:`` block declaring every dangling requester that is not a near
    miss (those are mis-wirings to fix, not outside inputs), for a new system contract's header."""
    skip = set(paired)
    by_kind: dict[str, dict[str, list[Dangling]]] = {}
    for item in dangling:
        if item not in skip:
            by_kind.setdefault(PROVIDER_OF[item.kind], {}).setdefault(item.name, []).append(item)
    if not by_kind:
        return ""
    lines = ["# Endpoints nothing in the launch files provides. If something outside them does (rviz, a",
             "# teleop, a driver started elsewhere), uncomment this block and write who; anything not declared",
             "# here fails the check (DANGLING_*), since it is usually a remapping or namespace mistake.",
             "# external:"]
    for kind in LISTS:
        if kind not in by_kind:
            continue
        lines.append(f"#   {kind}:")
        for name, items in sorted(by_kind[kind].items()):
            users = ", ".join(sorted({i.node for i in items}))
            type_name = next((i.type for i in items if i.type), None)
            lines.append(f"#     {name}: WHO    # {type_name + ', ' if type_name else ''}for {users}")
    return "\n".join(lines) + "\n"
