"""One contract compared with another version of itself, without running anything: the one diff
core of ``diff OLD NEW``, ``diff --against REF`` and the pytest gate items (issue 51 item 1).

Every pair is read by ``model.contract_kind`` (node contracts, marker goldens, NoDL documents and
system contracts alike) and compared by :func:`compare_contracts`, the drift rules of a check with
the older file playing the contract and the newer the capture: the same rules, severities and
middleware (:func:`said_middleware`: a system contract is judged for the middleware it says it
runs on) whichever command asked. Each pair becomes one :class:`DiffResult`, which every report
format reads (``cli/emit.py``): two files (``diff OLD NEW``), or a contract against its file at a
git revision (``check.gate``: its status, interface versions, ``accept:`` entries and baseline).

A ``DiffResult`` is not a ``check.result.ContractCheck``: that core's half is the capture and the
golden (what ran, what an update writes, what the contract would gain), which a diff has none of.
What a diff and a check share is below it: ``compare.drift.compare`` (which
:func:`compare_contracts` wraps with the NoDL projection and the distribution's type hashes),
``compare.rule_levels``, ``compare.acceptance`` and the report model (``compare.report``,
``ContractOutcome`` for the CI formats).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..compare import drift, report, rule_levels
from ..compare.acceptance import Accepted
from ..compare.ci_report import ContractOutcome
from ..compare.drift import DriftItem
from ..compare.options import ComparisonOptions
from ..compare.rule_levels import RuleLevel
from ..model import contract_kind, nodl
from ..model.contract import Contract
from ..model.contract_kind import Kind
from ..model.interface_version import Bump
from ..model.locate import LineIndex
from ..model.paths import shown as display
from ..model.vocabulary import Severity
from .pipeline import Layers, OptionLayer


@dataclass
class DiffResult:
    """One contract compared with another version of itself (``kind``: what it is now).

    ``shown`` is the newer file as shown (a removed one: as it was), ``against`` the older one
    (``REF:path`` at a git revision; None: added since REF). ``revision`` is the REF of a gate's
    pair (None: two files, ``diff OLD NEW``); ``status`` says what happened to the file since REF
    (``changed``, ``renamed``, ``added``, ``removed``, ``unchanged``, ``unreadable``).
    ``threshold`` is the least severe finding that fails: the gate's (``--fail-on``, else
    breaking), else the options' ``fail_on``."""

    shown: str
    against: str | None
    options: ComparisonOptions = field(default_factory=ComparisonOptions)
    items: list[DriftItem] = field(default_factory=list)
    kind: Kind = Kind.NODE
    old: Contract | None = None
    new: Contract | None = None
    revision: str | None = None
    path: Path | None = None  # the file in the work tree (a removed one: where it was)
    status: str = "changed"
    fail_at: Severity | None = None
    #: what the contract's ``accept:`` entries, the interface versions and a baseline accepted
    accepted: list[Accepted] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    error: str | None = None
    nodes: list[str] = field(default_factory=list)
    lines: LineIndex = field(default_factory=dict)
    #: the project's levels of rules (``compare.rule_levels``) and how many findings they turned off
    rules: tuple[RuleLevel, ...] = ()
    turned_off: int = 0
    #: the bump the drift needs under semantic versioning, and the versions before and now
    needs: Bump = Bump.NONE
    versions: tuple[str | None, str | None] = (None, None)

    @property
    def old_shown(self) -> str | None:
        return self.against

    @property
    def new_shown(self) -> str:
        return self.shown

    @property
    def threshold(self) -> Severity:
        return self.fail_at if self.fail_at is not None else self.options.threshold()

    @property
    def failed(self) -> bool:
        return self.error is not None or report.fails(self.items, self.threshold)

    def heading(self) -> str:
        if self.status == "renamed":
            return f"{self.shown} (renamed from {self.against})"
        if self.status == "added":
            return f"{self.shown} (added since the base revision)"
        if self.status == "removed":
            return f"{self.shown} (removed: everything it promised is gone)"
        if self.status == "unreadable":
            return f"{self.shown} (could not be read)"
        return self.shown

    def render_text(self) -> str:
        if self.error is not None:
            return f"{self.shown}: error: {self.error}\n"
        text = report.render_text(self.items, contract_path=self.against, threshold=self.threshold,
                                  title=f"Interface drift of {self.heading()}", accepted=self.accepted)
        return text + "".join(f"  note: {note}\n" for note in self.notes)

    def to_json(self) -> list[dict[str, Any]]:
        """The items, each naming its contract: at a revision the contract file, with the file at
        REF (``against``) and its ``status``; of two files OLD, which plays the contract."""
        if self.revision is None:
            return [{"contract": self.against, **item} for item in report.to_json(self.items)]
        where = {"contract": self.shown, "against": self.against, "status": self.status}
        if self.error is not None:
            return [{**where, "error": self.error}]
        return ([{**where, **item} for item in report.to_json(self.items)]
                + [{**where, **item} for item in report.accepted_to_json(self.accepted)])

    def for_ci(self) -> ContractOutcome:
        """For the CI formats: annotations point at the newer file, the one a pull request changes."""
        return ContractOutcome(contract=self.shown, items=self.items, threshold=self.threshold, nodes=self.nodes,
                               error=self.error, lines=self.lines, accepted=self.accepted, notes=tuple(self.notes))


def diff_contracts(
    old_path: str | Path,
    new_path: str | Path,
    options: Sequence[OptionLayer] | Mapping[str, Any] | ComparisonOptions | None = None,
) -> DiffResult:
    """Compare two contract files of any kind (node contracts, marker goldens, NoDL documents,
    system contracts; ``model.contract_kind``) without running anything: ``old`` plays the
    contract, ``new`` the capture, so the rules and severities are those of a check.

    ``options``: a :class:`ComparisonOptions`, a mapping of option values, or layers stacked on
    top of the old contract's ``options:`` block. ``include_infrastructure`` has no effect
    (both files already list what they list). When both files have a ``types:`` section, a
    changed type is reported field by field. Raises :class:`ContractError`.
    """
    old_shown, new_shown = display(old_path), display(new_path)
    old, _ = contract_kind.load(old_path)
    new, kind = contract_kind.load(new_path)
    if isinstance(options, ComparisonOptions):
        opts = options
    else:
        if isinstance(options, Mapping):
            layers: Sequence[OptionLayer] = [(options, "diff_contracts()")]
        else:
            layers = options or ()
        opts = Layers(strong_options=layers).options(old, shown=old_shown)
    opts = said_middleware(old, new, opts)
    leveled = rule_levels.apply(compare_contracts(old, new, opts), opts.rules)  # the project's levels of rules
    return DiffResult(new_shown, old_shown, opts, leveled.items, kind, old, new, nodes=sorted(new.nodes),
                      lines=new.lines(), rules=opts.rules, turned_off=leveled.off,
                      notes=[rule_levels.turned_off_text(leveled.off)] if leveled.off else [])


def said_middleware(old: Contract, new: Contract, options: ComparisonOptions) -> ComparisonOptions:
    """``options`` judging for the middleware a system contract of the pair says it runs on
    (NEW's word first; it wins over the option ``rmw``, which is for contracts that do not say)."""
    said = new.middleware or old.middleware
    return dataclasses.replace(options, rmw=said) if said is not None else options


def compare_contracts(old: Contract, new: Contract, options: ComparisonOptions) -> list[DriftItem]:
    """The drift from ``old`` (playing the contract) to ``new`` (playing the capture): what a NoDL
    side does not state is not compared; type sections field by field; distributions noted."""
    old_nodes, new_nodes = old.nodes, new.nodes
    if old.nodl is not None:  # what a NoDL side does not state is not compared
        new_nodes = nodl.project(new_nodes, old_nodes)
    if new.nodl is not None:
        old_nodes = nodl.project(old_nodes, new_nodes)
    return drift.attribute_to_distribution(
        drift.compare(old_nodes, new_nodes, options, expected_types=old.types, actual_types=new.types),
        old.ros_distribution, new.ros_distribution)
