"""Reports for CI: Markdown (a pull-request comment, ``$GITHUB_STEP_SUMMARY``) and GitHub Actions
workflow commands (``::error file=...,line=...::``, shown as annotations on the contract file).

The text report (``report.py``) stays the one for terminals and failing tests; these render the
same items for the places CI shows them. Items at or above the fail threshold are errors,
items below it warnings.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

from ..model.acceptance import Acceptance
from ..model.locate import LineIndex, line_of
from ..model.vocabulary import LABELS, THRESHOLD_WORDS, Severity
from . import report
from .acceptance import Accepted
from .compatibility import CompatItem
from .drift import DriftItem

#: a contract's row of the Markdown table names this many nodes, and counts the rest
NODES_SHOWN = 10


@dataclass(frozen=True)
class ContractOutcome:
    """One contract's result as the CI formats show it."""

    contract: str  # the path as shown
    items: Sequence[DriftItem] = ()
    threshold: Severity = Severity.SAFE
    nodes: Sequence[str] = ()
    error: str | None = None  # the check could not run
    written: str | None = None  # "created" / "updated" (check --update)
    lines: LineIndex = field(default_factory=dict)  # where the contract lists each node and interface
    #: a system contract's system-check problems, judged against their own threshold
    system_items: Sequence[CompatItem] = ()
    system_threshold: Severity = Severity.BREAKING
    #: findings the contract accepts on purpose, and its ``accept:`` entries that match nothing
    accepted: Sequence[Accepted] = ()
    stale: Sequence[Acceptance] = ()
    #: a system contract's processes (by label) → where the launch file starts them (``robot.launch.xml:12``)
    launched_at: Mapping[str, str] = field(default_factory=dict)
    #: what to know beside the findings (``diff --against``: the bump the changes need, a rename)
    notes: Sequence[str] = ()
    #: what the check notes (a device this machine lacks), each with its line in the contract
    #: (None: unknown); said once per run (:func:`once`) however many contracts note it
    notices: Sequence[tuple[str, int | None]] = ()

    @property
    def failed(self) -> bool:
        """An error, drift at or above the threshold (not when the update wrote it: ``written``),
        or a system problem at or above its threshold (an update does not fix those)."""
        drift_fails = self.written is None and any(i.severity >= self.threshold for i in self.items)
        return (self.error is not None or drift_fails
                or any(i.severity >= self.system_threshold for i in self.system_items))


def _counts(items: Sequence[DriftItem | CompatItem]) -> str:
    return report.counts(items)


def _cell(text: str) -> str:
    """Text inside a Markdown table cell: one line, pipes escaped."""
    first = text.strip().splitlines()[0] if text.strip() else ""
    return first.replace("|", "\\|")


def _result_cell(outcome: ContractOutcome) -> str:
    if outcome.error is not None:
        return f"🛑 error: {_cell(outcome.error)}"
    if outcome.written:
        if outcome.failed:  # written, and the system still broken
            return f"✏️ {outcome.written}, but ❌ system check: {_counts(outcome.system_items)}"
        return f"✏️ {outcome.written}"
    everything: list[DriftItem | CompatItem] = [*outcome.items, *outcome.system_items]
    if not everything:
        return "✅ matches"
    if outcome.failed:
        return f"❌ {_counts(everything)}"
    if report.notes_only(everything):
        return f"✅ matches ({_counts(everything)})"
    return f"⚠️ {_counts(everything)} (below the fail threshold: {THRESHOLD_WORDS[outcome.threshold]})"


def _drift_bullets(items: Sequence[DriftItem], threshold: Severity) -> list[str]:
    if report.at_scale(items):
        return _drift_bullets_at_scale(items, threshold)
    lines: list[str] = []
    for severity in reversed(Severity):
        group = [i for i in items if i.severity is severity]
        if not group:
            continue
        note = " (notes, never failing)" if severity is Severity.NOTE else \
            "" if severity >= threshold else " (below the fail threshold)"
        lines += ["", f"**{severity.name}** ({len(group)}){note}", ""]
        for item in group:
            where = f"`{item.node}`" if item.kind == "node" else f"`{item.node}` {LABELS.get(item.kind, item.kind)} `{item.name}`"
            lines.append(f"- {where}: `{item.rule}` {item.message}{report.set_by(item)}")
    return lines


def drift_markdown(outcomes: Sequence[ContractOutcome], *, title: str = "Interface contracts",
                   intro: Sequence[str] = ()) -> str:
    """A summary table (one row per contract) and each contract's drift grouped by severity;
    ``intro``: lines said between the heading and the table (the gate: what it looked at)."""
    failing = sum(1 for o in outcomes if o.failed)
    verdict = f"{failing} of {len(outcomes)} failing" if failing else f"all {len(outcomes)} pass"
    lines = [f"## {title}: {verdict}", ""] + [f"{line}  " for line in intro] + ([""] if intro else [])
    lines += ["| contract | nodes | result |", "|---|---|---|"]
    noted = once(outcomes)
    for o in outcomes:
        nodes = ", ".join(f"`{n}`" for n in o.nodes[:NODES_SHOWN]) or "-"
        if len(o.nodes) > NODES_SHOWN:
            nodes += f" and {len(o.nodes) - NODES_SHOWN} more"
        lines.append(f"| `{o.contract}` | {nodes} | {_result_cell(o)} |")
    for o, notices in zip(outcomes, noted, strict=True):
        notes = [*o.notes, *(text for text, _ in notices)]
        if o.error is None and (o.accepted or o.stale or notes) and not (o.items or o.system_items):
            lines += ["", f"### `{o.contract}`"] + _note_lines(notes)
        if o.error is not None:
            lines += ["", f"### `{o.contract}`", "", "```", o.error.rstrip("\n"), "```"]
        elif o.items or o.system_items:
            lines += ["", f"### `{o.contract}`: {len(o.items)} change(s) ({_counts(o.items)})"]
            lines += _note_lines(notes)
            lines += _drift_bullets(o.items, o.threshold)
            if o.system_items:
                lines += _system_bullets(o.system_items)
        if o.error is None:
            lines += _acceptance_bullets(o.accepted, o.stale)
    return "\n".join(lines) + "\n"


def _system_bullets(items: Sequence[CompatItem]) -> list[str]:
    """A system check's problems by rule and process, cut like the text report
    (``report.by_rule_and_process``)."""
    processes = {item.requester.label for item in items}
    lines = ["", f"System check: {len(items)} problem(s) in {len(processes)} process(es) ({_counts(items)})", ""]
    for group in report.by_rule_and_process(items):
        lines.append(f"- {group.severity.name} `{group.rule}`: {group.count} finding(s) in "
                     f"{len(group.places)} process(es)")
        kept, more_processes, more_findings = group.shown()
        for process in kept:
            for item in process.items[:report.FINDINGS_SHOWN]:
                ends = f"{item.provider} → {item.requester}" if item.provider else str(item.requester)
                lines.append(f"  - `{process.place}` `{item.name}`: {ends}: {item.message}{report.set_by(item)}")
            if len(process.items) > report.FINDINGS_SHOWN:
                lines.append(f"  - `{process.place}`: … and {len(process.items) - report.FINDINGS_SHOWN} more")
        if more_processes:
            lines.append(f"  - {report.left_out(more_processes, more_findings)}")
    return lines


def _drift_bullets_at_scale(items: Sequence[DriftItem], threshold: Severity) -> list[str]:
    """Drift in many nodes (``report.at_scale``) by rule and node, cut like the text report."""
    lines: list[str] = []
    for group in report.drift_by_rule_and_node(items):
        note = " (a note, never failing)" if group.severity is Severity.NOTE else \
            "" if group.severity >= threshold else " (below the fail threshold)"
        lines += ["", f"- {group.severity.name}{note} `{group.rule}`: {group.count} change(s) in "
                      f"{len(group.places)} node(s)"]
        kept, more_nodes, more_changes = group.shown()
        for node in kept:
            lines += [f"  - `{node.place}`: {report.drift_place_line(item)}" for item in node.items[:report.FINDINGS_SHOWN]]
            if len(node.items) > report.FINDINGS_SHOWN:
                lines.append(f"  - `{node.place}`: … and {len(node.items) - report.FINDINGS_SHOWN} more")
        if more_nodes:
            lines.append(f"  - {report.left_out(more_nodes, more_changes, place='node', noun='change')}")
    return lines


def once(outcomes: Sequence[ContractOutcome]) -> list[list[tuple[str, int | None]]]:
    """Each outcome's ``notices`` not said by an outcome before it: a note is said once per run
    (the same device of the same node, noted by every contract that launches it)."""
    said: set[str] = set()
    out = []
    for o in outcomes:
        fresh = [(text, line) for text, line in o.notices if text not in said]
        said.update(text for text, _ in fresh)
        out.append(fresh)
    return out


def _note_lines(notes: Sequence[str]) -> list[str]:
    return [line for note in notes for line in ("", f"> {_cell(note)}")]


def _acceptance_bullets(accepted: Sequence[Accepted], stale: Sequence[Acceptance]) -> list[str]:
    lines: list[str] = []
    if accepted:
        lines += ["", f"Accepted on purpose ({len(accepted)}, not failing):", ""]
        lines += [f"- `{entry.item.rule}` {_cell(entry.item.message)}: {_cell(entry.acceptance.reason)}"
                  for entry in accepted]
    if stale:
        lines += ["", f"Stale `accept:` entries ({len(stale)}, they match nothing: remove them):", ""]
        lines += [f"- `{entry.where()}`: {entry.describe()}" for entry in stale]
    return lines


def compat_markdown(items: Sequence[CompatItem], *, threshold: Severity, labels: Sequence[str],
                    title: str = "Compatibility check") -> str:
    """The compatibility check: a verdict, the contracts checked and the problems by severity."""
    failing = any(i.severity >= threshold for i in items)
    verdict = "FAIL" if failing else "pass"
    lines = [f"## {title} of {len(labels)} contract(s): {verdict}", ""]
    lines.append(f"{len(items)} problem(s) ({_counts(items)}); fail on: {THRESHOLD_WORDS[threshold]}.")
    lines += ["", "| severity | name | rule | provider → requester | problem |", "|---|---|---|---|---|"]
    for item in items:
        ends = f"{item.provider} → {item.requester}" if item.provider else str(item.requester)
        lines.append(f"| {item.severity.name} | `{item.name}` | `{item.rule}` | {_cell(ends)} | {_cell(item.message)} |")
    lines += ["", "<details><summary>contracts checked</summary>", ""]
    lines += [f"- `{label}`" for label in labels]
    lines += ["", "</details>"]
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------------- GitHub workflow commands


def _escape_data(text: str) -> str:
    return text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def _escape_property(text: str) -> str:
    return _escape_data(text).replace(":", "%3A").replace(",", "%2C")


def annotation(level: str, message: str, *, file: str | None = None, line: int | None = None,
               title: str | None = None) -> str:
    """One workflow command: ``::error file=F,line=L,title=T::message``."""
    props = []
    if file:
        props.append(f"file={_escape_property(file)}")
    if line:
        props.append(f"line={line}")
    if title:
        props.append(f"title={_escape_property(title)}")
    return f"::{level} {','.join(props)}::{_escape_data(message)}" if props else f"::{level}::{_escape_data(message)}"


def _title(item: DriftItem | CompatItem) -> str:
    """An annotation's title: the rule and its level (and who set it, when the project did)."""
    return f"{item.rule} ({item.severity.name}{' set by the project' if item.level_set_by else ''})"


def annotation_level(severity: Severity, threshold: Severity) -> str:
    """The annotation a finding gets: ``error`` when it fails the gate, except a SAFE one (it breaks
    nothing: ``warning`` even when ``--fail-on any`` fails on it); below the threshold ``warning``,
    or ``notice`` for a SAFE one."""
    fails = severity >= threshold
    if severity is Severity.NOTE:
        return "notice"
    if severity == Severity.SAFE:
        return "warning" if fails else "notice"
    return "error" if fails else "warning"


def drift_github(outcomes: Sequence[ContractOutcome]) -> str:
    """An annotation per drift item (:func:`annotation_level`: error when it fails the gate), on the
    contract's line of the interface (or of its node), one per contract that could not be
    checked, and a notice per note (once per run: :func:`once`)."""
    lines = []
    for o, notices in zip(outcomes, once(outcomes), strict=True):
        if o.error is not None:
            lines.append(annotation("error", o.error.rstrip("\n"), file=o.contract, title="contract not checked"))
            continue
        # notes are notices on the contract (the line of what they are about), once per run
        lines += [annotation("notice", text, file=o.contract, line=line, title="note") for text, line in notices]
        lines += [annotation("notice", text, file=o.contract, title="note") for text in o.notes]
        shown, counted = _drift_annotated(o.items)
        for item in shown:
            level = annotation_level(item.severity, o.threshold)
            what = item.node if item.kind == "node" else f"{item.node} {LABELS.get(item.kind, item.kind)} {item.name}"
            lines.append(annotation(level, f"{what}: {item.message}", file=o.contract,
                                    line=line_of(o.lines, item.node, item.kind, item.name),
                                    title=_title(item)))
        for item, more in counted:
            lines.append(annotation(annotation_level(item.severity, o.threshold),
                                    f"{more} more change(s) of this rule not annotated (all of them: --format json "
                                    "or sarif)", file=o.contract, title=_title(item)))
        if o.system_items:
            lines.append(compat_github(o.system_items, threshold=o.system_threshold, lines={o.contract: o.lines},
                                       file=o.contract, cut=True).rstrip("\n"))
        lines += acceptance_github(o.accepted, o.stale)
    return "\n".join(lines) + ("\n" if lines else "")


def _drift_annotated(items: Sequence[DriftItem]) -> tuple[list[DriftItem], list[tuple[DriftItem, int]]]:
    """The drift items to annotate one by one, and per rule cut (``report.at_scale``: only what
    the text report shows) its first item with how many are left out (GitHub shows a step's
    first few annotations only)."""
    if not report.at_scale(items):
        return list(items), []
    shown: list[DriftItem] = []
    counted: list[tuple[DriftItem, int]] = []
    for group in report.drift_by_rule_and_node(items):
        kept, _, more = group.shown()
        shown += [item for node in kept for item in node.items[:report.FINDINGS_SHOWN]]
        more += sum(max(0, len(node.items) - report.FINDINGS_SHOWN) for node in kept)
        if more:
            counted.append((group.places[0].items[0], more))
    return shown, counted


def acceptance_github(accepted: Sequence[Accepted], stale: Sequence[Acceptance]) -> list[str]:
    """A notice per accepted finding on the line of the entry that accepts it (the finding is
    not shown as a problem) and a warning per stale entry on its line."""
    out = [annotation("notice", f"{entry.item.message} (accepted: {entry.acceptance.reason})",
                      file=entry.acceptance.source, line=entry.acceptance.line,
                      title=f"{entry.item.rule} accepted") for entry in accepted]
    out += [annotation("warning", f"`accept:` entry {entry.describe()} matches nothing any more; remove it",
                       file=entry.source, line=entry.line, title="ACCEPTANCE_STALE") for entry in stale]
    return out


def compat_github(items: Sequence[CompatItem], *, threshold: Severity,
                  lines: Mapping[str, LineIndex] | None = None, file: str | None = None,
                  file_of: Callable[[str], str] | None = None,
                  accepted: Sequence[Accepted] = (), stale: Sequence[Acceptance] = (), cut: bool = False) -> str:
    """An annotation per system-check problem, on the requesting end's contract and line:
    ``file`` when one contract holds every end, else ``file_of(label)`` (a system contract's
    process label → its file), else the end's label (a node contract's path). ``cut``: per rule,
    only the findings the text report shows (``report.by_rule_and_process``), and one
    annotation counting the rest (GitHub shows a step's first few annotations only)."""
    out = []
    shown: list[CompatItem] = list(items)
    counted: list[tuple[CompatItem, str]] = []
    if cut:
        shown = []
        for group in report.by_rule_and_process(items):
            kept, more_processes, more_findings = group.shown()
            shown += [item for process in kept for item in process.items[:report.FINDINGS_SHOWN]]
            more_findings += sum(max(0, len(p.items) - report.FINDINGS_SHOWN) for p in kept)
            if more_findings:
                counted.append((group.places[0].items[0],
                                f"{more_findings} more finding(s) of this rule not annotated (all of them: --format "
                                f"json or sarif)"))
    for item in shown:
        level = annotation_level(item.severity, threshold)
        where = file or (file_of(item.requester.label) if file_of else item.requester.label)
        index = (lines or {}).get(where, {})
        ends = f"{item.provider} → {item.requester}" if item.provider else str(item.requester)
        out.append(annotation(level, f"{item.name}: {ends}: {item.message}", file=where,
                              line=line_of(index, item.requester.node, item.requester.kind, item.name),
                              title=_title(item)))
    for item, message in counted:
        out.append(annotation(annotation_level(item.severity, threshold), message,
                              file=file or (file_of(item.requester.label) if file_of else item.requester.label),
                              title=_title(item)))
    out += acceptance_github(accepted, stale)
    return "\n".join(out) + ("\n" if out else "")
