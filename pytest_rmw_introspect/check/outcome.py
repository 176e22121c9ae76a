"""What a check means: the one pure function from a result (:class:`Checked`) to an
:class:`Outcome` (pass, warn, fail, write the golden, or an error), with the text and JSON of
the report.

Front ends only translate it into their world: the ``interfaces`` marker and contract-file
items into a pytest outcome, ``rmw-introspect check`` into output and an exit status. Writing
the golden (``Verdict.WRITE``) is the front end's job, through ``golden.update``.
"""

from __future__ import annotations

import enum
import textwrap
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

from ..compare.options import ComparisonOptions
from ..errors import RmwIntrospectError
from ..model import interface_version
from ..model.acceptance import Acceptance
from ..model.contract_shapes import ContractNode
from ..model.vocabulary import Severity

if TYPE_CHECKING:  # the findings' types: the drift rules are loaded by the first check (plugin hooks)
    from ..compare.acceptance import Accepted, Finding
    from ..compare.ci_report import ContractOutcome
    from ..compare.compatibility import CompatItem
    from ..compare.drift import DriftItem


class _Described(Protocol):
    def describe(self) -> str: ...


class _Summarised(Protocol):
    def summary(self) -> str: ...


class _WithNodes(Protocol):
    @property
    def nodes(self) -> Mapping[str, ContractNode]: ...
    @property
    def interface_version(self) -> str | None: ...


class Checked(Protocol):
    """A result: what checking one contract found, as everything that reads one (:func:`decide`,
    the baselines, the command line, the plugin) sees it. ``result.ContractCheck`` is its one
    implementation, with ``pipeline.CheckResult`` (a node contract) and
    ``system_pipeline.SystemCheckResult`` (a system contract). ``items``: everything found but
    what the contract accepts (``accepted``); ``stale``: its ``accept:`` entries that accepted
    nothing; ``drifted``: whether the golden differs from the capture (what updating would write)."""

    @property
    def error(self) -> RmwIntrospectError | None: ...
    @property
    def path(self) -> Path: ...
    @property
    def shown(self) -> str: ...
    @property
    def contract(self) -> _WithNodes | None: ...
    @property
    def spec(self) -> _Described | None: ...
    @property
    def capture(self) -> _Summarised | None: ...
    @property
    def options(self) -> ComparisonOptions: ...
    @property
    def items(self) -> Sequence[DriftItem | CompatItem]: ...
    @property
    def accepted(self) -> Sequence[Accepted]: ...
    @property
    def stale(self) -> Sequence[Acceptance]: ...
    @property
    def missing(self) -> bool: ...
    @property
    def drifted(self) -> bool: ...
    @property
    def gains(self) -> list[str]: ...
    @property
    def failed(self) -> bool: ...
    @property
    def stood_in(self) -> list[str]: ...
    def keep(self, items: Iterable[Finding], accepted: Iterable[Accepted] = ()) -> None: ...
    def to_json(self) -> list[dict[str, Any]]: ...
    def render_text(self, accept_command: str | None = None) -> str: ...
    def update(self) -> str | None: ...
    def unfixed(self) -> Sequence[CompatItem]: ...
    def matched(self, *, names: bool) -> str: ...
    def check_notes(self) -> list[str]: ...
    def rule_level_notes(self) -> list[str]: ...
    def for_ci(self, *, written: str | None = None) -> ContractOutcome: ...


class Verdict(enum.Enum):
    PASS = "pass"  # the capture matches the contract
    WARN = "warn"  # drift, all of it below the fail threshold
    FAIL = "fail"  # drift at or above the fail threshold, or the golden is missing
    WRITE = "write"  # updating: the golden is missing or drifted and is to be written
    ERROR = "error"  # the check could not run (no target, bad contract, target failed, ...)


@dataclass(frozen=True)
class Outcome:
    """``message``: the one text for people (the failure, the warning, the error, or
    ``CONTRACT: matches (NODES)``, a system ``CONTRACT: matches (N nodes in P processes)``);
    ``report``: the drift report (empty without drift); ``json``: the drift items as JSON objects, each naming its contract."""

    verdict: Verdict
    message: str
    report: str = ""
    json: list[dict[str, Any]] = field(default_factory=list)
    #: for ``WRITE``: the bump of ``interface_version`` the update needs (updates never change it)
    version_advice: str = ""
    #: for ``WRITE``: what the update leaves broken (system problems at or above ``system_fail_on``),
    #: one sentence; the run fails after writing the golden (:func:`still_broken`)
    unfixed: str = ""

    @property
    def failed(self) -> bool:
        """The run fails: a failure, an error, or a golden written over a system still broken."""
        return self.verdict in (Verdict.FAIL, Verdict.ERROR) or bool(self.unfixed)


def still_broken(result: Checked) -> str:
    """What an update of ``result`` leaves broken, for people ("" when nothing), to follow "updated
    FILE, but": the golden is written, the system problems at or above ``system_fail_on`` are not
    the golden's to fix."""
    unfixed = result.unfixed()
    if not unfixed:
        return ""
    rules = sorted({f"{item.rule} {item.name}" for item in unfixed})
    shown = "; ".join(rules[:5]) + (f"; and {len(rules) - 5} more" if len(rules) > 5 else "")
    return (f"the system still fails its check: {len(unfixed)} system problem(s) "
            f"at or above system_fail_on ({result.options.system_fail_on}): {shown}. An update writes the "
            "contract's nodes, not the launch file's wiring: fix the launch file (or declare the outside world "
            "under `external:`, or accept the finding under `accept:`)")


def decide(result: Checked, *, update: bool, accept_command: str | None = None, verbose: bool = False) -> Outcome:
    """The outcome of ``result``; ``update``: goldens may be written (``--update-golden``,
    ``check --update``); ``accept_command``: the command that accepts the drift, for messages;
    ``verbose``: a passing system check names every node it matched (else it counts them)."""
    if result.error is not None:
        return Outcome(Verdict.ERROR, str(result.error))
    items = result.to_json()
    if result.contract is None:
        if update:
            return Outcome(Verdict.WRITE, f"{result.shown}: to be created", report=result.render_text()
                           if result.unfixed() else "", json=items, unfixed=still_broken(result))
        assert result.spec is not None and result.capture is not None
        return Outcome(
            Verdict.FAIL,
            f"The golden contract {result.shown} does not exist. Create it from the current capture of "
            f"{result.spec.describe()} with:\n  {accept_command}\n\nCaptured:\n"
            + textwrap.indent(result.capture.summary(), "  "),
            json=items,
        )
    gains = result.gains
    if result.items and all(i.severity is Severity.NOTE for i in result.items) and not result.failed and not (update and result.drifted):
        # notes (Severity.NOTE) only: a pass, with the notes shown (report, JSON) and nothing to accept
        nodes = result.matched(names=verbose)
        count = len(result.items)
        turned_off = "".join(f"; {said}" for said in result.rule_level_notes())
        return Outcome(Verdict.PASS, f"{result.shown}: matches ({nodes}); {count} note{'' if count == 1 else 's'}"
                       f"{turned_off}",
                       report=result.render_text(), json=items)
    if not result.items and not (update and gains):
        nodes = result.matched(names=verbose)
        hint = (f"; it does not state {', '.join(gains)} yet: {accept_command} adds them"
                if gains and accept_command else "")
        if result.stood_in:
            hint += f"; stood in for, not run here: {', '.join(result.stood_in)}"
        hint += "".join(f"; {said}" for said in result.rule_level_notes())
        in_baseline = sum(1 for entry in result.accepted if entry.acceptance.baseline)
        if in_baseline:
            hint = f"; {in_baseline} finding(s) in the baseline{hint}"
        if len(result.accepted) > in_baseline:
            hint = f"; {len(result.accepted) - in_baseline} finding(s) accepted in the contract{hint}"
        if result.stale:
            entries = "; ".join(entry.describe() for entry in result.stale)
            return Outcome(Verdict.WARN, f"{result.shown}: matches ({nodes}){hint}; but {len(result.stale)} `accept:` "
                           f"entr{'y' if len(result.stale) == 1 else 'ies'} match nothing any more ({entries}): "
                           "remove them", report=result.render_text(), json=items)
        return Outcome(Verdict.PASS, f"{result.shown}: matches ({nodes}){hint}", json=items if result.accepted else [])
    if update and result.drifted:
        text = result.render_text() if result.items else f"{result.shown}: adds {', '.join(gains)}\n"
        advice = interface_version.advice(result.items, result.contract.interface_version)
        return Outcome(Verdict.WRITE, text, report=text, json=items,
                       version_advice=f"{result.shown}: {advice}" if advice else "", unfixed=still_broken(result))
    # a system check can find problems without drift: nothing to accept then
    text = result.render_text(accept_command=accept_command if result.drifted else None)
    if result.failed:
        return Outcome(Verdict.FAIL, text, report=text, json=items)
    if not result.drifted:
        warning = f"{len(result.items)} system problem(s) in {result.shown} below the fail threshold"
        return Outcome(Verdict.WARN, warning, report=text, json=items)
    warning = (
        f"{len(result.items)} interface change(s) against {result.shown} below the fail threshold "
        f"({result.options.fail_on}); accept them with {accept_command}"
    )
    return Outcome(Verdict.WARN, warning, report=text, json=items)
