"""JUnit XML of a report (``--format junit``): what CI systems that show test results read
(GitLab, Jenkins, Azure Pipelines, GitHub's test-report actions).

One ``<testcase>`` per contract (``check``, ``check --live``, ``check --bag``, ``diff``, ``diff
--against``), per contract file of a system check (``compat``) or per file ``validate`` read.
A contract whose findings fail it has a ``<failure>`` (its message counts the findings, its text
lists them one per line); one that could not be checked has an ``<error>``; findings below the
threshold, notes and accepted findings are ``<property>`` elements of a passing test case, as
the pytest plugin writes its own (``rmw_introspect_finding``, ``rmw_introspect_note``). Written
with the standard library's ElementTree, so the XML is escaped as XML wants it.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field

from ..model.vocabulary import THRESHOLD_WORDS, Severity
from .ci_report import ContractOutcome
from .compatibility import CompatItem
from .drift import DriftItem

#: the suite every test case is in, and their class name
SUITE = "rmw-introspect"
FINDING_PROPERTY = "rmw_introspect_finding"
NOTE_PROPERTY = "rmw_introspect_note"
ACCEPTED_PROPERTY = "rmw_introspect_accepted"


def _drift_line(item: DriftItem) -> str:
    return f"[{item.rule}] {item.severity.name} {item.node} {item.kind} {item.name}: {item.message}"


def _compat_line(item: CompatItem) -> str:
    ends = str(item.requester) if item.provider is None else f"{item.provider} -> {item.requester}"
    return f"[{item.rule}] {item.severity.name} {item.name} {ends}: {item.message}"


@dataclass
class _Case:
    name: str
    failing: list[str] = field(default_factory=list)
    passing: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    accepted: list[str] = field(default_factory=list)
    error: str | None = None
    #: the failure's message: what the failing lines are
    failure: str = ""


def _failure(failing: Sequence[str], threshold: str) -> str:
    return f"{len(failing)} finding{'' if len(failing) == 1 else 's'} at or above the threshold ({threshold})"


def _document(cases: Sequence[_Case]) -> str:
    failures = sum(1 for case in cases if case.error is None and case.failing)
    errors = sum(1 for case in cases if case.error is not None)
    counts = {"tests": str(len(cases)), "failures": str(failures), "errors": str(errors), "skipped": "0"}
    root = ET.Element("testsuites", {"name": SUITE, **counts})
    suite = ET.SubElement(root, "testsuite", {"name": SUITE, **counts})
    for case in cases:
        element = ET.SubElement(suite, "testcase", {"classname": SUITE, "name": case.name, "file": case.name})
        said = [(FINDING_PROPERTY, line) for line in case.passing] + [(NOTE_PROPERTY, n) for n in case.notes]
        said += [(ACCEPTED_PROPERTY, line) for line in case.accepted]
        if said:
            properties = ET.SubElement(element, "properties")
            for name, value in said:
                ET.SubElement(properties, "property", {"name": name, "value": value})
        if case.error is not None:
            ET.SubElement(element, "error", {"message": case.error.strip().splitlines()[0] if case.error.strip() else
                                             "error", "type": "error"}).text = case.error
        elif case.failing:
            ET.SubElement(element, "failure", {"message": case.failure, "type": SUITE}).text = "\n".join(case.failing)
    ET.indent(root)
    return '<?xml version="1.0" encoding="utf-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def drift_junit(outcomes: Iterable[ContractOutcome]) -> str:
    """A test case per contract outcome: its drift and system problems at or above their
    thresholds fail it; the rest are properties."""
    cases = []
    for outcome in outcomes:
        case = _Case(outcome.contract, error=outcome.error,
                     notes=[*outcome.notes, *(note for note, _line in outcome.notices)])
        for drift_item in outcome.items:
            failing = outcome.written is None and drift_item.severity >= outcome.threshold
            (case.failing if failing else case.passing).append(_drift_line(drift_item))
        for compat_item in outcome.system_items:
            failing = compat_item.severity >= outcome.system_threshold
            (case.failing if failing else case.passing).append(_compat_line(compat_item))
        if outcome.written:
            case.notes.append(f"contract {outcome.written}")
        case.failure = _failure(case.failing, f"fail on: {THRESHOLD_WORDS[outcome.threshold]}")
        case.accepted = [f"[{a.item.rule}] {a.item.message} (accepted: {a.acceptance.reason})" for a in outcome.accepted]
        case.notes += [f"`accept:` entry {entry.describe()} matches nothing; remove it" for entry in outcome.stale]
        cases.append(case)
    return _document(cases)


def compat_junit(items: Sequence[CompatItem], *, threshold: Severity, labels: Sequence[str],
                 file_of: Callable[[str], str] | None = None) -> str:
    """``compat``: a test case per contract file of the system (``labels``, mapped by
    ``file_of``), each problem on the file of its requesting end."""
    where = file_of or (lambda label: label)
    cases = {where(label): _Case(where(label)) for label in labels}
    for item in items:
        case = cases.setdefault(where(item.requester.label), _Case(where(item.requester.label)))
        (case.failing if item.severity >= threshold else case.passing).append(_compat_line(item))
    for case in cases.values():
        case.failure = _failure(case.failing, f"fail on: {THRESHOLD_WORDS[threshold]}")
    return _document(list(cases.values()))


def invalid_junit(files: Sequence[str], invalid: Iterable[tuple[str, int | None, str]]) -> str:
    """``validate``: a test case per file read, an invalid one failing with what is wrong
    (``(file, line or None, message)``: the message as the terminal shows it)."""
    cases = {name: _Case(name) for name in files}
    for file, _line, message in invalid:
        case = cases.setdefault(file, _Case(file))
        case.failing.append(message)
        case.failure = "invalid contract"
    return _document(list(cases.values()))
