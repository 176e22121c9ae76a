"""The one writer of a command's report in each ``--format`` (text, json, markdown, github, sarif,
junit).

A command that reports drift or incompatibility (``check``, ``diff``, ``diff --against``,
``compat``) describes its outcome as a :class:`Report` and hands it to :func:`emit`; no command
has a format ladder of its own, so a format that works for one kind of contract works for every
kind (the system ``diff`` once printed text for ``--format markdown`` and ``github``).
"""

from __future__ import annotations

import json
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, TextIO

from .._version import __version__
from ..compare import ci_report, junit, sarif

if TYPE_CHECKING:
    from ..check.pipeline import CompatibilityResult
    from ..compare.ci_report import ContractOutcome


@dataclass(frozen=True)
class Report:
    """What a command found, in the forms the formats need.

    ``text``: the report for people (``""`` when the command wrote it as it went); ``data``: what
    ``--format json`` prints; ``outcomes``: the contracts' outcomes that the drift formats
    (markdown, github, sarif) are written from, or ``compat``: the system check of ``compat``.
    ``title`` and ``intro`` head the Markdown report; ``notice`` is an annotation said first
    under ``--format github`` (the gate: what it looked at). ``invalid``: the files ``validate``
    refused, each ``(file, line, message, reason)``, and ``read`` every file it read (each a JUnit test
    case)."""

    text: str | Callable[[], str]
    data: Any
    outcomes: Sequence[ContractOutcome] = ()
    compat: CompatibilityResult | None = None
    title: str = "Interface contracts"
    intro: Sequence[str] = ()
    notice: str | None = None
    invalid: Sequence[tuple[str, int | None, str, str]] | None = None
    read: Sequence[str] = ()

    def markdown(self) -> str:
        """The Markdown report (what ``--summary FILE`` appends, too)."""
        if self.compat is not None:
            return ci_report.compat_markdown(self.compat.items, threshold=self.compat.threshold,
                                             labels=self.compat.labels)
        return ci_report.drift_markdown(self.outcomes, title=self.title, intro=self.intro)

    def github(self) -> str:
        head = ci_report.annotation("notice", self.notice, title="rmw-introspect gate") + "\n" if self.notice else ""
        if self.invalid is not None:  # validate: an annotation per invalid file, nothing else
            return head + "".join(ci_report.annotation("error", reason, file=file, line=line,
                                                       title="invalid contract") + "\n"
                                  for file, line, _message, reason in self.invalid)
        compat = self.compat
        if compat is not None:
            return head + ci_report.compat_github(compat.items, threshold=compat.threshold, lines=compat.lines,
                                                  file_of=compat.file_of, accepted=compat.accepted,
                                                  stale=compat.stale)
        return head + ci_report.drift_github(self.outcomes)

    def sarif(self) -> dict[str, Any]:
        if self.invalid is not None:
            return sarif.invalid_log([(file, line, message) for file, line, message, _ in self.invalid],
                                     tool_version=__version__)
        compat = self.compat
        if compat is not None:
            return sarif.compat_log(compat.items, threshold=compat.threshold, lines=compat.lines,
                                    file_of=compat.file_of, tool_version=__version__, accepted=compat.accepted,
                                    stale=compat.stale)
        return sarif.drift_log(self.outcomes, tool_version=__version__)

    def junit(self) -> str:
        """JUnit XML: a test case per contract (``compare.junit``)."""
        if self.invalid is not None:
            return junit.invalid_junit(self.read, [(file, line, message) for file, line, message, _r in self.invalid])
        compat = self.compat
        if compat is not None:
            return junit.compat_junit(compat.items, threshold=compat.threshold, labels=compat.labels,
                                      file_of=compat.file_of)
        return junit.drift_junit(self.outcomes)

    def rendered_text(self) -> str:
        return self.text() if callable(self.text) else self.text


#: every --format a report command takes, and how it is written
WRITERS: dict[str, Callable[[Report], str]] = {
    "text": Report.rendered_text,
    "json": lambda report: json.dumps(report.data, indent=2, default=str) + "\n",
    "markdown": Report.markdown,
    "github": Report.github,
    "sarif": lambda report: json.dumps(report.sarif(), indent=2) + "\n",
    "junit": Report.junit,
}


def emit(report: Report, fmt: str, out: TextIO | None = None) -> None:
    """Write ``report`` in the format ``fmt`` (one of :data:`WRITERS`) to ``out`` (stdout)."""
    (out or sys.stdout).write(WRITERS[fmt](report))
