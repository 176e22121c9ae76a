"""The check pipeline: the one place that loads a contract, layers its target and options,
captures the target and compares. The ``interfaces`` marker, contract files collected as pytest
items and the ``rmw-introspect`` command line all go through here, and then let
:func:`pytest_rmw_introspect.check.outcome.decide` say what the result means.

Layers (docs/design.md, "Options and their precedence"). Comparison options are ``(mapping,
source)`` pairs and target options ``(mapping, base_dir, source)`` triples; within a list the
later layer wins. :class:`Layers` holds ``weak`` layers, below the contract (ini file, pytest's
command line), and ``strong`` layers, above it (marker keyword arguments, the target flags of
``rmw-introspect``)::

    layers = Layers(strong_target=[({"script": "t.py"}, here, "command line")])
    prepared = prepare("contracts/talker.yaml", layers=layers)
    result = run(prepared, library=lib, ros=ros)      # captures; raises a TargetError
    outcome.decide(result, update=False, accept_command="...")

:func:`check` does both and never raises an :class:`~pytest_rmw_introspect.errors.RmwIntrospectError`:
it is put on ``result.error``. ``check.diff`` compares two contract files without running
anything; ``system_pipeline.check_contracts`` runs the compatibility check over contract files.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeAlias

from ..compare import acceptance, drift, report, rule_levels
from ..compare import type_lock as type_lock_check
from ..compare.acceptance import Accepted
from ..compare.ci_report import ContractOutcome
from ..compare.compatibility import CompatItem
from ..compare.drift import DriftItem
from ..compare.options import ComparisonOptions, resolve
from ..errors import LifecycleTransitionFailed, RmwIntrospectError, TargetConfigError
from ..model import contract as contract_module
from ..model import nodl, type_lock
from ..model import types as type_model
from ..model.acceptance import Acceptance
from ..model.capture import Capture
from ..model.contract import Contract
from ..model.locate import LineIndex
from ..model.option_tables import PRECEDENCE, Source, stack
from ..model.paths import shown as display
from ..model.unstable_names import NameRules
from ..model.vocabulary import Severity
from ..run import runner
from ..run.ros_env import RosEnvironment
from ..run.target import TargetSpec, merge
from . import golden
from .result import ContractCheck

OptionLayer: TypeAlias = tuple[Mapping[str, Any] | None, str]
TargetLayer: TypeAlias = tuple[Mapping[str, Any] | None, "str | Path | None", str]


@dataclass(frozen=True)
class Layers:
    """Where target and comparison options come from around a contract.

    Precedence is the table's (``model.option_tables.PRECEDENCE``), applied here and nowhere
    else, by :func:`~pytest_rmw_introspect.model.option_tables.stack`: ``weak_*`` layers (by
    source: the ini file, pytest's command line) < the contract's ``options:`` / ``target:``
    (paths relative to the contract) < ``strong_*`` layers (the test's or command's own: marker
    keyword arguments, ``rmw_capture()`` arguments, ``rmw-introspect`` flags).
    """

    weak_target: Mapping[Source, Sequence[TargetLayer]] = field(default_factory=dict)
    strong_target: Sequence[TargetLayer] = ()
    weak_options: Mapping[Source, Sequence[OptionLayer]] = field(default_factory=dict)
    strong_options: Sequence[OptionLayer] = ()

    def __post_init__(self) -> None:
        below_contract = set(PRECEDENCE[:PRECEDENCE.index(Source.CONTRACT)])
        assert set(self.weak_target) <= below_contract and set(self.weak_options) <= below_contract

    def target(self, contract: Contract | None = None, *, path: Path | None = None, shown: str = "") -> TargetSpec:
        """The target: the layers around the contract's ``target:`` block (raises TargetConfigError)."""
        around: list[TargetLayer] = []
        if contract is not None and contract.target and path is not None:
            around.append((contract.target, path.absolute().parent, f"{shown}: target"))
        return merge(*stack({**self.weak_target, Source.CONTRACT: around, Source.OWN: self.strong_target}))

    def options(self, contract: Contract | None = None, *, shown: str = "") -> ComparisonOptions:
        """The comparison options: the layers around the contract's ``options:`` block (raises OptionError)."""
        around: list[OptionLayer] = [(contract.options if contract else None, f"{shown}: options")]
        return resolve(*stack({**self.weak_options, Source.CONTRACT: around, Source.OWN: self.strong_options}))


def _default_no_target(contract: Contract | None, shown: str) -> str:
    if contract is None:
        return f"The contract {shown} does not exist and no target is given, so there is nothing to capture."
    return (
        f"No target to run: the contract {shown} has no `target:` block naming one (package+executable, "
        "command, script or module), and none was given."
    )


# ---------------------------------------------------------------------------- prepare


@dataclass
class Prepared:
    """A contract with its target and options resolved, ready to capture."""

    path: Path
    shown: str
    contract: Contract | None  # None when the file does not exist (allow_missing)
    spec: TargetSpec
    options: ComparisonOptions


def prepare(
    contract_path: str | Path,
    *,
    layers: Layers = Layers(),
    shown: str | None = None,
    allow_missing: bool = False,
    no_target: Callable[[Contract | None, str], str] = _default_no_target,
    loaded: Contract | None = None,
) -> Prepared:
    """Load the contract and resolve its options and target (raises an RmwIntrospectError).

    ``allow_missing``: a contract file that does not exist is ``contract=None`` instead of a
    :class:`ContractError`. ``no_target(contract, shown)`` words the error raised when no layer
    names a target. ``loaded``: the contract already read from ``contract_path`` (a contract
    file collected as a pytest item is not parsed twice).
    """
    path = Path(contract_path)
    shown = shown or display(path)
    contract = loaded
    if contract is None and (path.exists() or not allow_missing):
        contract = contract_module.load(path)
    if contract is not None:
        acceptance.check_rules(contract.accept)
    options = layers.options(contract, shown=shown)
    spec = layers.target(contract, path=path, shown=shown)
    if spec.kind is None:
        raise TargetConfigError(no_target(contract, shown))
    return Prepared(path=path, shown=shown, contract=contract, spec=spec, options=read_as_asked(spec, options))


def read_as_asked(spec: TargetSpec, options: ComparisonOptions) -> ComparisonOptions:
    """``options`` for a capture of ``spec``: parameters a target does not read
    (``read_parameters: false``) cannot be compared, and stay as the contract has them."""
    if spec.effective_read_parameters():
        return options
    return dataclasses.replace(options, ignore_parameters=True)


# ---------------------------------------------------------------------------- result


@dataclass
class CheckResult(ContractCheck[Contract, TargetSpec, Capture]):
    """What checking one node contract found (``result.ContractCheck``: the fields and rules it
    shares with a system check): a target and its capture, drift and no system problems; the
    contract may be a NoDL document. ``golden_target``: the ``target:`` block the golden should
    state (a marker test's target, written by an update; None: the file's stays as it is)."""

    golden_target: dict[str, Any] | None = None

    @property
    def stood_in(self) -> list[str]:
        """Processes stood in for (a system check's); a node contract's target always runs."""
        return []

    def matched(self, *, names: bool) -> str:
        """What a passing check matched: the contract's node names (a node contract has few)."""
        assert self.contract is not None
        return ", ".join(sorted(self.contract.nodes)) or "no nodes"

    def can_gain(self) -> bool:
        """A NoDL document states parameters always, and can never state a lifecycle."""
        return self.contract is None or self.contract.nodl is None

    @property
    def gains(self) -> list[str]:
        """What updating would add (``result.ContractCheck.gains``), and the target of a marker
        test that the golden does not state (yet): it makes the golden checkable by itself."""
        gains = super().gains
        if gains or self.drift_items or self.contract is None or self.capture is None or not self.can_gain():
            return gains  # (a target alone is written with any other change)
        if self.golden_target is not None and self.contract.target != self.golden_target:
            gains.append("its target")
        return gains

    def name_rules(self) -> NameRules:
        """The contract's patterns of names that change every run (the built-in rules alone
        without a contract; none for a NoDL document, which names its node literally)."""
        if self.writes_nodl:  # a NoDL document names its nodes literally
            return NameRules.literal(self.capture.node_names if self.capture is not None else ())
        return self.contract.name_rules() if self.contract is not None else NameRules()

    def golden_types(self) -> dict[str, type_model.TypeDescription] | None:
        """The ``types:`` section to write with the golden: when ``include_types`` is on or the
        contract already has one (and the capture recorded types); None leaves it alone."""
        assert self.capture is not None, "no capture to accept"
        keeps = self.contract is not None and self.contract.types is not None
        if not self.capture.has_types or not (self.options.include_types or keeps):
            return None
        return self.capture.to_contract_types()

    @property
    def writes_nodl(self) -> bool:
        """The golden is a NoDL file: read from one, or a new ``*.nodl.yaml``."""
        if self.contract is not None:
            return self.contract.nodl is not None
        return nodl.is_nodl("", self.path)

    def check_notes(self) -> list[str]:
        """What a NoDL document could not state (not compared): said once per run by the front
        end (``check``'s notes, pytest's terminal summary), not in every report."""
        return list(self.contract.nodl.notes) if self.contract is not None and self.contract.nodl is not None else []

    def notes(self) -> list[str]:
        """What to know about the result beside the drift: how the capture came about (what the
        check notes is :meth:`check_notes`)."""
        return self.capture.notes() if self.capture is not None else []

    def update(self, *, new_header: str | None = None) -> str | None:
        """Write the golden (``golden.update``): ``created``, ``updated`` or None."""
        if self.writes_nodl:
            previous = self.contract.nodl if self.contract is not None else None
            text = nodl.render(self.golden_nodes(), previous, self.path)
            return golden.update_with(self.path, lambda _old: text)
        return golden.update(self.path, self.golden_nodes(), new_header=new_header, types=self.golden_types(),
                             distribution=self.capture.ros_distribution if self.capture is not None else None,
                             target=self.golden_target)

    def render_text(self, accept_command: str | None = None) -> str:
        """The report for people (the same text as a failing test)."""
        if self.error is not None:
            return str(self.error)
        text = report.render_text(self.drift_items, contract_path=self.shown, threshold=self.threshold,
                                  accept_command=accept_command, title=self.title(), accepted=self.accepted,
                                  stale=self.stale)
        notes = self.notes()
        if notes:
            text = text.rstrip("\n") + "\n\nNotes on the capture:\n" + "\n".join(f"  - {note}" for note in notes)
        for said in self.rule_level_notes():
            text = text.rstrip("\n") + f"\n\n{said}.\n"
        return text

    def for_ci(self, *, written: str | None = None) -> ContractOutcome:
        """This result for the CI formats (``--format markdown|github``)."""
        if self.contract is not None:
            nodes = sorted(self.contract.nodes)
        else:
            nodes = self.capture.node_names if self.capture is not None else []
        return ContractOutcome(
            contract=self.shown, items=self.drift_items, threshold=self.threshold, nodes=nodes,
            error=str(self.error) if self.error is not None else None, written=written,
            lines=self.contract.lines() if self.contract is not None else {},
            accepted=self.accepted, stale=self.stale, notices=[(note, None) for note in self.check_notes()],
            notes=self.rule_level_notes(),
        )


def compare(prepared: Prepared, capture: Capture) -> CheckResult:
    """Compare a capture with the prepared contract (no drift items when it does not exist)."""
    contract = prepared.contract
    result = CheckResult(path=prepared.path, shown=prepared.shown, contract=contract,
                         spec=prepared.spec, options=prepared.options, capture=capture)
    actual = capture.to_contract_nodes(names=result.name_rules())
    if contract is not None and contract.nodl is not None:
        # a NoDL document: bound to the target's node, and only what it states is compared
        contract = dataclasses.replace(contract, nodes=nodl.bind(contract.nodl, contract.nodes, capture.node_names,
                                                                 prepared.shown))
        actual = nodl.project(actual, contract.nodes)
        result.contract = contract
    if contract is not None:
        items = drift.compare(
            contract.nodes, actual, prepared.options,
            expected_types=contract.types, actual_types=capture.types if capture.has_types else None,
            require_types=prepared.options.include_types and contract.nodl is None)
        items = drift.attribute_to_distribution(drift.sort_items(items + locked_type_items(prepared, capture)),
                                                contract.ros_distribution, capture.ros_distribution)
        leveled = rule_levels.apply(items, prepared.options.rules)  # the project's levels of rules
        result.turned_off = leveled.off
        judged = acceptance.judge(leveled.items, contract.accept, rules=acceptance.DRIFT_RULES)
        result.keep(judged.kept, judged.accepted)
        result.stale = judged.stale
    return result


def locked_type_items(prepared: Prepared, capture: Capture) -> list[DriftItem]:
    """The interface types of the capture against the package's type lock (``interfaces.lock.json``
    next to the contract or above it, written by ``rmw-introspect lock``); nothing without a lock,
    a capture without type descriptions, or with ``ignore_type_hash``. Raises TypeLockError."""
    if prepared.options.ignore_type_hash or not capture.has_types:
        return []
    found = type_lock.find(prepared.path)
    if found is None:
        return []
    return type_lock_check.lock_drift(capture.to_contract_nodes(), capture.types, type_lock.load(found))


def run_capture(prepared: Prepared, *, library: str | Path | None = None,
                ros: RosEnvironment | None = None) -> Capture:
    """Capture the prepared target (raises a TargetError; a failed lifecycle transition names
    the contract)."""
    try:
        return runner.run(prepared.spec, library=library, ros=ros,
                          include_infrastructure=prepared.options.include_infrastructure)
    except LifecycleTransitionFailed as exc:
        raise exc.naming_contract(prepared.shown) from None


def run(prepared: Prepared, *, library: str | Path | None = None, ros: RosEnvironment | None = None) -> CheckResult:
    """Capture and compare (raises a TargetError when the target cannot be captured)."""
    return compare(prepared, run_capture(prepared, library=library, ros=ros))


def check_contract(
    contract_path: str | Path,
    *,
    library: str | Path | Callable[[], str | Path] | None = None,
    ros: RosEnvironment | Callable[[], RosEnvironment] | None = None,
    layers: Layers = Layers(),
    shown: str | None = None,
    allow_missing: bool = False,
    no_target: Callable[[Contract | None, str], str] = _default_no_target,
) -> CheckResult:
    """:func:`prepare` + :func:`run`; an RmwIntrospectError ends up in ``result.error``.

    ``library``/``ros`` may be callables (called only once a target is known), so that a
    missing middleware is reported only for contracts that get as far as capturing.
    """
    path = Path(contract_path)
    shown = shown or display(path)
    prepared = None
    try:
        prepared = prepare(path, layers=layers, shown=shown, allow_missing=allow_missing, no_target=no_target)
        lib = library() if callable(library) else library
        env = ros() if callable(ros) else ros
        return run(prepared, library=lib, ros=env)
    except RmwIntrospectError as exc:
        result = CheckResult(path=path, shown=shown, error=exc)
        if prepared is not None:
            result.contract, result.spec, result.options = prepared.contract, prepared.spec, prepared.options
        return result


# --------------------------------------------------------------------- compatibility checks


@dataclass
class CompatibilityResult:
    """Whether the nodes of several contracts fit together (``system_pipeline.check_contracts``)."""

    labels: list[str]
    items: list[CompatItem]
    threshold: Severity
    #: where each contract (by label) lists its nodes and interfaces, for annotations
    lines: dict[str, LineIndex] = field(default_factory=dict)
    #: problems the contracts' ``accept:`` entries accept (not in ``items``), and entries that accepted nothing
    accepted: list[Accepted] = field(default_factory=list)
    stale: list[Acceptance] = field(default_factory=list)
    #: the file of an end's label (a system contract's process labels name its file); None: the label
    file_of: Callable[[str], str] | None = None
    #: what the rules note without finding a problem (``compatibility.NOTES``): never failing
    notes: list[str] = field(default_factory=list)

    @property
    def failed(self) -> bool:
        return report.fails(self.items, self.threshold)

    def render_text(self) -> str:
        text = report.render_compat_text(self.items, threshold=self.threshold,
                                         title=f"Compatibility check of {len(self.labels)} contract(s)",
                                         accepted=self.accepted, stale=self.stale)
        if self.notes:
            text = text.rstrip("\n") + "\n\nNotes:\n" + "".join(f"  - {note}\n" for note in self.notes)
        return text

    def to_json(self) -> list[dict[str, Any]]:
        return [*report.compat_to_json(self.items), *report.accepted_to_json(self.accepted),
                *report.stale_to_json(self.stale)]


def judge_compatibility(items: Sequence[CompatItem], accept: Sequence[Acceptance],
                        file_of: Callable[[str], str] = lambda label: label) -> acceptance.Judged:
    """The system problems sorted by the contracts' ``accept:`` entries: an entry accepts a
    problem one of whose ends is in its own contract (``file_of``: an end's label → its file)."""
    def applies(entry: Acceptance, item: acceptance.Finding) -> bool:
        assert isinstance(item, CompatItem)
        ends = [item.requester, *([item.provider] if item.provider else [])]
        return any(file_of(end.label) == entry.source for end in ends)

    return acceptance.judge(items, accept, rules=acceptance.SYSTEM_RULES, applies=applies)
