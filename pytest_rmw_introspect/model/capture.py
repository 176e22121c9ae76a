"""One process's capture: the :class:`Capture` value and the facts of the run that made it.

A :class:`Capture` holds what the middleware's capture file says (``model.capture_file``:
``raw_nodes``, ``raw_endpoints`` and the file's other fields), the *contract view* built on it
(``nodes``: each node's fully qualified name → a :class:`~.capture_view.Node` with its six
interface lists, ``model.capture_view``) and, for a capture the runner made, the runner's
:class:`RunFacts` (exit status, stderr, command line, other processes, how it started), given
to it once (:meth:`Capture.with_facts`). ``Capture.notes()`` (``model.capture_notes``) says
what a report's reader should know about how it came about; ``Capture.to_contract_nodes()``
gives the ``nodes`` mapping of a contract (docs/design.md section 2).

``pytest_rmw_introspect.capture(script="talker.py")`` runs a target on the recording middleware
and returns its :class:`Capture` (see :func:`pytest_rmw_introspect.run.api.capture`).
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from . import capture_file, capture_notes, portable
from . import parameters as parameter_model
from . import types as type_model
from .capture_file import ComponentLoadRecord, Endpoint, Quiescence, RawNode, Stimulus, VirtualTime
from .capture_view import Node, build_view
from .contract_shapes import ContractNode, ContractNodes
from .parameters import Probe
from .unstable_names import NameRules, contract_keys
from .vocabulary import TRANSITION_FROM_STATE

# ---------------------------------------------------------------------- the capture


@dataclass(frozen=True)
class OtherProcess:
    """Another ROS process the target started (it ran on the middleware too and wrote its own
    capture file, which is not part of the target's capture)."""

    pid: int | None
    argv: list[str]
    node_names: list[str]

    def describe(self) -> str:
        # long paths by their last part: the program and script names are what tell processes apart
        words = [f".../{Path(w).name}" if len(w) > 40 and "/" in w else w for w in self.argv]
        command = " ".join(words) if words else "?"
        if len(command) > 120:
            command = command[:117] + "..."
        nodes = ", ".join(self.node_names) or "no node"
        return f"pid {self.pid} `{command}` ({nodes})"


@dataclass(frozen=True)
class RunFacts:
    """What the runner knows about the run that made a capture, given to it once
    (:meth:`Capture.with_facts`); a capture read from a file has none (every field empty)."""

    #: the target's exit status (negative: the signal that ended it)
    returncode: int | None = None
    #: the tail of the target's stderr
    stderr: str = ""
    #: seconds from starting the target to its end
    wall_time: float | None = None
    #: the command line the runner started
    command: tuple[str, ...] = ()
    #: other ROS processes the target started (each wrote a capture of its own)
    other_processes: tuple[OtherProcess, ...] = ()
    #: the target created no ROS node itself: this capture is of the one ROS process it started
    from_child: OtherProcess | None = None
    #: the ROS 2 distribution the target ran on (``ros_env``: jazzy, kilted, ...)
    ros_distribution: str | None = None
    #: how the runner started the target: "warm" (forked from a warm start server that had
    #: imported rclpy already) or "cold" (a new process)
    started: str | None = None
    #: why a target was started cold (a compiled executable, ``cold_start`` asked for it, the
    #: server still starting, ...); None when it started warm
    start_note: str | None = None


@dataclass
class Capture:
    """One process's capture: the raw records plus the contract view in ``nodes``."""

    nodes: dict[str, Node]
    raw_nodes: list[RawNode]
    raw_endpoints: list[Endpoint]
    state: str
    format_version: int = 1
    rmw_implementation: str | None = None
    pid: int | None = None
    argv: list[str] = field(default_factory=list)
    settle_ms: float | None = None
    time_to_settle_ms: float | None = None
    elapsed_ms: float | None = None
    #: "wait" (a thread waited quietly in an executor), "poll" (a thread polled rmw_wait and found
    #: nothing, again and again), "activity" (a steady loop that never waits kept using the
    #: middleware) or "sleep" (a loop that uses ROS and sleeps, proven idle while it slept);
    #: None before any settle
    settled_by: str | None = None
    ever_waited: bool | None = None
    activity_calls: int | None = None
    virtual_time: VirtualTime | None = None
    #: written as the process ended (states exit/shutdown): whether that was before its final settle
    ended_before_settle: bool | None = None
    include_infrastructure: bool = False
    path: Path | None = None
    #: the document as the file held it (``capture --raw`` prints it, ``with_infrastructure`` reads
    #: it again): read what it says through the fields above, never by its keys (``capture_file``)
    raw: Mapping[str, Any] = field(default_factory=dict)
    #: every interface type the process used, nested ones included, by name (``model.types``);
    #: ``has_types`` is False for captures of middleware versions that did not record them
    types: dict[str, type_model.TypeDescription] = field(default_factory=dict)
    has_types: bool = False
    #: the additive revision of ``format_version`` (1: parameters, lifecycle, probe, created_in)
    format_minor: int = 0
    #: what the middleware asked the nodes' own services after the first settle (None: a capture
    #: of a middleware version that did not)
    probe: Probe | None = None
    #: how the settles ended (None: a capture of a middleware version that did not say)
    quiescence: Quiescence | None = None
    #: each name of ``RMW_INTROSPECT_STIMULI`` and what it came to, in order (the target's ``stimuli``)
    stimuli: tuple[Stimulus, ...] = ()
    #: what each LoadNode request handed to a container's middleware came to, in order
    component_loads: tuple[ComponentLoadRecord, ...] = ()
    #: the runner's facts about the run (``RunFacts()``: a capture read from a file)
    facts: RunFacts = field(default_factory=RunFacts)

    # ---------------------------------------------------------------- building
    @classmethod
    def from_dict(
        cls,
        data: Any,
        *,
        include_infrastructure: bool = False,
        path: str | Path | None = None,
    ) -> Capture:
        """Parse a capture document (validates ``format``/``format_version`` and field types)."""
        where = Path(path) if path else None
        fields = capture_file.parse(data, path=where)
        nodes = build_view(fields["raw_nodes"], fields["raw_endpoints"], include_infrastructure=include_infrastructure)
        return cls(nodes=nodes, include_infrastructure=include_infrastructure, path=where, **fields)

    @classmethod
    def load(cls, path: str | Path, *, include_infrastructure: bool = False) -> Capture:
        """Read a capture file written by the middleware."""
        path = Path(path)
        return cls.from_dict(capture_file.read(path), include_infrastructure=include_infrastructure, path=path)

    def with_facts(self, facts: RunFacts, *, argv: Sequence[str] | None = None, keep_path: bool = True) -> Capture:
        """This capture with the runner's ``facts`` (in place of any it had); ``argv``: the command
        line the process had in place of the one the file records (a warm start's child reads the
        server's), ``keep_path``: False when the file is not kept (``path`` None)."""
        return replace(self, facts=facts, argv=self.argv if argv is None else list(argv),
                       path=self.path if keep_path else None)

    def with_infrastructure(self, include: bool) -> Capture:
        """The same capture with the infrastructure filter set to ``include``."""
        if include == self.include_infrastructure:
            return self
        other = Capture.from_dict(self.raw, include_infrastructure=include, path=self.path)
        return other.with_facts(self.facts, argv=self.argv)

    # ---------------------------------------------------------------- the runner's facts
    @property
    def returncode(self) -> int | None:
        """The target's exit status (None: a capture read from a file)."""
        return self.facts.returncode

    @property
    def stderr(self) -> str:
        """The tail of the target's stderr."""
        return self.facts.stderr

    @property
    def wall_time(self) -> float | None:
        """Seconds from starting the target to its end."""
        return self.facts.wall_time

    @property
    def command(self) -> list[str]:
        """The command line the runner started."""
        return list(self.facts.command)

    @property
    def other_processes(self) -> list[OtherProcess]:
        """Other ROS processes the target started (each wrote a capture of its own)."""
        return list(self.facts.other_processes)

    @property
    def from_child(self) -> OtherProcess | None:
        """The target created no ROS node itself: this capture is of the one ROS process it started."""
        return self.facts.from_child

    @property
    def ros_distribution(self) -> str | None:
        """The ROS 2 distribution the target ran on (None: a capture read from a file)."""
        return self.facts.ros_distribution

    @property
    def started(self) -> str | None:
        """How the runner started the target, ``warm`` or ``cold`` (None: a capture read from a file)."""
        return self.facts.started

    @property
    def start_note(self) -> str | None:
        """Why the target was started cold; None when it started warm."""
        return self.facts.start_note

    # ---------------------------------------------------------------- queries
    def __getitem__(self, fqn: str) -> Node:
        try:
            return self.nodes[fqn]
        except KeyError:
            raise KeyError(f"no node {fqn!r} in the capture; nodes: {sorted(self.nodes)}") from None

    def __contains__(self, fqn: object) -> bool:
        return fqn in self.nodes

    def __iter__(self) -> Iterator[Node]:
        return iter(self.nodes[k] for k in sorted(self.nodes))

    def __len__(self) -> int:
        return len(self.nodes)

    def node(self, fqn: str) -> Node:
        return self[fqn]

    @property
    def node_names(self) -> list[str]:
        return sorted(self.nodes)

    @property
    def settled(self) -> bool:
        return self.state in ("settled", "shutdown", "exit")

    @property
    def settled_once(self) -> bool:
        """The process settled at least once: what it had then, and created later, is valid."""
        if self.state in ("probing", "warping", "settled"):
            return True
        return self.state in ("exit", "shutdown") and self.time_to_settle_ms is not None

    @property
    def ended_by_itself(self) -> bool:
        """The program ended on its own, with status 0, before the capture's final settle."""
        return bool(self.ended_before_settle) and self.returncode == 0

    @property
    def duplicate_node_names(self) -> list[str]:
        """Fully qualified names held by more than one live node of this process (a real ROS 2
        failure: their parameter services and logs collide; a contract can list them only once)."""
        counts: dict[str, int] = {}
        for raw_node in self.raw_nodes:
            if raw_node.alive:
                counts[raw_node.fqn] = counts.get(raw_node.fqn, 0) + 1
        return sorted(fqn for fqn, count in counts.items() if count > 1)

    def notes(self) -> list[str]:
        """What a reader of a report should know about how this capture came about
        (``model.capture_notes``)."""
        return capture_notes.notes(self)

    def make_values_portable(self, shares: Mapping[str, str], home: str | None = None) -> None:
        """Write every package share directory (``shares``: directory → package) in the nodes'
        parameter values as ``$(find-pkg-share PACKAGE)``, and the home directory ``home`` as
        ``$(env HOME)`` (``model.portable``), so that the values are the same on every machine."""
        for node in self.nodes.values():
            if node.parameters:
                node.parameters = [replace(p, value=portable.portable_value(p.value, shares, home))
                                   for p in node.parameters]

    @property
    def polls(self) -> int:
        """Polls of ``rmw_wait`` (timeout 0: ``spin_some``, ``spin_once(timeout_sec=0)``) the process
        made (``quiescence.polls``; 0 for captures that do not say)."""
        return self.quiescence.polls if self.quiescence is not None else 0

    @property
    def not_idle(self) -> str | None:
        """Why the middleware last found the process not provably idle (a thread not blocked,
        and in which system call), or None (``quiescence.not_idle``)."""
        return self.quiescence.not_idle if self.quiescence is not None else None

    def last_change_ms(self) -> float | None:
        """Real age of the process when it created its last node or interface (None: unknown)."""
        ages = [n.created_real_ms for n in self.raw_nodes] + [e.created_real_ms for e in self.raw_endpoints]
        known = [age for age in ages if age is not None]
        return max(known) if known else None

    def failed_transitions(self) -> list[tuple[str, str, str, str]]:
        """The lifecycle transitions the middleware drove that did not succeed: ``(node, transition,
        what was recorded, the state the node stays in)`` per node (the driving stops there)."""
        out = []
        for node in self:
            lifecycle = node.lifecycle
            failed = lifecycle.failed_transition if lifecycle is not None else None
            if lifecycle is None or failed is None:
                continue
            recorded = lifecycle.error or f"change_state {failed.result}"
            prefix = f"transition {failed.label} of {node.fqn} failed: "
            out.append((node.fqn, failed.label, recorded.removeprefix(prefix),
                        TRANSITION_FROM_STATE.get(failed.label, "none")))
        return out

    def endpoints(self, *, include_destroyed: bool = False) -> list[Endpoint]:
        """All raw endpoints (infrastructure included), by creation order."""
        return [e for e in self.raw_endpoints if include_destroyed or not e.destroyed]

    def to_contract_nodes(self, *, with_type_hash: bool = True, with_qos: bool = True,
                          with_parameters: bool = True, names: NameRules | None = None) -> ContractNodes:
        """The ``nodes`` mapping of a contract (sorted; see docs/design.md section 2): a node
        whose name changes every run under its pattern (``unstable_names``; ``names``: the
        contract's patterns and nodes, default the built-in rules only)."""
        return dict(sorted(contract_keys(self.named_contract_nodes(with_type_hash=with_type_hash, with_qos=with_qos,
                                                                   with_parameters=with_parameters), names)))

    def named_contract_nodes(self, *, with_type_hash: bool = True, with_qos: bool = True,
                             with_parameters: bool = True) -> list[tuple[str, ContractNode, int | None]]:
        """Each node as ``(its name in this run, its contract entry, the process id)``, sorted by
        name: what ``unstable_names.contract_keys`` turns into contract keys."""
        return [
            (fqn, self.nodes[fqn].to_contract(with_type_hash=with_type_hash, with_qos=with_qos,
                                              with_parameters=with_parameters), self.pid)
            for fqn in sorted(self.nodes)
        ]

    def to_contract_types(self) -> dict[str, type_model.TypeDescription]:
        """The ``types:`` section of a contract: the descriptions the contract view's interfaces
        need (their types, an action's parts, everything they nest), by name."""
        return type_model.for_interfaces(
            self.types, ((list_name, i.type) for node in self for list_name, i in node.interfaces()))

    def summary(self) -> str:
        """A short human-readable listing (used in error messages)."""
        lines = [f"state: {self.state}; {len(self.nodes)} node(s)"
                 + (f"; started {self.started}" if self.started else "")]
        vt = self.virtual_time
        if vt is not None and vt.enabled:
            lines.append(
                f"virtual time: {vt.virtual_elapsed_ms / 1000:.3g} s of a {vt.horizon_ms / 1000:g} s horizon "
                f"in {vt.real_elapsed_ms / 1000:.3g} s real ({vt.jumps} jumps)"
            )
        lines += [f"note: {note}" for note in self.notes()]
        for node in self:
            state = f" (lifecycle node, {node.lifecycle_state})" if node.lifecycle_state else ""
            lines.append(node.fqn + state + _destroyed_text(node.destroyed_at))
            for list_name, entry in node.interfaces():
                created = f" (created in {entry.created_in})" if entry.created_in else ""
                destroyed = _destroyed_text(entry.destroyed_at) if entry.destroyed_at != node.destroyed_at else ""
                lines.append(f"  {list_name}: {entry.name} [{entry.type}]{created}{destroyed}")
            for param in node.parameters or ():
                lines.append(f"  parameter: {param.name} [{param.type}] = "
                             f"{parameter_model.format_value(param.value)}")
        return "\n".join(lines)

    def __repr__(self) -> str:
        return f"<Capture state={self.state} nodes={self.node_names}>"



def _destroyed_text(age: float | None) -> str:
    return "" if age is None else f" (destroyed by the program at {age:g} s)"
