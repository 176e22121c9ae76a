"""Checking a system contract (``*.system.yaml``): the check pipeline for a whole launch file.

The same steps as ``pipeline`` for a node contract, and the same option layers
(``pipeline.Layers``): load the system contract (``model.system_contract``), resolve its
``launch:`` block, the process-wide target options (``settle``, ``timeout``, ``horizon``,
``lifecycle``, ``read_parameters``, ``env``) and the comparison options, capture every process (``run.system_capture.capture_system``),
then

* compare the system's nodes with the contract's ``nodes`` (``compare.drift``: the drift rules
  of a node contract), and
* run the compatibility rules on the capture (``compare.compatibility.check_launched``: type, hash and QoS
  of every connection, requesters without providers, duplicate node names, several servers,
  launched processes that created no node), judged with ``system_fail_on`` (default
  ``breaking``, like ``rmw-introspect compat``).

:class:`SystemCheckResult` is what ``check.outcome.decide`` reads, like a ``CheckResult``; its
``items`` are the drift and then the system problems, ``drifted`` says whether the golden
differs. :func:`load_any` and :func:`check_contracts` run the compatibility rules on contract files
without capturing (``compat``, ``graph``); ``check.diff`` compares two contracts of any kind.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..compare import acceptance, drift, launch_given, rule_levels
from ..compare.ci_report import ContractOutcome
from ..compare.compatibility import (
    NOTES,
    CompatItem,
    LaunchedProcess,
    check_compatibility,
    check_launched,
    propose_external,
)
from ..compare.launch_given import Given
from ..compare.options import ComparisonOptions
from ..errors import RmwIntrospectError, TargetConfigError, UsageError
from ..launch import component_loads
from ..model import contract as contract_module
from ..model import contract_kind, middlewares, system_contract
from ..model import stand_ins as stand_in_model
from ..model.acceptance import Acceptance
from ..model.contract_shapes import ContractNode
from ..model.locate import LineIndex, line_index, line_of
from ..model.paths import shown as display
from ..model.stand_ins import StoodIn
from ..model.system_contract import SYSTEM_TARGET_KEYS, SystemContract
from ..model.unstable_names import NameRules
from ..model.vocabulary import PARAMETERS, parse_threshold
from ..run import system_capture
from ..run.ros_env import RosEnvironment
from ..run.system_capture import LaunchSpec, ProcessCapture, SystemCapture
from ..run.target import TargetSpec
from . import golden, launch_settings
from .pipeline import CompatibilityResult, Layers, judge_compatibility, read_as_asked
from .result import ContractCheck

NO_LAYERS = Layers()


@dataclass
class SystemPrepared:
    """A system contract with its launch file, process-wide target and options resolved."""

    path: Path
    shown: str
    contract: SystemContract | None
    launch: LaunchSpec
    target: TargetSpec
    options: ComparisonOptions
    #: the ROS environment the processes run in (the ament prefixes that paths resolve against)
    ros: RosEnvironment | None = None
    #: the processes not run here and the nodes that stand in for them (``stand_ins:``)
    stand_ins: list[StoodIn] = field(default_factory=list)


def prepare(
    contract_path: str | Path,
    *,
    layers: Layers = NO_LAYERS,
    launch: Mapping[str, Any] | None = None,
    launch_base: str | Path | None = None,
    launch_arguments: Mapping[str, Any] | None = None,
    shown: str | None = None,
    allow_missing: bool = False,
    ros: RosEnvironment | Callable[[], RosEnvironment] | None = None,
) -> SystemPrepared:
    """Load the system contract and resolve what to launch, the process-wide target options and
    the comparison options. ``launch``: a ``launch:`` block given by the caller (relative paths
    to ``launch_base``), replacing the contract's; ``launch_arguments``: launch arguments on top of
    the block's. Raises an RmwIntrospectError."""
    path = Path(contract_path)
    shown = shown or display(path)
    contract = None
    stood_in: list[StoodIn] = []
    if path.exists() or not allow_missing:
        contract = system_contract.load(path)
        acceptance.check_rules(contract.accept)
        stood_in = stand_in_model.load_all(contract.stand_ins, path)
    as_contract = None if contract is None else contract_kind.as_node_contract(contract)
    options = layers.options(as_contract, shown=shown)
    target = layers.target(as_contract, path=path, shown=shown)
    extra = sorted(k for k in target.to_mapping() if k not in SYSTEM_TARGET_KEYS)
    if extra:
        raise TargetConfigError(
            f"{shown}: a system contract runs what its launch file starts; its target options may only be "
            f"{', '.join(SYSTEM_TARGET_KEYS)} (got {', '.join(extra)})")
    if launch is not None:
        block, base, source = launch, Path(launch_base or Path.cwd()), "launch options"
    elif contract is not None:
        block, base, source = contract.launch, path.absolute().parent, f"{shown}: launch"
    else:
        raise TargetConfigError(
            f"The system contract {shown} does not exist and no launch file is given, so there is nothing to "
            "capture; name one (--launch FILE, or --launch-package P --launch-file F)")
    if launch_arguments:
        block = {**block, "arguments": {**(block.get("arguments") or {}), **launch_arguments}}
    env = ros() if callable(ros) else ros
    spec = system_capture.resolve_launch(block, base_dir=base, source=source,
                                         prefixes=system_capture.ament_prefixes(env))
    return SystemPrepared(path=path, shown=shown, contract=contract, launch=spec, target=target,
                          options=read_as_asked(target, options), ros=env,
                          stand_ins=stood_in)


# ---------------------------------------------------------------------------- result


def launched_processes(capture: SystemCapture) -> list[LaunchedProcess]:
    """The processes of a capture as the compatibility rules read them."""
    return [LaunchedProcess(label=p.label, expected=p.launched.expected_fqn, nodes=p.contract_nodes(),
                            duplicates=tuple(p.capture.duplicate_node_names) if p.capture is not None else (),
                            where=str(p.launched.where), given=launch_settings.given(p.launched),
                            unloaded=unloaded_components(p), component_given=component_settings(p))
            for p in capture.processes]


def component_settings(process: ProcessCapture) -> dict[str, Given]:
    """What each component the container ``process`` loaded was given, by the node it became
    (the container's answer, ``full_node_name``)."""
    if not process.launched.components or process.capture is None:
        return {}
    out: dict[str, Given] = {}
    for load, record in zip(process.launched.components, process.capture.component_loads, strict=False):
        if record.result == "loaded" and record.full_node_name:
            out[record.full_node_name] = launch_settings.component_given(load)
    return out


def unloaded_components(process: ProcessCapture) -> tuple[tuple[str, str], ...]:
    """The components the launch file loads into ``process`` (a container) that it did not create."""
    if not process.launched.components:
        return ()
    records = process.capture.component_loads if process.capture is not None else ()
    container = process.launched.expected_fqn or process.label
    out = []
    for load, why in component_loads.problems(records, process.launched.components):
        name = f"{(load.namespace or '').rstrip('/')}/{load.name}" if load.name else load.plugin
        out.append((name, f"the launch file loads {load.describe()} into {container}, but no node came of it: {why}"))
    return tuple(out)


def contract_processes(contract: SystemContract, label: str | None = None) -> list[LaunchedProcess]:
    """The processes of a system contract as the compatibility rules read them (labels as in a capture)."""
    entries = [p for p, _ in contract.process_nodes()]
    names = system_capture.labels([(p.get("package"), str(p.get("executable"))) for p in entries])
    prefix = f"{label}: " if label else ""
    return [LaunchedProcess(label=prefix + name, expected=p.get("name"), nodes=nodes)
            for name, (p, nodes) in zip(names, contract.process_nodes(), strict=True)]


@dataclass
class SystemCheckResult(ContractCheck[SystemContract, LaunchSpec, SystemCapture]):
    """What checking one system contract found (``result.ContractCheck``: the fields and rules it
    shares with a node check): drift of its nodes and system problems."""

    #: what the system rules note without finding a problem (``launch_given.NOTES``: a device the
    #: capture machine lacks)
    rule_notes: list[CompatItem] = field(default_factory=list)

    def check_notes(self) -> list[str]:
        """What the system rules note (devices this machine lacks): said once per run by the
        front end (``check``'s notes, pytest's terminal summary), not in every report."""
        return [f"{item.requester.node}: {item.message}" for item in self.rule_notes]

    def notes(self) -> list[str]:
        """The notes of this check's report: the capture's (the rules' are :meth:`check_notes`),
        and the stand-in advice where it applies: a node that ran without its device and lost
        interfaces."""
        return (self.capture.notes() if self.capture is not None else []) + self.stand_in_advice()

    def stand_in_advice(self) -> list[str]:
        """For each node that ran without a device it names (``rule_notes``) and lost what its
        contract has (drift ``removed`` at or above ``fail_on``): stand in for its process. (A
        node that ran fine gets the note only, said once per run: :meth:`check_notes`.)"""
        failing = {item.node for item in self.drift_items if item.change == "removed" and item.severity >= self.threshold}
        devices: dict[str, list[str]] = {}
        for item in self.rule_notes:
            if item.rule in launch_given.NOTES and item.requester.node in failing:
                devices.setdefault(item.requester.node, []).append(f"`{item.name}`")
        return [f"{node} ran without the device its parameter {', '.join(names)} names, which this machine lacks, "
                "and lost interfaces its contract has: if that is for lack of the hardware, stand in for its process "
                "(`stand_ins:`, docs/system-contracts.md, \"Hardware processes\")" for node, names in devices.items()]

    @property
    def stood_in(self) -> list[str]:
        """The processes not run here, each with the file that stood in for it."""
        if self.capture is None:
            return []
        return [f"{p.label} by {p.stood_in.shown}" for p in self.capture.stood_in if p.stood_in is not None]

    def matched(self, *, names: bool) -> str:
        """What a passing check matched: how many nodes in how many processes (a robot has
        hundreds), their names only when asked (``-v``)."""
        assert self.contract is not None
        nodes = sorted(self.contract.nodes)
        processes = len(self.capture.processes) if self.capture is not None else len(self.contract.processes)
        counted = f"{len(nodes)} node{'' if len(nodes) == 1 else 's'} in {processes} process{'' if processes == 1 else 'es'}"
        return f"{counted}: {', '.join(nodes)}" if names and nodes else counted

    def for_ci(self, *, written: str | None = None) -> ContractOutcome:
        """This result for the CI formats (``--format markdown|github``)."""
        nodes = sorted(self.contract.nodes) if self.contract is not None else []
        lines = line_index(self.contract.text) if self.contract is not None else {}
        return ContractOutcome(
            contract=self.shown, items=self.drift_items, threshold=self.threshold, nodes=nodes,
            error=str(self.error) if self.error is not None else None, written=written,
            lines=lines,
            system_items=self.system_items, system_threshold=self.system_threshold,
            accepted=self.accepted, stale=self.stale,
            launched_at={p.label: p.where for p in launched_processes(self.capture) if p.where}
            if self.capture is not None else {},
            notices=[(f"{item.requester.node}: {item.message}",
                      line_of(lines, item.requester.node, PARAMETERS, item.name))
                     for item in self.rule_notes],
            notes=self.rule_level_notes(),
        )

    def name_rules(self) -> NameRules:
        """The contract's patterns of node names that change every run (``model.unstable_names``)."""
        if self.contract is None:
            return NameRules()
        return NameRules.of_contract(self.contract.unstable_names, self.contract.nodes)

    def new_text(self, old: str | None) -> str:
        """The system contract to write, given the current text (None: a new file)."""
        assert self.capture is not None and self.spec is not None
        nodes = self.golden_nodes()
        if old:
            try:
                current = system_contract.loads(old, path=self.path)
                nodes = contract_module.preserve_spelling(current.nodes, nodes)
                if not current.processes and not current.nodes and not current.external and "# external:" not in old:
                    # a hand-written header filled in for the first time: propose its outside world too
                    old = old + ("" if old.endswith("\n") else "\n") + self.external_proposal()
            except RmwIntrospectError:
                pass
            return system_contract.update_text(old, self.capture.process_entries(self.name_rules()), nodes)
        header = system_contract.new_header(self.spec.to_block(self.path.absolute().parent),
                                            options={"include_infrastructure": True}
                                            if self.options.include_infrastructure else None,
                                            how="pytest-rmw-introspect (--update-golden / check --update)",
                                            external_proposal=self.external_proposal())
        return system_contract.render(self.capture.process_entries(self.name_rules()), nodes, header=header)

    def external_proposal(self) -> str:
        """The commented-out ``external:`` block a new contract gets (``compare.wiring.proposal``)."""
        assert self.capture is not None
        return propose_external(launched_processes(self.capture))

    def update(self) -> str | None:
        """Write the system contract (``golden.update_with``): ``created``, ``updated`` or None."""
        return golden.update_with(self.path, self.new_text)

    def render_text(self, accept_command: str | None = None) -> str:
        if self.error is not None:
            return str(self.error)
        text = self.findings_text(accept_command=accept_command, system_title=f"System check of {self.shown}")
        notes = self.notes()
        if notes:
            text = text.rstrip("\n") + "\n\nNotes on the capture:\n" + "\n".join(f"  - {note}" for note in notes) + "\n"
        for said in self.rule_level_notes():
            text = text.rstrip("\n") + f"\n\n{said}.\n"
        return text


def compare(prepared: SystemPrepared, capture: SystemCapture) -> SystemCheckResult:
    """Compare a system capture with the prepared contract and run the compatibility rules on it."""
    result = SystemCheckResult(path=prepared.path, shown=prepared.shown, contract=prepared.contract,
                               spec=prepared.launch, options=prepared.options, capture=capture)
    external = prepared.contract.external if prepared.contract is not None else None
    missing_path = launch_settings.missing_path(system_capture.ament_prefixes(prepared.ros))
    options = dataclasses.replace(prepared.options, rmw=system_rmw(prepared, capture))
    system_items = check_launched(launched_processes(capture), external=external, missing_path=missing_path,
                                  rmw=options.rmw)
    drift_items = []
    if prepared.contract is not None:
        drift_items = drift.compare(prepared.contract.nodes, capture.to_contract_nodes(names=result.name_rules()),
                                    options)
    leveled = rule_levels.apply([*drift_items, *system_items], options.rules)  # the project's levels of rules
    result.turned_off = leveled.off
    # what the rules note (``compatibility.NOTES``: a device the capture machine lacks, a pair only DDS
    # would refuse) is said once per run, unless the project gave its rule a level
    result.rule_notes = [item for item in leveled.items
                         if isinstance(item, CompatItem) and item.rule in NOTES and not item.level_set_by]
    accept = prepared.contract.accept if prepared.contract is not None else ()
    judged = acceptance.judge([item for item in leveled.items if item not in result.rule_notes], accept,
                              rules=acceptance.DRIFT_RULES | acceptance.SYSTEM_RULES)
    result.keep(judged.kept, judged.accepted)
    result.stale = judged.stale
    return result


def system_rmw(prepared: SystemPrepared, capture: SystemCapture) -> str | None:
    """The middleware whose QoS rules judge the system (issue 49 item 3): the contract's ``rmw:``,
    else RMW_IMPLEMENTATION in its launch environment (``target: {env:}``, what the launch file
    gives each process), else the ``rmw`` option (``--rmw``), else None (the DDS rules)."""
    launched = [(f"{p.label} at {p.launched.where}", p.launched.env) for p in capture.processes]
    if prepared.contract is not None:
        return prepared.contract.middleware(prepared.options.rmw, launched)
    return middlewares.choose([("target.env", prepared.target.to_mapping().get("env") or {}), *launched],
                              prepared.options.rmw, shown=prepared.shown)


def run_capture(prepared: SystemPrepared, *, library: str | Path | None = None,
                ros: RosEnvironment | None = None, jobs: int | None = None) -> SystemCapture:
    """Capture every process of the prepared system (raises a TargetError); ``jobs``: processes
    at a time (default: the number of cores)."""
    return system_capture.capture_system(prepared.launch, target=prepared.target, library=library, ros=ros,
                                         include_infrastructure=prepared.options.include_infrastructure, jobs=jobs,
                                         stand_ins=prepared.stand_ins)


def check_system_contract(
    contract_path: str | Path,
    *,
    library: str | Path | Callable[[], str | Path] | None = None,
    ros: RosEnvironment | Callable[[], RosEnvironment] | None = None,
    layers: Layers = NO_LAYERS,
    launch: Mapping[str, Any] | None = None,
    launch_base: str | Path | None = None,
    launch_arguments: Mapping[str, Any] | None = None,
    shown: str | None = None,
    allow_missing: bool = False,
    jobs: int | None = None,
) -> SystemCheckResult:
    """:func:`prepare`, capture, :func:`compare`; an RmwIntrospectError ends up in ``result.error``."""
    path = Path(contract_path)
    shown = shown or display(path)
    prepared = None
    try:
        prepared = prepare(path, layers=layers, launch=launch, launch_base=launch_base,
                           launch_arguments=launch_arguments, shown=shown,
                           allow_missing=allow_missing, ros=ros)
        lib = library() if callable(library) else library
        env = ros() if callable(ros) else ros
        return compare(prepared, run_capture(prepared, library=lib, ros=env, jobs=jobs))
    except RmwIntrospectError as exc:
        result = SystemCheckResult(path=path, shown=shown, error=exc)
        if prepared is not None:
            result.contract, result.spec, result.options = prepared.contract, prepared.launch, prepared.options
        return result


# ---------------------------------------------------------------------------- without capturing


@dataclass
class LoadedContracts:
    """Contract files of either kind, as the compatibility rules and the graph read them."""

    labels: list[str]
    processes: list[LaunchedProcess]
    any_system: bool
    #: the ``accept:`` entries of every file
    accept: list[Acceptance] = field(default_factory=list)
    #: the outside world the system contracts among them declare (``external:``, merged)
    external: dict[str, dict[str, str]] = field(default_factory=dict)
    #: where each file (by label) lists its nodes and interfaces, for annotations
    lines: dict[str, LineIndex] = field(default_factory=dict)
    #: the middleware each system contract among them runs on, when it says (``rmw:``, its
    #: ``target: {env:}``), by label
    middlewares: dict[str, str] = field(default_factory=dict)
    #: the rule levels each file's ``options: rules`` sets, by label
    rules: dict[str, tuple[rule_levels.RuleLevel, ...]] = field(default_factory=dict)

    def middleware(self, option: str | None = None) -> str | None:
        """The middleware whose QoS rules judge these contracts: the one their system contracts
        say, else ``option`` (``--rmw``), else None (the DDS rules). Raises UsageError when the
        system contracts say different ones."""
        said = sorted(set(self.middlewares.values()))
        if len(said) > 1:
            named = ", ".join(f"{label} runs on {name}" for label, name in sorted(self.middlewares.items()))
            raise UsageError(f"these system contracts run on different middlewares ({named}): a publisher on one never "
                             "reaches a subscription on another; check them apart")
        return said[0] if said else option

    def nodes_by_label(self) -> dict[str, Mapping[str, ContractNode]]:
        return {p.label: p.nodes for p in self.processes}

    def file_of(self, label: str) -> str:
        """The file of a system-check end: its label, a system contract's process label
        (``FILE: package/executable``) or, when one system contract was read alone (its process
        labels do not name the file), that file."""
        for file in self.labels:
            if label == file or label.startswith(f"{file}: "):
                return file
        return self.labels[0] if len(self.labels) == 1 else label


def load_any(paths: Iterable[str | Path], *, base_dir: str | Path | None = None) -> LoadedContracts:
    """The one loader of contract files for the compatibility rules and the graph: node contracts
    (one process each, labelled with the path) and system contracts (their processes, labelled
    ``PATH: package/executable``). Relative paths are relative to ``base_dir`` (default: the
    current directory). Raises ContractError, UsageError (no contract given)."""
    labels: list[str] = []
    lines: dict[str, LineIndex] = {}
    processes: list[LaunchedProcess] = []
    accept: list[Acceptance] = []
    any_system = False
    external: dict[str, dict[str, str]] = {}
    said: dict[str, str] = {}
    levels: dict[str, tuple[rule_levels.RuleLevel, ...]] = {}
    paths = list(paths)
    for p in paths:
        path = Path(os.path.expanduser(str(p)))
        if not path.is_absolute() and base_dir is not None:
            path = Path(base_dir) / path
        label = display(path)
        if label in labels:
            continue
        labels.append(label)
        if contract_kind.is_system_file(path):
            any_system = True
            system = system_contract.load(path)
            middleware = system.middleware()
            if middleware is not None:
                said[label] = middleware
            for kind, declared in system.external.items():
                external.setdefault(kind, {}).update(declared)
            # the process labels name the file only when several files are drawn together
            processes += contract_processes(system, label if len(paths) > 1 else None)
            acceptance.check_rules(system.accept)
            accept += system.accept
            lines[label] = line_index(system.text)
            options = system.options
        else:
            contract = contract_module.load(path)
            processes.append(LaunchedProcess(label=label, expected=None, nodes=contract.nodes, launched=False))
            acceptance.check_rules(contract.accept)
            accept += contract.accept
            lines[label] = contract.lines()
            options = contract.options
        if options.get("rules"):
            levels[label] = rule_levels.parse(options["rules"], f"{label}: options")
    if not labels:
        raise UsageError("no contracts given to the compatibility check")
    return LoadedContracts(labels, processes, any_system, accept, external, lines, said, levels)


def compatibility_items(loaded: LoadedContracts, *, strict_system_default: bool = False,
                        rmw: str | None = None) -> list[CompatItem]:
    """The compatibility rules over loaded contracts: all of them when a system contract is among
    them, the connection rules (``compat`` as before) for node contracts alone; QoS judged for the
    middleware the system contracts say, else ``rmw`` (``LoadedContracts.middleware``)."""
    rmw = loaded.middleware(rmw)
    if loaded.any_system:
        return check_launched(loaded.processes, external=loaded.external, strict_system_default=strict_system_default,
                              rmw=rmw)
    return check_compatibility(loaded.nodes_by_label(), strict_system_default=strict_system_default, rmw=rmw)


def check_contracts(
    contract_paths: Iterable[str | Path],
    *,
    fail_on: str = "breaking",
    strict_system_default: bool = False,
    base_dir: str | Path | None = None,
    rmw: str | None = None,
    rules: Sequence[rule_levels.RuleLevel] = (),
) -> CompatibilityResult:
    """Load contract files of either kind (:func:`load_any`) and check that their nodes fit
    together (:func:`compatibility_items`), judged by their ``accept:`` entries (an entry accepts
    a problem one of whose ends is in its own file). Labels are the paths as shown (relative to
    the current directory). ``rmw``: the middleware for contracts that do not say (``--rmw``).
    Notes (``compatibility.NOTES``) are kept apart from the problems: they never fail.
    ``rules``: the command line's rule levels, over each file's ``options: rules``
    (:func:`levels_by_ends`). Raises ContractError, UsageError (no contract given, or system
    contracts on different middlewares), or OptionError for a bad ``fail_on`` or rule level."""
    threshold = parse_threshold(fail_on)
    loaded = load_any(contract_paths, base_dir=base_dir)
    items = compatibility_items(loaded, strict_system_default=strict_system_default, rmw=rmw)
    leveled = levels_by_ends(items, loaded, rules)
    notes = [f"{i.name}: {i.message}" for i in leveled.items if i.rule in NOTES and not i.level_set_by]
    judged = judge_compatibility([i for i in leveled.items if i.rule not in NOTES or i.level_set_by], loaded.accept,
                                 loaded.file_of)
    return CompatibilityResult(labels=loaded.labels, items=[i for i in judged.kept if isinstance(i, CompatItem)],
                               threshold=threshold, lines=loaded.lines, accepted=judged.accepted,
                               stale=judged.stale, file_of=loaded.file_of,
                               notes=[*notes, *([rule_levels.turned_off_text(leveled.off)] if leveled.off else [])])


def levels_by_ends(items: Sequence[CompatItem], loaded: LoadedContracts,
                   rules: Sequence[rule_levels.RuleLevel] = ()) -> rule_levels.Applied:
    """The problems at the levels the project gives their rules: the command line's ``rules``
    over the ``options: rules`` of the file of each end (as an ``accept:`` entry applies to a
    problem one of whose ends is in its file); when the two files set different levels, the more
    severe (``rule_levels.apply_each``)."""
    if not rules and not loaded.rules:
        return rule_levels.Applied(list(items))

    def entries_of(item: CompatItem) -> list[tuple[rule_levels.RuleLevel, ...]]:
        ends = [item.requester, *([item.provider] if item.provider else [])]
        files = dict.fromkeys(loaded.file_of(end.label) for end in ends)
        return [rule_levels.merge(loaded.rules.get(file, ()), rules) for file in files]

    return rule_levels.apply_each(items, entries_of)
