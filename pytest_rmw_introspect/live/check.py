"""Checking contracts against a running graph (``check --live``): the drift rules of a node
contract and, for a system contract, the compatibility rules, on what the live reader saw.

A node contract is compared with the live nodes it names (a node it names that is not running
is drift; other nodes of the graph are not its business); a system contract with every node of
the graph (a node someone started by hand is drift), and the compatibility rules run on the
graph's real endpoints (the QoS the middleware really offers and requests) with the contract's
``external:``. Severities, ``fail_on``/``system_fail_on``, ``accept:`` entries, baselines and the
report formats are those of ``check`` (:class:`LiveCheckResult` is a ``ContractCheck``).

What the live graph cannot show is taken as the contract states it and said in the report's
notes, never reported as drift (:func:`observable`; docs/known-limits.md, "The live check"):
the type hash of services and of an action's goal and result services (the graph API gives
service types without hashes); QoS fields the middleware reports as UNKNOWN (Fast DDS: history
and depth); a QoS policy the contract leaves to the middleware (SYSTEM_DEFAULT: the graph shows
what the middleware made of it); the parameters of a node whose parameter services did not
answer in time, and the state of a lifecycle node whose ``get_state`` did not; the launch file's
part (which process started a node, with which command line, parameters file or remapping: the
rules that judge it, ``PARAM_NOT_DECLARED`` and its kin, need the launch file and do not run).
"""

from __future__ import annotations

import copy
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, cast

from ..check.pipeline import Layers
from ..check.result import ContractCheck
from ..compare import acceptance, drift, rule_levels
from ..compare.ci_report import ContractOutcome
from ..compare.compatibility import LaunchedProcess, check_launched
from ..errors import RmwIntrospectError
from ..model import contract as contract_module
from ..model import contract_kind, nodl, system_contract
from ..model import qos as qos_module
from ..model.capture import Capture
from ..model.contract import Contract
from ..model.contract_shapes import ContractNode, ContractNodes
from ..model.locate import line_index
from ..model.paths import shown as display
from ..model.system_contract import SystemContract
from ..model.unstable_names import NameRules, is_pattern_key
from ..model.vocabulary import LIFECYCLE, LISTS, PARAMETERS
from .graph import LiveGraph

#: the QoS policies a contract can leave to the middleware (SYSTEM_DEFAULT), which the graph
#: shows resolved
_POLICIES = ("history", "reliability", "durability", "liveliness")
_SERVICE_LISTS = ("service_servers", "service_clients")
_ACTION_LISTS = ("action_servers", "action_clients")


@dataclass
class LiveSpec:
    """What a live check ran: the graph it read."""

    graph: LiveGraph

    def describe(self) -> str:
        return self.graph.describe()


@dataclass
class LiveView:
    """The live capture as one contract sees it: the graph's nodes with what the graph cannot
    show taken from the contract (``nodes``), and the notes that say what that was."""

    graph: LiveGraph
    nodes: ContractNodes
    unobserved: list[str] = field(default_factory=list)

    def to_contract_nodes(self, *, with_type_hash: bool = True, with_qos: bool = True,
                          names: NameRules | None = None) -> ContractNodes:
        nodes = copy.deepcopy(self.nodes)
        for node in nodes.values():
            for list_name in LISTS:
                for entry in node.get(list_name, []):
                    if not with_type_hash:
                        entry.pop("type_hash", None)
                    if not with_qos:
                        entry.pop("qos", None)
        return nodes

    def notes(self) -> list[str]:
        return [*self.graph.notes(self.nodes), *self.unobserved]

    def summary(self) -> str:
        names = sorted(self.graph.capture.nodes)
        return f"live graph of ROS_DOMAIN_ID {self.graph.domain_id}: {len(names)} node(s): {', '.join(names)}"


def _observed_qos(expected: Any, actual: Mapping[str, Any]) -> tuple[dict[str, Any], list[str]]:
    """``actual`` with the QoS fields the graph cannot show taken from ``expected``; and a
    sentence for each field taken."""
    try:
        want: dict[str, Any] = dict(qos_module.expand(expected))
        have: dict[str, Any] = dict(qos_module.expand(dict(actual)))
    except ValueError:
        return dict(actual), []
    taken = []
    for policy in _POLICIES:
        if have[policy] == want[policy]:
            continue
        if have[policy] == "UNKNOWN":
            taken.append(f"QoS {policy}{' and depth' if policy == 'history' else ''}, which the middleware does "
                         "not report (UNKNOWN)")
        elif want[policy] == "SYSTEM_DEFAULT":
            taken.append(f"QoS {policy} the contract leaves to the middleware (SYSTEM_DEFAULT): the graph shows "
                         "what the middleware made of it")
        else:
            continue
        have[policy] = want[policy]
        if policy == "history":
            have["depth"] = want["depth"]
        if policy == "liveliness" and have["liveliness_lease_duration_ns"] != want["liveliness_lease_duration_ns"]:
            have["liveliness_lease_duration_ns"] = want["liveliness_lease_duration_ns"]
    return dict(qos_module.from_capture(have)), taken


def observable(expected: Mapping[str, ContractNode], actual: ContractNodes, graph: LiveGraph) -> tuple[ContractNodes, list[str]]:
    """``actual`` with every field the live graph cannot show taken as ``expected`` states it,
    and one note per kind of field taken (never drift; docs/known-limits.md)."""
    out: dict[str, Any] = copy.deepcopy(dict(actual))
    taken: dict[str, set[str]] = {}
    for fqn, node in out.items():
        want: Any = expected.get(fqn)
        if want is None:
            continue
        for list_name in LISTS:
            wanted = {e["name"]: e for e in want.get(list_name, []) or []}
            for entry in node.get(list_name, []) or []:
                other = wanted.get(entry["name"])
                if other is None:
                    continue
                if list_name in _SERVICE_LISTS and "type_hash" in other and not entry.get("type_hash"):
                    entry["type_hash"] = other["type_hash"]
                    taken.setdefault("the type hashes of services (the graph API gives a service's type, not its "
                                     "hash)", set()).add(fqn)
                elif list_name in _ACTION_LISTS and isinstance(other.get("type_hash"), Mapping):
                    hashes = dict(entry.get("type_hash") or {})
                    missing = {k: v for k, v in other["type_hash"].items() if k not in hashes}
                    if missing:
                        entry["type_hash"] = {**hashes, **missing}
                        taken.setdefault("the type hashes of actions' goal and result services", set()).add(fqn)
                elif "qos" in entry and "qos" in other:
                    entry["qos"], fields = _observed_qos(other["qos"], entry["qos"])
                    for what in fields:
                        taken.setdefault(what, set()).add(fqn)
        if fqn in graph.parameters_unanswered:
            if PARAMETERS in want:
                node[PARAMETERS] = copy.deepcopy(want[PARAMETERS])
            else:
                node.pop(PARAMETERS, None)
        if fqn in graph.lifecycle_unanswered and LIFECYCLE in want:
            node[LIFECYCLE] = want[LIFECYCLE]
    notes = [f"not observable in a live graph, taken as the contract states it: {what} ({', '.join(sorted(nodes))})"
             for what, nodes in sorted(taken.items())]
    return cast(ContractNodes, out), notes


@dataclass
class LiveCheckResult(ContractCheck[Any, LiveSpec, LiveView]):
    """What checking one contract against the live graph found."""

    system: bool = False

    def name_rules(self) -> NameRules:
        if self.contract is None:
            return NameRules()
        return NameRules.of_contract(self.contract.unstable_names, self.contract.nodes)

    def update(self) -> str | None:
        raise RmwIntrospectError("a live check does not write contracts: write one from the running system with "
                                 "`rmw-introspect capture --live -o FILE`")

    def can_gain(self) -> bool:
        return False

    def matched(self, *, names: bool) -> str:
        assert self.contract is not None
        nodes = sorted(self.contract.nodes)
        counted = f"{len(nodes)} node{'' if len(nodes) == 1 else 's'} running"
        if self.spec is not None:
            counted += f" in ROS_DOMAIN_ID {self.spec.graph.domain_id}"
        return f"{counted}: {', '.join(nodes)}" if names and nodes else counted

    @property
    def stood_in(self) -> list[str]:
        return []

    def check_notes(self) -> list[str]:
        """What the live graph could not show, said once per run (``note:`` lines, pytest's
        terminal summary) when there is no report to say it in."""
        return self.notes() if not self.items and self.error is None else []

    def notes(self) -> list[str]:
        return [*(self.capture.notes() if self.capture is not None else []), *self.rule_level_notes()]

    def title(self) -> str:
        return f"Interface drift of {self.spec.describe()}" if self.spec is not None else "Interface drift (live)"

    def render_text(self, accept_command: str | None = None) -> str:
        if self.error is not None:
            return str(self.error)
        text = self.findings_text(accept_command=None, system_title=f"System check of {self.shown} (live)")
        notes = self.notes()
        if notes:
            text = text.rstrip("\n") + "\n\nNotes on the live graph:\n" + "\n".join(f"  - {n}" for n in notes) + "\n"
        return text

    def for_ci(self, *, written: str | None = None) -> ContractOutcome:
        nodes = sorted(self.contract.nodes) if self.contract is not None else []
        text = getattr(self.contract, "text", "") if self.contract is not None else ""
        return ContractOutcome(
            contract=self.shown, items=self.drift_items, threshold=self.threshold, nodes=nodes,
            error=str(self.error) if self.error is not None else None, written=written,
            lines=line_index(text) if text else {}, system_items=self.system_items,
            system_threshold=self.system_threshold, accepted=self.accepted, stale=self.stale,
            notices=[(note, None) for note in self.notes()])


def load(path: Path) -> Contract | SystemContract:
    """A node contract (or NoDL document) or a system contract (raises an RmwIntrospectError)."""
    if contract_kind.is_system_file(path):
        return system_contract.load(path)
    return contract_module.load(path)


def expected_nodes(contracts: Iterable[Contract | SystemContract]) -> tuple[str, ...]:
    """The nodes ``contracts`` name literally and expect running (not a pattern key, not a node
    the program destroyed itself, not a NoDL document's, which is bound to the graph by type): the
    reader waits for them before it counts the graph as stable (``LiveSettings.expect``)."""
    names: set[str] = set()
    for contract in contracts:
        if isinstance(contract, Contract) and contract.nodl is not None:
            continue
        names.update(fqn for fqn, node in contract.nodes.items()
                     if not is_pattern_key(fqn) and node.get("destroyed_at") is None)
    return tuple(sorted(names))


def check_contract(path: str | Path, graph: LiveGraph, *, layers: Layers | None = None,
                   shown: str | None = None) -> LiveCheckResult:
    """Compare the contract at ``path`` with ``graph``; an RmwIntrospectError ends up in ``result.error``."""
    path = Path(path)
    shown = shown or display(path)
    spec = LiveSpec(graph)
    try:
        contract = load(path)
        acceptance.check_rules(contract.accept)
        is_system = isinstance(contract, SystemContract)
        as_contract = Contract(path=contract.path, nodes=contract.nodes, target=contract.target,
                               options=contract.options) if is_system else contract
        options = (layers or Layers()).options(as_contract, shown=shown)  # type: ignore[arg-type]
    except RmwIntrospectError as exc:
        return LiveCheckResult(path=path, shown=shown, spec=spec, error=exc)
    result = LiveCheckResult(path=path, shown=shown, contract=contract, spec=spec, options=options, system=is_system)
    capture: Capture = graph.capture.with_infrastructure(options.include_infrastructure)
    everything = capture.to_contract_nodes(names=result.name_rules())
    if isinstance(contract, Contract) and contract.nodl is not None:
        bound = nodl.bind(contract.nodl, contract.nodes, sorted(everything), shown)
        result.contract = contract = Contract(path=contract.path, nodes=bound, text=contract.text, nodl=contract.nodl)
        everything = nodl.project(everything, bound)
    actual = everything if is_system else {k: v for k, v in everything.items() if k in contract.nodes}
    actual, unobserved = observable(contract.nodes, actual, graph)
    if is_system:
        unobserved.append("not observable in a live graph: which process started each node and what its launch file "
                          "gave it; the rules that judge the launch file (PARAM_NOT_DECLARED, REMAP_UNUSED, "
                          "LAUNCHED_NODE_NOT_CREATED, ...) run on `rmw-introspect check` without --live")
    result.capture = LiveView(graph=graph, nodes=actual, unobserved=unobserved)
    items: list[Any] = drift.compare(contract.nodes, actual, options)
    if is_system:
        assert isinstance(contract, SystemContract)
        # one process per node (the graph does not say which process started which node); a name
        # that more than one node has stands for them all: DUPLICATE_NODE_NAME, as on a capture
        processes = [LaunchedProcess(label=fqn, expected=None, nodes={fqn: node}, launched=False,
                                     duplicates=(fqn,) * (graph.duplicate_nodes.get(fqn, 1) - 1))
                     for fqn, node in everything.items()]
        items += check_launched(processes, external=contract.external)
    leveled = rule_levels.apply(items, options.rules)  # the project's levels of rules, as check applies them
    result.turned_off = leveled.off
    items = leveled.items
    judged = acceptance.judge(drift.sort_items([i for i in items if isinstance(i, drift.DriftItem)])
                              + [i for i in items if not isinstance(i, drift.DriftItem)], contract.accept,
                              rules=acceptance.DRIFT_RULES | (acceptance.SYSTEM_RULES if is_system else frozenset()))
    result.keep(judged.kept, judged.accepted)
    result.stale = judged.stale
    return result
