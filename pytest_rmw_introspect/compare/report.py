"""Drift and system-check results → a report for people (text) or machines (JSON-ready dicts)."""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from ..model import qos
from ..model.acceptance import Acceptance
from ..model.parameters import format_value
from ..model.vocabulary import DESTROYED_AT, LABELS, PARAMETERS, THRESHOLD_WORDS, Severity
from .acceptance import Accepted
from .compatibility import CompatItem
from .drift import DriftItem

#: the rule of a stale ``accept:`` entry in JSON and SARIF
STALE_RULE = "ACCEPTANCE_STALE"


def fails(items: Iterable[DriftItem | CompatItem], threshold: Severity) -> bool:
    """True when any item is at least as severe as ``threshold``."""
    return any(item.severity >= threshold for item in items)


def counts(items: Sequence) -> str:
    """"1 breaking, 0 risky, 2 safe" (and ", 1 note" when there are notes: a note never fails)."""
    parts = [
        f"{sum(1 for i in items if i.severity is severity)} {severity.name.lower()}"
        for severity in reversed(Severity)
        if severity is not Severity.NOTE or any(i.severity is Severity.NOTE for i in items)
    ]
    return ", ".join(parts)


_counts = counts


def notes_only(items: Iterable[DriftItem | CompatItem]) -> bool:
    """True when every item is a note (``Severity.NOTE``: shown, never failing)."""
    return all(item.severity is Severity.NOTE for item in items)


def _plural(count: int, word: str) -> str:
    return f"{count} {word}" if count == 1 else f"{count} {word}s"


def _section_header(severity: Severity, count: int, threshold: Severity) -> str:
    header = f"{severity.name} ({count})"
    if severity is Severity.NOTE:
        header += " - notes, never failing"
    elif severity < threshold:
        header += f" - below the fail threshold ({THRESHOLD_WORDS[threshold]}), not failing"
    return header


def _verdict(items: Sequence, threshold: Severity) -> str:
    word = THRESHOLD_WORDS[threshold]
    return f"Result: {'FAIL' if fails(items, threshold) else 'pass'} (fail on: {word})"


# --------------------------------------------------------------------------- drift


def _short_hash(value: Any) -> str:
    if isinstance(value, str) and len(value) > 20:
        return f"{value[:14]}...{value[-4:]}"
    return str(value)


def _parameter_details(entry: Mapping[str, Any]) -> str:
    details = [str(entry.get("type") or "no type")]
    if "default_value" in entry:
        details.append(f"default {format_value(entry['default_value'])}")
    details += [flag.replace("_", " ") for flag in ("read_only", "dynamic_typing") if entry.get(flag)]
    return f" (was: {', '.join(details)})"


def _entry_details(kind: str, entry: Any, change: str) -> str:
    if not isinstance(entry, Mapping):
        return ""
    if kind == PARAMETERS:  # an added parameter's message already says its type and default
        return _parameter_details(entry) if change == "removed" else ""
    details = []
    if kind != "node" and entry.get("qos") is not None:
        try:
            details.append(f"qos {qos.describe(entry['qos'])}")
        except ValueError:
            details.append(f"qos {entry['qos']!r}")
    if entry.get(DESTROYED_AT) is not None:
        details.append(f"destroyed by the program at {entry[DESTROYED_AT]:g} s")
    return f" ({', '.join(details)})" if details else ""


def _drift_change(item: DriftItem) -> str:
    """The change for people: its message and, where it helps, what was added or removed or the
    two type hashes."""
    line = item.message
    if item.change in ("added", "removed"):
        line += _entry_details(item.kind, item.new if item.change == "added" else item.old, item.change)
    elif item.change == "type_hash" and isinstance(item.old, str) and isinstance(item.new, str):
        line += f" ({_short_hash(item.old)} -> {_short_hash(item.new)})"
    return line


def set_by(item: DriftItem | CompatItem) -> str:
    """`` (RISKY, set by rules: in contracts/x.yaml: options)`` when the project set the item's
    level (``compare.rule_levels``), else nothing."""
    return f" ({item.severity.name}, {item.level_set_by})" if item.level_set_by else ""


def _drift_line(item: DriftItem) -> str:
    return f"[{item.rule}] {_drift_change(item)}{set_by(item)}"


def render_text(
    items: Sequence[DriftItem],
    *,
    contract_path: str | None = None,
    threshold: Severity = Severity.SAFE,
    accept_command: str | None = None,
    title: str | None = None,
    accepted: Sequence[Accepted] = (),
    stale: Sequence[Acceptance] = (),
) -> str:
    """The drift report for people: grouped by severity, then node, then interface (in more
    nodes than a rule shows, :func:`at_scale`: by severity, rule, then node, cut and counted);
    then the findings the contract accepts and its stale ``accept:`` entries."""
    heading = title or "Interface drift"
    where = f" against {contract_path}" if contract_path else ""
    if not items:
        return "\n".join([f"{heading}: no drift{where}.", *render_acceptances(accepted, stale)]) + "\n"

    if at_scale(items):
        lines = render_drift_at_scale(items, heading=f"{heading}{where}", threshold=threshold)
    else:
        lines = [f"{heading}{where}: {_plural(len(items), 'change')} ({_counts(items)})",
                 _verdict(items, threshold)]
        lines += _drift_sections(items, threshold)
    lines += render_acceptances(accepted, stale)
    if accept_command:
        lines += ["", "To accept these changes as the new contract, run:", f"  {accept_command}"]
    return "\n".join(lines) + "\n"


def _drift_sections(items: Sequence[DriftItem], threshold: Severity) -> list[str]:
    """A short drift report's body: by severity, then node, then interface, every change."""
    lines: list[str] = []
    for severity in reversed(Severity):
        group = [item for item in items if item.severity is severity]
        if not group:
            continue
        lines += ["", _section_header(severity, len(group), threshold)]
        current_node = current_interface = None
        for item in group:  # already sorted by node, kind, name within a severity
            if item.node != current_node:
                current_node, current_interface = item.node, None
                lines.append(f"  {item.node}")
            interface = (item.kind, item.name)
            if item.kind != "node" and interface != current_interface:
                current_interface = interface
                lines.append(f"    {LABELS.get(item.kind, item.kind)} {item.name}")
            indent = "    " if item.kind == "node" else "      "
            lines.append(f"{indent}{_drift_line(item)}")
    return lines


def _finding_place(item: DriftItem | CompatItem) -> str:
    if isinstance(item, DriftItem):
        return item.node if item.kind == "node" else f"{item.node} {LABELS.get(item.kind, item.kind)} {item.name}"
    return f"{item.name} ({item.requester}{f' and {item.provider}' if item.provider else ''})"


def render_acceptances(accepted: Sequence[Accepted], stale: Sequence[Acceptance]) -> list[str]:
    """Report lines of the accepted findings (with their reasons) and of the stale entries."""
    lines: list[str] = []
    if accepted:
        lines += ["", f"ACCEPTED ({len(accepted)}) - accepted on purpose (`accept:` entries, a baseline), not failing"]
        for entry in accepted:
            lines.append(f"  {_finding_place(entry.item)}: [{entry.item.rule}] {entry.item.message}")
            lines.append(f"    accepted ({entry.acceptance.where()}): {entry.acceptance.reason}")
    if stale:
        lines += ["", f"STALE ACCEPTANCES ({len(stale)}) - `accept:` entries that match nothing any more; "
                  "remove them before they hide a new finding"]
        lines += [f"  {entry.where()}: {entry.describe()} (reason given: {entry.reason})" for entry in stale]
    return lines


def accepted_to_json(accepted: Iterable[Accepted]) -> list[dict[str, Any]]:
    """The accepted findings as their JSON objects with ``accepted``: the entry that accepts them."""
    out = []
    for entry in accepted:
        item = entry.item
        (plain,) = to_json([item]) if isinstance(item, DriftItem) else compat_to_json([item])
        out.append({**plain, "accepted": entry.acceptance.to_json()})
    return out


def stale_to_json(stale: Iterable[Acceptance]) -> list[dict[str, Any]]:
    """Stale entries as JSON objects of the rule ``ACCEPTANCE_STALE``."""
    return [{"rule": STALE_RULE, "severity": Severity.SAFE.name, "accept": entry.to_json(),
             "message": f"`accept:` entry {entry.describe()} matches nothing; remove it"} for entry in stale]


def _plain(value: Any) -> Any:
    """``value`` as strict JSON can hold it: NaN and infinities (parameter values) as the strings
    the capture file uses (``nan``, ``inf``, ``-inf``)."""
    if isinstance(value, float) and not math.isfinite(value):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
    if isinstance(value, Mapping):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


def to_json(items: Iterable[DriftItem]) -> list[dict[str, Any]]:
    """Plain dicts for machines; ``severity`` as its name ("BREAKING", "RISKY", "SAFE", "NOTE")."""
    return [
        {
            "node": item.node,
            "kind": item.kind,
            "name": item.name,
            "change": item.change,
            "rule": item.rule,
            "severity": item.severity.name,
            "old": _plain(item.old),
            "new": _plain(item.new),
            "message": item.message,
            **({"level_set_by": item.level_set_by} if item.level_set_by else {}),
        }
        for item in items
    ]


# -------------------------------------------------------------------- compatibility checks


def render_compat_text(
    items: Sequence[CompatItem],
    *,
    threshold: Severity = Severity.SAFE,
    title: str | None = None,
    accepted: Sequence[Accepted] = (),
    stale: Sequence[Acceptance] = (),
) -> str:
    """The system-check report for people: grouped by severity, then topic/service name; then
    the accepted problems and the stale ``accept:`` entries."""
    heading = title or "Compatibility check"
    if not items:
        return "\n".join([f"{heading}: all contracts fit together.", *render_acceptances(accepted, stale)]) + "\n"
    lines = [f"{heading}: {_plural(len(items), 'problem')} ({_counts(items)})",
             _verdict(items, threshold)]
    for severity in reversed(Severity):
        group = [item for item in items if item.severity is severity]
        if not group:
            continue
        lines += ["", _section_header(severity, len(group), threshold)]
        current_name = None
        for item in group:
            if item.name != current_name:
                current_name = item.name
                lines.append(f"  {item.name}")
            if item.provider is None:
                ends = str(item.requester)
            elif item.provider.kind == item.requester.kind:  # two of a kind: duplicates, several servers
                ends = f"{item.provider} and {item.requester}"
            else:
                ends = f"{item.provider} -> {item.requester}"
            lines.append(f"    [{item.rule}] {ends}: {item.message}{set_by(item)}")
    lines += render_acceptances(accepted, stale)
    return "\n".join(lines) + "\n"


def _endpoint_json(endpoint) -> dict[str, str] | None:
    if endpoint is None:
        return None
    return {"label": endpoint.label, "node": endpoint.node, "kind": endpoint.kind}


def compat_to_json(items: Iterable[CompatItem]) -> list[dict[str, Any]]:
    return [
        {
            "name": item.name,
            "rule": item.rule,
            "severity": item.severity.name,
            "requester": _endpoint_json(item.requester),
            "provider": _endpoint_json(item.provider),
            "message": item.message,
            **({"other_name": item.other_name} if item.other_name else {}),
            **({"level_set_by": item.level_set_by} if item.level_set_by else {}),
        }
        for item in items
    ]


# ------------------------------------------------------------------ reports at scale

#: a report at scale shows this many places (processes, nodes) per rule, and this many findings
#: per place; the rest is counted (``--format json`` and SARIF list every finding)
PROCESSES_SHOWN = 10
FINDINGS_SHOWN = 3


@dataclass
class PlaceFindings:
    """The findings of one rule at one place: the process of a system problem's requesting end,
    or the node of a drift item."""

    place: str
    items: list[Any]


@dataclass
class RuleGroup:
    """The findings of one rule at one severity, by place, most findings first."""

    rule: str
    severity: Severity
    places: list[PlaceFindings]

    @property
    def count(self) -> int:
        return sum(len(p.items) for p in self.places)

    def shown(self, limit: int = PROCESSES_SHOWN) -> tuple[list[PlaceFindings], int, int]:
        """The first ``limit`` places, and how many places and findings are left out."""
        kept, rest = self.places[:limit], self.places[limit:]
        return kept, len(rest), sum(len(p.items) for p in rest)


def _by_rule_and_place(items: Iterable[Any], place: Callable[[Any], str]) -> list[RuleGroup]:
    groups: dict[tuple[Severity, str], dict[str, list[Any]]] = {}
    for item in items:
        groups.setdefault((item.severity, item.rule), {}).setdefault(place(item), []).append(item)
    out = []
    for (severity, rule), places in sorted(groups.items(), key=lambda kv: (-kv[0][0], kv[0][1])):
        ordered = sorted(places.items(), key=lambda kv: (-len(kv[1]), _natural(kv[0])))
        out.append(RuleGroup(rule, severity, [PlaceFindings(where, found) for where, found in ordered]))
    return out


def by_rule_and_process(items: Iterable[CompatItem]) -> list[RuleGroup]:
    """System findings grouped by severity (most severe first), rule, then the process of the
    requesting end (the processes with most findings first, then by label)."""
    return _by_rule_and_place(items, lambda item: item.requester.label)


def drift_by_rule_and_node(items: Iterable[DriftItem]) -> list[RuleGroup]:
    """Drift items grouped by severity (most severe first), rule, then node (the nodes with most
    changes first, then by name)."""
    return _by_rule_and_place(items, lambda item: item.node)


def at_scale(items: Sequence[DriftItem]) -> bool:
    """Whether a drift report is too long to list whole: its changes are in more nodes than a
    rule shows (:data:`PROCESSES_SHOWN`): a system of many processes that moved at once."""
    return len({item.node for item in items}) > PROCESSES_SHOWN


def _natural(label: str) -> list[Any]:
    """Sorts ``talker #2`` before ``talker #10``."""
    return [int(part) if part.isdigit() else part for part in re.split(r"(\d+)", label)]


def finding_ends(item: CompatItem) -> str:
    """The ends of a system finding: ``provider -> requester``, ``a and b`` (two of a kind), or
    the requester alone."""
    if item.provider is None:
        return str(item.requester)
    if item.provider.kind == item.requester.kind:  # two of a kind: duplicates, several servers
        return f"{item.provider} and {item.requester}"
    return f"{item.provider} -> {item.requester}"


def left_out(places: int, findings: int, *, place: str = "process", noun: str = "finding") -> str:
    """What a cut list leaves out, for people (``place``: "process" or "node"; ``noun``: "finding"
    or, for drift, "change")."""
    plural = "processes" if place == "process" else f"{place}s"
    where = f"{places} more {place if places == 1 else plural}"
    return f"... and {_plural(findings, 'more ' + noun)} in {where} (all of them: --format json)"


def drift_place_line(item: DriftItem) -> str:
    """One drift item under its node in a report at scale: the interface, then the change."""
    what = "" if item.kind == "node" else f"{LABELS.get(item.kind, item.kind)} {item.name}: "
    return what + _drift_change(item) + set_by(item)


def _rule_lines(groups: Sequence[RuleGroup], all_items: Sequence[Any], threshold: Severity, *, noun: str,
                place: str, line: Callable[[Any], str]) -> list[str]:
    """The body of a report at scale: a section per severity, in it a line per rule, under it
    the first places with their first findings, and what is left out counted."""
    lines: list[str] = []
    current: Severity | None = None
    for group in groups:
        if group.severity is not current:
            current = group.severity
            count = sum(1 for item in all_items if item.severity is current)
            lines += ["", _section_header(current, count, threshold)]
        places = "processes" if place == "process" else f"{place}s"
        lines.append(f"  [{group.rule}] {_plural(group.count, noun)} in {len(group.places)} "
                     f"{place if len(group.places) == 1 else places}")
        kept, more_places, more_findings = group.shown()
        for found in kept:
            lines.append(f"    {found.place}")
            lines += [f"      {line(item)}" for item in found.items[:FINDINGS_SHOWN]]
            if len(found.items) > FINDINGS_SHOWN:
                lines.append(f"      ... and {_plural(len(found.items) - FINDINGS_SHOWN, 'more ' + noun)}")
        if more_places:
            lines.append(f"    {left_out(more_places, more_findings, place=place, noun=noun)}")
    return lines


def render_system_problems(items: Sequence[CompatItem], *, threshold: Severity = Severity.SAFE,
                           title: str | None = None) -> str:
    """A system check's problems for people, at any size: by severity, rule, then process, each
    rule's longest lists cut (:data:`PROCESSES_SHOWN` processes, :data:`FINDINGS_SHOWN` findings
    each) with a count of what is left out."""
    heading = title or "System check"
    processes = {item.requester.label for item in items}
    lines = [f"{heading}: {_plural(len(items), 'problem')} in {len(processes)} process"
             f"{'' if len(processes) == 1 else 'es'} ({_counts(items)})", _verdict(items, threshold)]
    lines += _rule_lines(by_rule_and_process(items), items, threshold, noun="finding", place="process",
                         line=lambda item: f"{item.name}: {finding_ends(item)}: {item.message}{set_by(item)}")
    return "\n".join(lines) + "\n"


def render_drift_at_scale(items: Sequence[DriftItem], *, heading: str, threshold: Severity) -> list[str]:
    """The lines of a drift report in many nodes (:func:`at_scale`): by severity, rule, then node,
    each rule's longest lists cut like :func:`render_system_problems`."""
    nodes = {item.node for item in items}
    lines = [f"{heading}: {_plural(len(items), 'change')} in {len(nodes)} nodes ({_counts(items)})",
             _verdict(items, threshold)]
    return lines + _rule_lines(drift_by_rule_and_node(items), items, threshold, noun="change", place="node",
                               line=drift_place_line)
