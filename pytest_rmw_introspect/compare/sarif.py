"""SARIF 2.1.0 logs (``--format sarif``): the results of ``check``, ``diff``, ``compat`` and
``validate`` for code-scanning tools (GitHub code scanning, IDE SARIF viewers).

One run of the tool ``rmw-introspect`` (``tool_version``: the version the front end gives; the
compare layer does not import it). Its ``rules`` are every rule of docs/drift-rules.md (drift,
field-level type, parameter and compatibility rules) plus the tool's own (a contract that could not be
checked or is invalid), each with its description and a default level from its severity
(BREAKING error, RISKY warning, SAFE and NOTE note). One result per drift item or system
problem, on the contract line of its interface (else of its node, else the file). A result's
level says whether it fails the run: ``error`` at or above the fail threshold, otherwise the
default level of its severity capped at ``warning``.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any
from urllib.parse import quote

from ..model.acceptance import Acceptance
from ..model.locate import LineIndex, line_of
from ..model.vocabulary import LABELS, Severity
from . import compatibility, drift, findings, report
from .acceptance import Accepted
from .ci_report import ContractOutcome
from .compatibility import CompatItem
from .drift import DriftItem

VERSION = "2.1.0"
SCHEMA_URI = "https://json.schemastore.org/sarif-2.1.0.json"
TOOL_NAME = "rmw-introspect"
#: SARIF's base for the relative paths of the contracts: the directory the command ran in
SRCROOT = "%SRCROOT%"
#: the key of :func:`findings.fingerprint` in ``partialFingerprints``
FINGERPRINT = "rmwIntrospectFinding/v1"

CONTRACT_NOT_CHECKED = "CONTRACT_NOT_CHECKED"
CONTRACT_INVALID = "CONTRACT_INVALID"
ACCEPTANCE_STALE = report.STALE_RULE
#: the tool's own rules: rule id → (severity, summary)
TOOL_RULES: dict[str, tuple[Severity, str]] = {
    CONTRACT_NOT_CHECKED: (Severity.BREAKING, "the contract could not be checked (missing or malformed contract, "
                           "no target, a target that fails, hangs or creates no node, setup)"),
    CONTRACT_INVALID: (Severity.BREAKING, "the contract file is not valid (YAML syntax, schema, QoS values, "
                       "duplicate interfaces, contract_version)"),
    ACCEPTANCE_STALE: (Severity.RISKY, "an `accept:` entry of the contract matches no finding any more: remove it "
                       "before it hides a new one"),
}

_DEFAULT_LEVEL = {Severity.BREAKING: "error", Severity.RISKY: "warning", Severity.SAFE: "note", Severity.NOTE: "note"}


def rules() -> dict[str, tuple[Severity, str]]:
    """Every rule a result can name: rule id → (severity, summary), in a stable order."""
    table = {rule_id: (rule.severity, rule.summary) for rule_id, rule in drift.RULES.items()}
    table.update((rule_id, (severity, compatibility.SUMMARIES[rule_id])) for rule_id, severity in compatibility.RULES.items())
    table.update(TOOL_RULES)
    return table


def level(severity: Severity, threshold: Severity) -> str:
    """``error`` when ``severity`` fails the run, else its default level capped at ``warning``."""
    if severity >= threshold:
        return "error"
    return "note" if severity <= Severity.SAFE else "warning"


def _descriptor(rule_id: str, severity: Severity, summary: str) -> dict[str, Any]:
    return {
        "id": rule_id,
        "shortDescription": {"text": summary},
        "fullDescription": {"text": f"{summary} ({severity.name}; docs/drift-rules.md of pytest-rmw-introspect "
                                    "gives the reason for each severity)"},
        "defaultConfiguration": {"level": _DEFAULT_LEVEL[severity]},
        "properties": {"severity": severity.name},
    }


def uri(path: str) -> dict[str, str]:
    """A SARIF ``artifactLocation`` for a path as shown: relative paths against %SRCROOT%."""
    if Path(path).is_absolute():
        return {"uri": Path(path).as_uri()}
    return {"uri": quote(Path(path).as_posix()), "uriBaseId": SRCROOT}


def _location(file: str, line: int | None, logical: str | None = None) -> dict[str, Any]:
    physical: dict[str, Any] = {"artifactLocation": uri(file)}
    if line:
        physical["region"] = {"startLine": line}
    location: dict[str, Any] = {"physicalLocation": physical}
    if logical:
        location["logicalLocations"] = [{"fullyQualifiedName": logical}]
    return location


def _launch_locations(item: CompatItem, launched_at: Mapping[str, str]) -> list[dict[str, Any]]:
    """Where the launch file starts the processes of a system problem's ends (``file:line``)."""
    related: list[dict[str, Any]] = []
    seen: set[str] = set()
    for end in [e for e in (item.requester, item.provider) if e is not None]:
        where = launched_at.get(end.label)
        if not where or where in seen:
            continue
        seen.add(where)
        file, _, line = where.rpartition(":")
        location = _location(file, int(line)) if file and line.isdigit() else _location(where, None)
        related.append({"id": len(related), **location,
                        "message": {"text": f"the launch file starts {end.label} here ({where})"}})
    return related


def _set_by(item: DriftItem | CompatItem) -> dict[str, str]:
    """A result's ``levelSetBy`` property when the project set its rule's level (``rules``)."""
    return {"levelSetBy": item.level_set_by} if item.level_set_by else {}


class _Log:
    """One SARIF run being filled: results refer to the rule table by index."""

    def __init__(self, tool_version: str | None) -> None:
        self.tool_version = tool_version
        self.table = rules()
        self.index = {rule_id: i for i, rule_id in enumerate(self.table)}
        self.results: list[dict[str, Any]] = []
        self.successful = True

    def add(self, rule_id: str, result_level: str, message: str, location: dict[str, Any],
            *, fingerprint: str | None = None, properties: Mapping[str, Any] | None = None,
            accepted_by: Acceptance | None = None) -> None:
        result: dict[str, Any] = {"ruleId": rule_id, "ruleIndex": self.index[rule_id], "level": result_level,
                                  "message": {"text": message}, "locations": [location]}
        if accepted_by is not None:  # SARIF's own word for it: suppressed in the source, with the reason
            result["suppressions"] = [{"kind": "external", "status": "accepted", "justification": accepted_by.reason}
                                      if accepted_by.baseline else
                                      {"kind": "inSource", "status": "accepted", "justification": accepted_by.reason,
                                       "location": _location(accepted_by.source, accepted_by.line)}]
        if fingerprint:
            result["partialFingerprints"] = {FINGERPRINT: fingerprint}
        if properties:
            result["properties"] = dict(properties)
        self.results.append(result)

    def add_drift(self, item: DriftItem, *, file: str, lines: LineIndex, threshold: Severity,
                  accepted_by: Acceptance | None = None) -> None:
        where = item.node if item.kind == "node" else f"{item.node} {LABELS.get(item.kind, item.kind)} {item.name}"
        logical = item.node if item.kind == "node" else f"{item.node}/{item.kind}/{item.name}"
        self.add(item.rule, level(item.severity, threshold), f"{where}: {item.message}",
                 _location(file, line_of(lines, item.node, item.kind, item.name), logical),
                 fingerprint=findings.fingerprint(item),
                 properties={"severity": item.severity.name, "node": item.node, "kind": item.kind,
                             "name": item.name, "change": item.change, **_set_by(item)}, accepted_by=accepted_by)

    def add_compat(self, item: CompatItem, *, file: str, lines: LineIndex, threshold: Severity,
                   accepted_by: Acceptance | None = None, launched_at: Mapping[str, str] | None = None) -> None:
        ends = f"{item.provider} → {item.requester}" if item.provider else str(item.requester)
        self.add(item.rule, level(item.severity, threshold), f"{item.name}: {ends}: {item.message}",
                 _location(file, line_of(lines, item.requester.node, item.requester.kind, item.name),
                           f"{item.requester.node}/{item.requester.kind}/{item.name}"),
                 fingerprint=findings.fingerprint(item),
                 properties={"severity": item.severity.name, "name": item.name,
                             "requester": item.requester.label, "provider": item.provider.label if item.provider else None,
                             **_set_by(item)},
                 accepted_by=accepted_by)
        related = _launch_locations(item, launched_at or {})
        if related:
            self.results[-1]["relatedLocations"] = related

    def add_acceptances(self, accepted: Sequence[Accepted], stale: Sequence[Acceptance], *,
                        lines: Mapping[str, LineIndex], drift_threshold: Severity, system_threshold: Severity,
                        file: str | None = None) -> None:
        """Accepted findings as suppressed results, on ``file`` (default: the contract that
        accepts them); stale entries as results on their own lines."""
        for entry in accepted:
            where = file or entry.acceptance.source
            if isinstance(entry.item, DriftItem):
                self.add_drift(entry.item, file=where, lines=lines.get(where, {}), threshold=drift_threshold,
                               accepted_by=entry.acceptance)
            else:
                self.add_compat(entry.item, file=where, lines=lines.get(where, {}), threshold=system_threshold,
                                accepted_by=entry.acceptance)
        for acceptance in stale:
            self.add(ACCEPTANCE_STALE, "warning", f"`accept:` entry {acceptance.describe()} matches nothing any more "
                     f"(reason given: {acceptance.reason}); remove it", _location(acceptance.source, acceptance.line))

    def add_error(self, rule_id: str, message: str, *, file: str, line: int | None = None) -> None:
        self.successful = False
        self.add(rule_id, "error", message, _location(file, line))

    def document(self) -> dict[str, Any]:
        descriptors = [_descriptor(rule_id, severity, summary) for rule_id, (severity, summary) in self.table.items()]
        driver: dict[str, Any] = {"name": TOOL_NAME, "informationUri": "https://pypi.org/project/pytest-rmw-introspect/"}
        if self.tool_version:
            driver.update(version=self.tool_version, semanticVersion=self.tool_version)
        run = {
            "tool": {"driver": {**driver, "rules": descriptors}},
            "originalUriBaseIds": {SRCROOT: {"uri": Path.cwd().as_uri() + "/"}},
            "invocations": [{"executionSuccessful": self.successful}],
            "results": self.results,
        }
        return {"$schema": SCHEMA_URI, "version": VERSION, "runs": [run]}


def drift_log(outcomes: Iterable[ContractOutcome], *, tool_version: str | None = None) -> dict[str, Any]:
    """``check`` and ``diff``: a result per drift item (and system problem of a system contract)
    on its contract's lines; a contract that could not be checked is one error result."""
    log = _Log(tool_version)
    for outcome in outcomes:
        if outcome.error is not None:
            log.add_error(CONTRACT_NOT_CHECKED, outcome.error.rstrip("\n"), file=outcome.contract)
            continue
        for item in outcome.items:
            log.add_drift(item, file=outcome.contract, lines=outcome.lines, threshold=outcome.threshold)
        for compat_item in outcome.system_items:
            log.add_compat(compat_item, file=outcome.contract, lines=outcome.lines, threshold=outcome.system_threshold,
                           launched_at=outcome.launched_at)
        log.add_acceptances(outcome.accepted, outcome.stale, file=outcome.contract,
                            lines={outcome.contract: outcome.lines}, drift_threshold=outcome.threshold,
                            system_threshold=outcome.system_threshold)
    return log.document()


def compat_log(items: Sequence[CompatItem], *, threshold: Severity,
               lines: Mapping[str, LineIndex] | None = None,
               file_of: Callable[[str], str] | None = None, tool_version: str | None = None,
               accepted: Sequence[Accepted] = (), stale: Sequence[Acceptance] = ()) -> dict[str, Any]:
    """``compat``: a result per system problem, on the requesting end's contract and line.
    ``file_of`` maps an end's label to its contract file (default: the label is the file; a
    system contract's processes are labelled ``FILE: package/executable``)."""
    log = _Log(tool_version)
    for item in items:
        where = file_of(item.requester.label) if file_of else item.requester.label
        log.add_compat(item, file=where, lines=(lines or {}).get(where, {}), threshold=threshold)
    log.add_acceptances(accepted, stale, lines=lines or {}, drift_threshold=threshold, system_threshold=threshold)
    return log.document()


def invalid_log(invalid: Iterable[tuple[str, int | None, str]], *, tool_version: str | None = None) -> dict[str, Any]:
    """``validate``: a result per invalid file, ``(file, line or None, reason)``."""
    log = _Log(tool_version)
    for file, line, reason in invalid:
        log.add_error(CONTRACT_INVALID, reason, file=file, line=line)
    return log.document()
