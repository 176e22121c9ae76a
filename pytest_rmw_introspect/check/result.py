"""The result core: what checking one contract found, a node contract's or a system contract's.

:class:`ContractCheck` holds what both kinds of check have and says once what it means: the
findings (``drift_items``, and the ``system_items`` only a system check finds), what the
contract's ``accept:`` entries accepted, whether the contract is ``missing``, whether the check
``failed`` (``fail_on`` for drift, ``system_fail_on`` for system problems), what updating would
add (``gains``) and the ``nodes`` it would write (:meth:`ContractCheck.golden_nodes`), the JSON
of the findings. ``pipeline.CheckResult`` (a node contract: a target, a ``Capture``) and
``system_pipeline.SystemCheckResult`` (a system contract: a launch file, a ``SystemCapture``)
add what differs: how a name changes every run, what a passing check matched, the report's
text, the golden's writing and the CI formats.

A base dataclass rather than a component both results hold: everything that reads a result
(``check.outcome.decide``, the baselines, the command line, the plugin) reads these fields and
properties of the result itself, as ``outcome.Checked`` states them; a component would have to
be forwarded name by name from both results, twins again. The base is generic in the three
things that differ in kind (the contract, what runs, the capture), so that each result keeps
its precise types.
"""

from __future__ import annotations

import abc
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Generic, Protocol, TypeVar

from ..compare import parameter_drift, report, rule_levels
from ..compare.acceptance import Accepted, Finding
from ..compare.ci_report import ContractOutcome
from ..compare.compatibility import CompatItem
from ..compare.drift import DriftItem
from ..compare.options import ComparisonOptions
from ..errors import RmwIntrospectError
from ..model.acceptance import Acceptance
from ..model.contract_shapes import ContractNode, ContractNodes
from ..model.unstable_names import NameRules
from ..model.vocabulary import Severity


class _WithNodes(Protocol):
    @property
    def nodes(self) -> Mapping[str, ContractNode]: ...


class _Described(Protocol):
    def describe(self) -> str: ...


class _Captured(Protocol):
    def to_contract_nodes(self, *, with_type_hash: bool = True, with_qos: bool = True,
                          names: NameRules | None = None) -> ContractNodes: ...
    def notes(self) -> list[str]: ...
    def summary(self) -> str: ...


ContractT = TypeVar("ContractT", bound=_WithNodes)
SpecT = TypeVar("SpecT", bound=_Described)
CaptureT = TypeVar("CaptureT", bound=_Captured)


@dataclass
class ContractCheck(abc.ABC, Generic[ContractT, SpecT, CaptureT]):
    """What checking one contract found (the fields and rules node and system checks share).

    ``contract``: None when the file does not exist (or could not be loaded: then ``error``);
    ``spec``: what was run; ``error``: the RmwIntrospectError that stopped the check.
    """

    path: Path
    shown: str
    contract: ContractT | None = None
    spec: SpecT | None = None
    options: ComparisonOptions = field(default_factory=ComparisonOptions)
    capture: CaptureT | None = None
    #: the drift of the contract's nodes (empty when it matches, or without contract or capture)
    drift_items: list[DriftItem] = field(default_factory=list)
    #: the problems the compatibility rules found in a system (a node check finds none)
    system_items: list[CompatItem] = field(default_factory=list)
    error: RmwIntrospectError | None = None
    #: findings the contract's ``accept:`` entries (or a baseline) accept, in neither list above,
    #: and the entries that accepted nothing
    accepted: list[Accepted] = field(default_factory=list)
    stale: list[Acceptance] = field(default_factory=list)
    #: how many findings the project's ``rules`` turned off (``compare.rule_levels``)
    turned_off: int = 0

    # ------------------------------------------------------------------------ the findings

    @property
    def items(self) -> list[DriftItem | CompatItem]:
        """Everything found but what is accepted: the drift, then the system problems."""
        return [*self.drift_items, *self.system_items]

    def keep(self, items: Iterable[Finding], accepted: Iterable[Accepted] = ()) -> None:
        """Keep only ``items`` of the findings, sorted into drift and system problems; add
        ``accepted`` to the findings accepted (by the contract's ``accept:`` entries, a baseline)."""
        kept = list(items)
        self.drift_items = [item for item in kept if isinstance(item, DriftItem)]
        self.system_items = [item for item in kept if isinstance(item, CompatItem)]
        self.accepted = [*self.accepted, *accepted]

    @property
    def threshold(self) -> Severity:
        """The least severe drift that fails (``fail_on``)."""
        return self.options.threshold()

    @property
    def system_threshold(self) -> Severity:
        """The least severe system problem that fails (``system_fail_on``)."""
        return self.options.system_threshold()

    @property
    def missing(self) -> bool:
        """The contract file does not exist (and there was a capture to create it from)."""
        return self.contract is None and self.error is None

    @property
    def failed(self) -> bool:
        """An error, a missing contract, drift at or above ``fail_on``, or a system problem at or
        above ``system_fail_on``."""
        return (self.error is not None or self.missing or report.fails(self.drift_items, self.threshold)
                or report.fails(self.system_items, self.system_threshold))

    def unfixed(self) -> list[CompatItem]:
        """The system problems at or above ``system_fail_on``: what an update leaves broken (it
        writes the contract's nodes, not the launch file's wiring). A node check has none."""
        return [item for item in self.system_items if item.severity >= self.system_threshold]

    @property
    def drifted(self) -> bool:
        """The golden differs from what updating would write: drift, or sections the contract
        does not state yet (:attr:`gains`). (System problems are not the golden's to fix; a note,
        ``Severity.NOTE``, is no drift an update must accept.)"""
        return any(item.severity > Severity.NOTE for item in self.drift_items) or bool(self.gains)

    def to_json(self) -> list[dict[str, Any]]:
        """``report.to_json`` of the drift and ``report.compat_to_json`` of the system problems,
        then the accepted findings (with ``accepted``) and the stale ``accept:`` entries
        (``ACCEPTANCE_STALE``), each naming the ``contract`` it belongs to."""
        found = [*report.to_json(self.drift_items), *report.compat_to_json(self.system_items),
                 *report.accepted_to_json(self.accepted), *report.stale_to_json(self.stale)]
        return [{"contract": self.shown, **item} for item in found]

    # ------------------------------------------------------------------------ the golden

    @property
    def gains(self) -> list[str]:
        """What updating would add to a contract that matches but does not state it yet (the
        parameters and lifecycle states of nodes written before they were recorded)."""
        if self.contract is None or self.capture is None or self.error is not None or not self.can_gain():
            return []
        return parameter_drift.gains(self.contract.nodes, self.golden_nodes())

    def can_gain(self) -> bool:
        """Whether the contract can state more than it does (see :attr:`gains`)."""
        return True

    def golden_nodes(self) -> ContractNodes:
        """The ``nodes`` to write when accepting the capture as the new contract (ignored
        parameters as the contract has them)."""
        assert self.capture is not None, "no capture to accept"
        opts = self.options
        nodes = self.capture.to_contract_nodes(with_type_hash=not opts.ignore_type_hash,
                                               with_qos=not opts.ignores_all_qos, names=self.name_rules())
        return parameter_drift.keep_ignored(self.contract.nodes if self.contract is not None else None, nodes, opts)

    @abc.abstractmethod
    def name_rules(self) -> NameRules:
        """The contract's patterns of node names that change every run (``model.unstable_names``)."""

    @abc.abstractmethod
    def update(self) -> str | None:
        """Write the golden (``golden``): ``created``, ``updated`` or None."""

    # ------------------------------------------------------------------------ for people

    def rule_level_notes(self) -> list[str]:
        """What the project's ``rules`` did that no finding shows: the findings they turned off."""
        return [rule_levels.turned_off_text(self.turned_off)] if self.turned_off else []

    def title(self) -> str:
        return f"Interface drift of {self.spec.describe()}" if self.spec is not None else "Interface drift"

    @abc.abstractmethod
    def matched(self, *, names: bool) -> str:
        """What a passing check matched (``names``: name every node)."""

    @property
    @abc.abstractmethod
    def stood_in(self) -> list[str]:
        """The processes not run here, each with the file that stood in for it."""

    @abc.abstractmethod
    def check_notes(self) -> list[str]:
        """What the check notes beside its findings, not about the capture (the report lists
        them with the capture's notes; ``check`` says them when there is no report)."""

    def findings_text(self, *, accept_command: str | None, system_title: str) -> str:
        """The drift report (also when nothing at all was found), then the system problems under
        ``system_title``, then what was accepted and the stale ``accept:`` entries."""
        parts = []
        if self.drift_items or not self.system_items:
            parts.append(report.render_text(self.drift_items, contract_path=self.shown, threshold=self.threshold,
                                            accept_command=accept_command if self.drift_items else None,
                                            title=self.title()))
        if self.system_items:
            parts.append(report.render_system_problems(self.system_items, threshold=self.system_threshold,
                                                       title=system_title))
        text = "\n".join(p.rstrip("\n") + "\n" for p in parts)
        if self.accepted or self.stale:
            text += "\n".join(report.render_acceptances(self.accepted, self.stale)).lstrip("\n") + "\n"
        return text

    @abc.abstractmethod
    def render_text(self, accept_command: str | None = None) -> str:
        """The report for people (the same text as a failing test)."""

    @abc.abstractmethod
    def for_ci(self, *, written: str | None = None) -> ContractOutcome:
        """This result for the CI formats (``--format markdown|github|sarif``)."""
