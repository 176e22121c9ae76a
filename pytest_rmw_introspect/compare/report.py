"""Drift and system-check results → a report for people (text) or machines (JSON-ready dicts)."""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Mapping, Sequence
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


def _counts(items: Sequence) -> str:
    parts = [
        f"{sum(1 for i in items if i.severity is severity)} {severity.name.lower()}"
        for severity in reversed(Severity)
    ]
    return ", ".join(parts)


def _plural(count: int, word: str) -> str:
    return f"{count} {word}" if count == 1 else f"{count} {word}s"


def _section_header(severity: Severity, count: int, threshold: Severity) -> str:
    header = f"{severity.name} ({count})"
    if severity < threshold:
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


def _drift_line(item: DriftItem) -> str:
    line = f"[{item.rule}] {item.message}"
    if item.change in ("added", "removed"):
        line += _entry_details(item.kind, item.new if item.change == "added" else item.old, item.change)
    elif item.change == "type_hash" and isinstance(item.old, str) and isinstance(item.new, str):
        line += f" ({_short_hash(item.old)} -> {_short_hash(item.new)})"
    return line


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
    """The drift report for people: grouped by severity, then node, then interface; then the
    findings the contract accepts and its stale ``accept:`` entries."""
    heading = title or "Interface drift"
    where = f" against {contract_path}" if contract_path else ""
    if not items:
        return "\n".join([f"{heading}: no drift{where}.", *render_acceptances(accepted, stale)]) + "\n"

    lines = [f"{heading}{where}: {_plural(len(items), 'change')} ({_counts(items)})",
             _verdict(items, threshold)]
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
    lines += render_acceptances(accepted, stale)
    if accept_command:
        lines += ["", "To accept these changes as the new contract, run:", f"  {accept_command}"]
    return "\n".join(lines) + "\n"


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
    """Plain dicts for machines; ``severity`` as its name ("BREAKING", "RISKY", "SAFE")."""
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
            lines.append(f"    [{item.rule}] {ends}: {item.message}")
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
        }
        for item in items
    ]


# ------------------------------------------------------------------ a whole system's problems

#: a system report shows this many processes per rule, and this many findings per process; the
#: rest is counted (``--format json`` and SARIF list every finding)
PROCESSES_SHOWN = 10
FINDINGS_SHOWN = 3


@dataclass
class ProcessFindings:
    """The findings of one rule whose requesting end is in one process."""

    process: str
    items: list[CompatItem]


@dataclass
class RuleGroup:
    """The findings of one rule at one severity, by process, most findings first."""

    rule: str
    severity: Severity
    processes: list[ProcessFindings]

    @property
    def count(self) -> int:
        return sum(len(p.items) for p in self.processes)

    def shown(self, limit: int = PROCESSES_SHOWN) -> tuple[list[ProcessFindings], int, int]:
        """The first ``limit`` processes, and how many processes and findings are left out."""
        kept, rest = self.processes[:limit], self.processes[limit:]
        return kept, len(rest), sum(len(p.items) for p in rest)


def by_rule_and_process(items: Iterable[CompatItem]) -> list[RuleGroup]:
    """System findings grouped by severity (most severe first), rule, then the process of the
    requesting end (the processes with most findings first, then by label)."""
    groups: dict[tuple[Severity, str], dict[str, list[CompatItem]]] = {}
    for item in items:
        groups.setdefault((item.severity, item.rule), {}).setdefault(item.requester.label, []).append(item)
    out = []
    for (severity, rule), processes in sorted(groups.items(), key=lambda kv: (-kv[0][0], kv[0][1])):
        ordered = sorted(processes.items(), key=lambda kv: (-len(kv[1]), _natural(kv[0])))
        out.append(RuleGroup(rule, severity, [ProcessFindings(label, found) for label, found in ordered]))
    return out


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


def left_out(processes: int, findings: int) -> str:
    """What a cut list leaves out, for people."""
    where = f"{processes} more process" + ("" if processes == 1 else "es")
    return f"... and {_plural(findings, 'more finding')} in {where} (all of them: --format json)"


def render_system_problems(items: Sequence[CompatItem], *, threshold: Severity = Severity.SAFE,
                           title: str | None = None) -> str:
    """A system check's problems for people, at any size: by severity, rule, then process, each
    rule's longest lists cut (:data:`PROCESSES_SHOWN` processes, :data:`FINDINGS_SHOWN` findings
    each) with a count of what is left out."""
    heading = title or "System check"
    processes = {item.requester.label for item in items}
    lines = [f"{heading}: {_plural(len(items), 'problem')} in {len(processes)} process"
             f"{'' if len(processes) == 1 else 'es'} ({_counts(items)})", _verdict(items, threshold)]
    current: Severity | None = None
    for group in by_rule_and_process(items):
        if group.severity is not current:
            current = group.severity
            count = sum(1 for item in items if item.severity is current)
            lines += ["", _section_header(current, count, threshold)]
        lines.append(f"  [{group.rule}] {_plural(group.count, 'finding')} in {len(group.processes)} process"
                     f"{'' if len(group.processes) == 1 else 'es'}")
        kept, more_processes, more_findings = group.shown()
        for process in kept:
            lines.append(f"    {process.process}")
            for item in process.items[:FINDINGS_SHOWN]:
                lines.append(f"      {item.name}: {finding_ends(item)}: {item.message}")
            if len(process.items) > FINDINGS_SHOWN:
                lines.append(f"      ... and {_plural(len(process.items) - FINDINGS_SHOWN, 'more finding')}")
        if more_processes:
            lines.append(f"    {left_out(more_processes, more_findings)}")
    return "\n".join(lines) + "\n"
