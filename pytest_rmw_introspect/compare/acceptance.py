"""Which findings the ``accept:`` entries of contracts accept, and which entries match nothing
any more (stale). An accepted finding is kept apart from the others: it is reported as
accepted with its reason and never fails a check; a stale entry is reported so that it is
removed before it hides a new finding.

An entry accepts a finding of its rule when its ``name`` (if given) is the finding's interface,
topic, service, action or parameter name and its ``node`` (if given) is the finding's node (for
a system-check problem: either end's node)."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field

from ..errors import ContractError
from ..model.acceptance import Acceptance
from . import compatibility, drift
from .compatibility import CompatItem
from .drift import DriftItem

#: the rules a check of a node contract's drift can find, and those of the compatibility checks
DRIFT_RULES = frozenset(drift.RULES)
SYSTEM_RULES = frozenset(compatibility.RULES)

Finding = DriftItem | CompatItem


@dataclass(frozen=True)
class Accepted:
    """A finding and the entry that accepts it."""

    item: Finding
    acceptance: Acceptance


@dataclass
class Judged:
    """Findings sorted by the entries: ``kept`` count, ``accepted`` do not, ``stale`` entries
    (of the rules the check ran) accepted nothing."""

    kept: list[Finding] = field(default_factory=list)
    accepted: list[Accepted] = field(default_factory=list)
    stale: list[Acceptance] = field(default_factory=list)


def check_rules(acceptances: Iterable[Acceptance]) -> None:
    """Raise a ContractError for an entry whose rule no check has (a typo would never match)."""
    for entry in acceptances:
        if entry.rule not in DRIFT_RULES | SYSTEM_RULES:
            raise ContractError(entry.source, "accept", f"unknown rule {entry.rule}: the rule ids are in "
                                "docs/drift-rules.md (drift rules like PUB_REMOVED, compatibility rules like "
                                "SUBSCRIPTION_WITHOUT_PUBLISHER)", line=entry.line)


def matches(entry: Acceptance, item: Finding) -> bool:
    """Whether ``entry`` accepts ``item`` (rule, then name and node when the entry gives them)."""
    if entry.rule != item.rule or (entry.name is not None and entry.name != item.name):
        return False
    if entry.node is None:
        return True
    if isinstance(item, DriftItem):
        return item.node == entry.node
    return entry.node in {item.requester.node, item.provider.node if item.provider else None}


def judge(items: Sequence[Finding], acceptances: Sequence[Acceptance], *, rules: frozenset[str],
          applies: Callable[[Acceptance, Finding], bool] | None = None) -> Judged:
    """Sort ``items`` by ``acceptances`` (the first entry that matches accepts a finding);
    entries of ``rules`` (the checks that ran) that accepted nothing are stale. ``applies``
    narrows which entries may accept a finding (an entry of one contract, a finding about
    another: no)."""
    check_rules(acceptances)
    judged = Judged()
    used: set[int] = set()
    for item in items:
        for i, entry in enumerate(acceptances):
            if matches(entry, item) and (applies is None or applies(entry, item)):
                judged.accepted.append(Accepted(item, entry))
                used.add(i)
                break
        else:
            judged.kept.append(item)
    judged.stale = [entry for i, entry in enumerate(acceptances) if i not in used and entry.rule in rules]
    return judged
