"""``rmw-introspect check --bag PATH CONTRACT...``: contracts checked against a recording.

The recording is read once (``model.recording``); then every contract (node or system contract)
gives one result, like a check that captured, and the recording itself one more (listed first):

* a contract's result (:class:`RecordingCheckResult`): the drift of its publishers against what was
  recorded, and its system problems (its subscriptions against the recorded publishers, its
  publishers' topics not recorded or recorded silent: ``compare.recordings``), judged by its
  ``options:`` (under the command line's), its ``accept:`` entries and a baseline as any check;
* the recording's result: the recorded topics no contract declares, and per topic the type and
  the message count (the passing line, the report, the notes of the CI formats).

The results are ``check.outcome.Checked`` values, so ``check``'s loop reports them in every format
with its exit statuses. Nothing is written: a recording does not update a contract (its drift is
accepted with ``accept:`` entries or a baseline).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..compare import acceptance, report, rule_levels
from ..compare import recordings as compare_recordings
from ..compare.ci_report import ContractOutcome
from ..compare.options import ComparisonOptions
from ..errors import RmwIntrospectError
from ..model import contract as contract_module
from ..model import contract_kind, system_contract
from ..model import recording as recording_model
from ..model.acceptance import Acceptance
from ..model.contract import Contract
from ..model.contract_shapes import ContractNodes, ContractOptions
from ..model.locate import LineIndex, line_index
from ..model.paths import shown as display
from ..model.recording import Recording
from ..model.unstable_names import NameRules
from ..model.vocabulary import parse_threshold
from .pipeline import Layers, OptionLayer
from .result import ContractCheck

#: what a recording does not show, said once per run
CANNOT_SHOW = ("a recording shows topics, their types, type hashes (where recorded), the QoS their publishers "
               "offered and the messages; not subscriptions, services, actions (but for their recorded topics), "
               "parameters, lifecycle states, nor which node published: those are not compared, and a contract's "
               "publisher is matched to its topic's recorded publishers by the topic alone")
#: how drift against a recording is accepted (there is no capture to write into the contract)
HOW_TO_ACCEPT = ("an `accept:` entry in the contract, or a baseline (--write-baseline FILE): a recording does not "
                 "update a contract")
COUNTS_SHOWN = 20


def _counted(n: int, word: str) -> str:
    return f"{n} {word}{'' if n == 1 else 's'}"


def _messages(count: int | None) -> str:
    return "? messages" if count is None else _counted(count, "message")


@dataclass(frozen=True)
class RecordingSpec:
    """What a recording check looked at (a result's ``spec``)."""

    recording: Recording

    def describe(self) -> str:
        return f"the recording {self.recording.shown}"


@dataclass(frozen=True)
class RecordedSystem:
    """The recording as a result's ``capture``: its topics; it has no nodes to write."""

    recording: Recording

    def to_contract_nodes(self, *, with_type_hash: bool = True, with_qos: bool = True,
                          names: NameRules | None = None) -> ContractNodes:
        return {}

    def notes(self) -> list[str]:
        return list(self.recording.notes)

    def summary(self) -> str:
        return topic_table(self.recording)


@dataclass(frozen=True)
class _NoPromises:
    """The recording's own result has no contract: it promises no node."""

    nodes: ContractNodes = field(default_factory=dict)
    interface_version: str | None = None


def topic_table(recording: Recording, names: Sequence[str] | None = None) -> str:
    """The recorded topics (or ``names`` of them), one line each: name, type, message count."""
    topics = [t for t in recording.topics if names is None or t.name in names]
    width = max((len(t.name) for t in topics), default=0)
    return "".join(f"{t.name.ljust(width)}  {t.type}  {_messages(t.message_count)}\n" for t in topics)


@dataclass
class RecordingCheckResult(ContractCheck[Contract | _NoPromises, RecordingSpec, RecordedSystem]):
    """One contract checked against a recording (``contract``: the node or system contract), or
    the recording's own result (``own``: the recorded topics no contract declares)."""

    own: bool = False
    #: the contract's publishers whose topics were recorded: (node, topic, message count)
    recorded: list[tuple[str, str, int | None]] = field(default_factory=list)
    #: how many of the contract's subscriptions have their topic in the recording
    subscribed: int = 0
    lines: LineIndex = field(default_factory=dict)

    @property
    def recording(self) -> Recording:
        assert self.spec is not None
        return self.spec.recording

    def can_gain(self) -> bool:
        return False

    def name_rules(self) -> NameRules:
        return NameRules()

    def update(self) -> str | None:
        return None  # refused before the check (``cli.recordings``)

    @property
    def stood_in(self) -> list[str]:
        return []

    def check_notes(self) -> list[str]:
        return [CANNOT_SHOW] if self.own else []

    def title(self) -> str:
        return f"Interface drift of the recording {self.recording.shown}"  # the report adds "against CONTRACT"

    def matched(self, *, names: bool) -> str:
        recording = self.recording
        if self.own:
            topics = sorted(recording.topics, key=lambda t: t.name)
            shown = topics if names else topics[:COUNTS_SHOWN]
            counts = ", ".join(f"{t.name} {_messages(t.message_count)}" for t in shown)
            more = f", and {len(topics) - len(shown)} more (-v: all)" if len(topics) > len(shown) else ""
            return (f"every topic declared; {_counted(len(topics), 'recorded topic')}, "
                    f"{_counted(recording.message_count, 'message')}: {counts}{more}")
        counted = sum(c or 0 for _, _, c in self.recorded)
        said = f"{_counted(len(self.recorded), 'publisher')} on recorded topics, {_counted(counted, 'message')}"
        if names and self.recorded:
            said += ": " + ", ".join(f"{node} {topic} {_messages(count)}" for node, topic, count in self.recorded)
        if self.subscribed:
            said += f"; {_counted(self.subscribed, 'subscription')} fit the recorded publishers"
        return f"{said}, in {recording.shown}"

    def to_json(self) -> list[dict[str, Any]]:
        """The findings (``ContractCheck.to_json``), each about a recorded topic with its
        ``message_count`` and every one with the ``recording`` it was found in."""
        counts = {t.name: t.message_count for t in self.recording.topics} if self.spec is not None else {}
        out = []
        for item in super().to_json():
            extra: dict[str, Any] = {"recording": self.recording.shown} if self.spec is not None else {}
            if item.get("name") in counts:
                extra["message_count"] = counts[item["name"]]
            out.append({**item, **extra})
        return out

    def notes(self) -> list[str]:
        return [*(self.recording.notes if self.own else []), *self.rule_level_notes()]

    def render_text(self, accept_command: str | None = None) -> str:
        if self.error is not None:
            return str(self.error)
        parts = []
        if self.drift_items:
            parts.append(report.render_text(self.drift_items, contract_path=self.shown, threshold=self.threshold,
                                            accept_command=None, title=self.title()))
        if self.system_items:
            title = (f"The recording {self.shown}" if self.own
                     else f"System check of the recording {self.recording.shown} against {self.shown}")
            parts.append(report.render_system_problems(self.system_items, threshold=self.system_threshold,
                                                       title=title))
        text = "\n".join(p.rstrip("\n") + "\n" for p in parts)
        if self.accepted or self.stale:
            text += "\n".join(report.render_acceptances(self.accepted, self.stale)).lstrip("\n") + "\n"
        if self.drift_items and not self.own:
            text += f"Accept on purpose with {HOW_TO_ACCEPT}.\n"
        if self.own:
            text += f"\nRecorded topics ({self.recording.storage}):\n" + "".join(
                f"  {line}\n" for line in topic_table(self.recording).splitlines())
        notes = self.notes()
        if notes:
            text += "\nNotes on the recording:\n" + "".join(f"  - {note}\n" for note in notes)
        return text

    def for_ci(self, *, written: str | None = None) -> ContractOutcome:
        recording = self.recording if self.spec is not None else None
        if self.own and recording is not None:
            nodes = [f"{t.name} ({_messages(t.message_count)})" for t in recording.topics]
            notes = [*recording.notes, CANNOT_SHOW]
        else:
            nodes = sorted(self.contract.nodes) if self.contract is not None else []
            notes = []
        return ContractOutcome(
            contract=self.shown, items=self.drift_items, threshold=self.threshold, nodes=nodes,
            error=str(self.error) if self.error is not None else None, written=written, lines=self.lines,
            system_items=self.system_items, system_threshold=self.system_threshold,
            accepted=self.accepted, stale=self.stale, notes=notes)


# ---------------------------------------------------------------------------- the check


def _load(path: Path) -> tuple[Contract, list[Acceptance], dict[str, dict[str, str]], LineIndex]:
    """A node or system contract as a ``Contract`` (nodes, options), its ``accept:`` entries, its
    declared outside world and where it lists its nodes (raises ContractError)."""
    if contract_kind.is_system_file(path):
        system = system_contract.load(path)
        return contract_kind.as_node_contract(system), list(system.accept), dict(system.external), line_index(system.text)
    contract = contract_module.load(path)
    return contract, list(contract.accept), {}, contract.lines()


@dataclass
class BagCheck:
    """A recording read once, checked against each contract of a run (:meth:`check`), and
    against all of them together (:meth:`check_recording`: the topics no contract declares)."""

    recording: Recording
    layers: Layers = field(default_factory=Layers)
    #: every contract checked so far: (as shown, nodes), and their ``external:`` blocks
    seen: list[tuple[str, ContractNodes]] = field(default_factory=list)
    external: list[dict[str, dict[str, str]]] = field(default_factory=list)
    #: the options each contract was judged by (the recording's result takes the strictest)
    judged_by: list[ComparisonOptions] = field(default_factory=list)

    @classmethod
    def read(cls, path: str | Path, options: Sequence[OptionLayer] = ()) -> BagCheck:
        """Read the recording at ``path`` (raises RecordingError); ``options``: the comparison
        options given above every contract's own (the command line's)."""
        return cls(recording_model.read(path), Layers(strong_options=options))

    @property
    def shown(self) -> str:
        return self.recording.shown

    @property
    def how_to_accept(self) -> str:
        """How drift against a recording is accepted (there is no capture to write)."""
        return HOW_TO_ACCEPT

    def order(self, contracts: Sequence[str]) -> list[str]:
        """What a run reports, in order: each contract, then the recording (as shown)."""
        return [*contracts, self.shown]

    def result(self, path: str | Path, shown: str) -> RecordingCheckResult:
        """The result of one entry of :meth:`order`: a contract's, or (last) the recording's."""
        return self.check_recording() if shown == self.shown else self.check(path, shown)

    def _result(self, path: Path, shown: str, **kwargs: object) -> RecordingCheckResult:
        return RecordingCheckResult(path=path, shown=shown, spec=RecordingSpec(self.recording),
                                    capture=RecordedSystem(self.recording), **kwargs)  # type: ignore[arg-type]

    def check(self, path: str | Path, shown: str | None = None) -> RecordingCheckResult:
        """One contract against the recording; an RmwIntrospectError ends up in ``result.error``."""
        path = Path(path)
        shown = shown or display(path)
        try:
            contract, accept, external, lines = _load(path)
            options = self.layers.options(contract, shown=shown)
        except RmwIntrospectError as exc:
            return self._result(path, shown, error=exc)
        self.seen.append((shown, contract.nodes))
        self.external.append(external)
        self.judged_by.append(options)
        found = compare_recordings.compare_contract(shown, contract.nodes, self.recording, options,
                                                    contract.ros_distribution)
        result = self._result(path, shown, contract=contract, options=options, recorded=found.recorded,
                              subscribed=found.subscribed, lines=lines)
        self._judge(result, [*found.drift_items, *found.system_items], accept)
        return result

    def check_recording(self) -> RecordingCheckResult:
        """The recording against every contract checked (call after :meth:`check` of each): the
        recorded topics none of them declares, judged by the strictest ``fail_on`` and
        ``system_fail_on`` of the contracts (under the command line's)."""
        strictest = ContractOptions()
        if self.judged_by:
            strictest["fail_on"] = min((o.fail_on for o in self.judged_by), key=parse_threshold)
            strictest["system_fail_on"] = min((o.system_fail_on for o in self.judged_by), key=parse_threshold)
        as_contract = Contract(path=None, nodes={}, options=strictest)
        options = self.layers.options(as_contract, shown=f"{self.shown} (the strictest options of the contracts)")
        items = compare_recordings.undeclared(self.recording, self.seen, self.external, options)
        result = self._result(self.recording.path, self.shown, contract=_NoPromises(), options=options, own=True)
        self._judge(result, items, [])
        return result

    @staticmethod
    def _judge(result: RecordingCheckResult, items: Sequence[object], accept: Sequence[Acceptance]) -> None:
        leveled = rule_levels.apply(items, result.options.rules)  # the project's levels of rules, as check's
        result.turned_off = leveled.off
        judged = acceptance.judge(leveled.items, accept, rules=compare_recordings.CHECKED_RULES)
        result.keep(judged.kept, judged.accepted)
        result.stale = judged.stale

