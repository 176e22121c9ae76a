"""A typed model of one capture (what one process created), read from the middleware's JSON.

The raw file (docs/design.md section 1) lists nodes and endpoints as the middleware saw them.
:class:`Capture` keeps that (``raw_nodes``, ``raw_endpoints``) and builds the *contract
view* on top of it: ``capture.nodes`` maps each live node's fully qualified name to a
:class:`Node` with six lists of :class:`Interface` (publishers, subscriptions, service
servers, service clients, action servers, action clients), where

* actions are grouped from their ``<a>/_action/...`` services and topics,
* infrastructure endpoints (``/rosout``, ``/parameter_events``, parameter services,
  ``get_type_description``, lifecycle services and ``transition_event``) are left out unless
  ``include_infrastructure=True``,
* nodes and endpoints the program itself destroyed while it ran are kept, with their virtual
  age at destruction (``destroyed_at``, seconds: they belong to the interface the program
  offered until then); those destroyed in the run of destructions that ended the program
  (``in_teardown``) count as alive until its own final teardown; captures older than
  ``format_minor`` 4 do not say when an entity was destroyed, so their destroyed entities are
  left out (they stay in ``raw_*``),
* hidden names (a segment starting with ``_``) are kept,

and each node has its ``parameters`` (as its own parameter services answered the middleware;
the ones the client library declares by itself, ``use_sim_time`` and the like, left out unless
``include_infrastructure``; None when they were not read) and, for a lifecycle node, its
``lifecycle`` record (how the middleware drove it and the state it reached).

``Capture.to_contract_nodes()`` gives the ``nodes`` mapping of a contract
(docs/design.md section 2).

This module is also callable: ``pytest_rmw_introspect.capture(script="talker.py")`` runs a
target on the recording middleware and returns its :class:`Capture` (see
:func:`pytest_rmw_introspect.run.api.capture`).
"""

from __future__ import annotations

import json
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, cast

from ..errors import CaptureFormatError
from . import parameters as parameter_model
from . import portable, untrusted
from . import qos as qos_module
from . import types as type_model
from .contract_shapes import ActionTypeHash, ContractNode, ContractNodes, InterfaceEntry, QosFields
from .parameters import Lifecycle, Parameter, Probe
from .vocabulary import (
    ACTION_HASHED_PARTS,
    ACTION_SERVICES,
    ACTION_TOPICS,
    DESTROYED_AT,
    INFRASTRUCTURE_TOPICS,
    KIND_TO_LIST,
    LIFECYCLE,
    LIFECYCLE_SERVICES,
    LIFECYCLE_TOPICS,
    LIFECYCLE_UNKNOWN,
    LISTS,
    LOGGER_SERVICES,
    PARAMETER_SERVICES,
    PARAMETERS,
    TRANSITION_FROM_STATE,
)

FORMAT = "rmw_introspect_capture"
FORMAT_VERSIONS = (1,)

SIM_CLOCK_TYPE = "rosgraph_msgs/msg/Clock"


# ---------------------------------------------------------------------- raw records


class _Lifetime:
    """How long a recorded node or endpoint lived (shared by :class:`RawNode` and :class:`Endpoint`)."""

    destroyed: bool
    in_teardown: bool
    destroyed_virtual_ms: float | None

    @property
    def alive(self) -> bool:
        """Alive at the end of the capture, or until the program's own final teardown."""
        return not self.destroyed or self.in_teardown

    @property
    def destroyed_at(self) -> float | None:
        """Seconds of virtual age at which the program itself destroyed it (None: alive)."""
        if self.alive or self.destroyed_virtual_ms is None:
            return None
        return round(self.destroyed_virtual_ms / 1000.0, 1)

    @property
    def in_view(self) -> bool:
        """Part of the contract view: alive, or destroyed by the program at a known age."""
        return self.alive or self.destroyed_at is not None


@dataclass(frozen=True)
class RawNode(_Lifetime):
    """A node as the middleware recorded it."""

    id: int
    seq: int
    name: str
    namespace: str
    fqn: str
    enclave: str = "/"
    destroyed: bool = False
    #: destroyed in the run of destructions that ended the process (alive before its teardown)
    in_teardown: bool = False
    #: the node's virtual and real age (ms since the first rmw_init) when it was created
    created_virtual_ms: float | None = None
    created_real_ms: float | None = None
    #: the node's virtual and real age when the program destroyed it (None: not destroyed by the
    #: program while it ran, or a capture older than format_minor 4)
    destroyed_virtual_ms: float | None = None
    destroyed_real_ms: float | None = None
    #: every parameter as the node's own services answered (None: not read, see
    #: ``parameters_error``), in the order the node listed them
    parameters: tuple[Parameter, ...] | None = None
    #: why a node with parameter services has no ``parameters``
    parameters_error: str | None = None
    #: how the middleware drove a lifecycle node (None: not a lifecycle node)
    lifecycle: Lifecycle | None = None


@dataclass(frozen=True)
class Endpoint(_Lifetime):
    """A publisher, subscription, service server or client as the middleware recorded it.

    ``kind`` is ``publisher``, ``subscription``, ``service`` or ``client``; ``qos`` is the raw
    rmw QoS (UPPER_CASE enums, integer nanoseconds).
    """

    seq: int
    kind: str
    node_id: int
    node: str
    name: str
    type: str
    type_hash: str | None
    qos: Mapping[str, Any]
    typesupport: str | None = None
    destroyed: bool = False
    in_teardown: bool = False
    created_virtual_ms: float | None = None
    created_real_ms: float | None = None
    destroyed_virtual_ms: float | None = None
    destroyed_real_ms: float | None = None
    #: the lifecycle transition the middleware had last driven on the node when the endpoint was
    #: created (``configure``, ``activate``); None: created at start-up (or by a node that
    #: drives itself)
    created_in: str | None = None


@dataclass(frozen=True)
class VirtualTime:
    """How far the middleware advanced the node's clock (``time`` in the capture file)."""

    horizon_ms: float
    virtual_elapsed_ms: float
    real_elapsed_ms: float
    jumps: int
    warp_ms: float
    horizon_reached: bool
    warp_budget_exhausted: bool
    #: the warp ended early: the process kept running but never waited with a timeout (it polls
    #: or sleeps on its own clock), so virtual time had nothing to jump to
    warp_stalled: bool = False
    #: what the program did in the warp (None: a capture that does not say): the real time the
    #: warp lasted, its returns from rmw_wait without waiting and its activity calls
    warp_real_ms: float | None = None
    warp_polls: int | None = None
    warp_activity: int | None = None

    @property
    def enabled(self) -> bool:
        return self.horizon_ms > 0


# ---------------------------------------------------------------------- contract view


@dataclass(frozen=True)
class Interface:
    """One entry of a node's interface list.

    ``type_hash`` is a string, or for actions the mapping ``{send_goal, get_result,
    feedback}``; ``qos`` is the contract form (NoDL v2 spellings, defaults omitted) for
    topics and ``None`` for services and actions. ``endpoints`` are the raw endpoints the
    entry was built from (five for an action).
    """

    name: str
    type: str
    type_hash: str | Mapping[str, str] | None = None
    qos: Mapping[str, Any] | None = None
    endpoints: tuple[Endpoint, ...] = ()

    @property
    def destroyed_at(self) -> float | None:
        """Seconds of virtual age at which the program destroyed the entry's last endpoint (None:
        one of them is alive to the end)."""
        return _destroyed_at(self.endpoints)

    @property
    def raw_qos(self) -> Mapping[str, Any] | None:
        """The raw rmw QoS of the (first) underlying endpoint."""
        return self.endpoints[0].qos if self.endpoints else None

    @property
    def created_in(self) -> str | None:
        """The lifecycle transition that created the (first) underlying endpoint, or None."""
        return self.endpoints[0].created_in if self.endpoints else None

    def to_contract(self, *, with_type_hash: bool = True, with_qos: bool = True,
                    node_destroyed_at: float | None = None) -> InterfaceEntry:
        """The contract entry; ``destroyed_at`` only when the entry went before its node
        (``node_destroyed_at``: when the node went, None: it lived to the end)."""
        entry: InterfaceEntry = {"name": self.name, "type": self.type}
        if with_type_hash and self.type_hash:
            entry["type_hash"] = (cast(ActionTypeHash, dict(self.type_hash)) if isinstance(self.type_hash, Mapping)
                                  else self.type_hash)
        if with_qos and self.qos is not None:
            entry["qos"] = cast(QosFields, dict(self.qos))
        if self.destroyed_at is not None and self.destroyed_at != node_destroyed_at:
            entry[DESTROYED_AT] = self.destroyed_at
        return entry


@dataclass
class Node:
    """A live node of the capture with its interfaces (contract view)."""

    fqn: str
    name: str
    namespace: str
    publishers: list[Interface] = field(default_factory=list)
    subscriptions: list[Interface] = field(default_factory=list)
    service_servers: list[Interface] = field(default_factory=list)
    service_clients: list[Interface] = field(default_factory=list)
    action_servers: list[Interface] = field(default_factory=list)
    action_clients: list[Interface] = field(default_factory=list)
    raw: tuple[RawNode, ...] = ()
    endpoints: tuple[Endpoint, ...] = ()
    #: the node's parameters (infrastructure ones left out unless ``include_infrastructure``),
    #: sorted by name; None when they were not read (no parameter services, a C node, target
    #: option ``read_parameters: false``, or see ``parameters_error``)
    parameters: list[Parameter] | None = None
    parameters_error: str | None = None
    #: how the middleware drove it, when it is a lifecycle (managed) node
    lifecycle: Lifecycle | None = None

    @property
    def destroyed_at(self) -> float | None:
        """Seconds of virtual age at which the program destroyed the node (None: alive to the
        end; of two nodes of one name, the later destruction)."""
        if any(r.destroyed_at is None for r in self.raw):
            return None
        return max((r.destroyed_at for r in self.raw if r.destroyed_at is not None), default=None)

    @property
    def lifecycle_state(self) -> str | None:
        """The state a lifecycle node was captured in (``unknown`` when it was not read: target
        ``lifecycle: none``); None for a node that is not a lifecycle node."""
        if self.lifecycle is None:
            return None
        return self.lifecycle.state or LIFECYCLE_UNKNOWN

    def parameter(self, name: str) -> Parameter | None:
        """The parameter ``name`` (None when the node has none of that name, or none read)."""
        for p in self.parameters or ():
            if p.name == name:
                return p
        return None

    @property
    def uses_sim_time(self) -> bool:
        """The node subscribes to ``/clock`` (``use_sim_time``): its ROS time stands still in a
        capture, so timers on the ROS clock never fire."""
        return any(
            e.kind == "subscription" and e.name == "/clock" and e.type == SIM_CLOCK_TYPE and e.alive for e in self.endpoints
        )

    def interfaces(self) -> Iterator[tuple[str, Interface]]:
        for list_name in LISTS:
            for entry in getattr(self, list_name):
                yield list_name, entry

    def names(self, list_name: str) -> list[str]:
        return [i.name for i in getattr(self, list_name)]

    def get(self, list_name: str, name: str) -> Interface | None:
        entries: list[Interface] = getattr(self, list_name)
        for entry in entries:
            if entry.name == name:
                return entry
        return None

    def to_contract(self, *, with_type_hash: bool = True, with_qos: bool = True,
                    with_parameters: bool = True) -> ContractNode:
        """The node's contract entry: ``lifecycle`` (a lifecycle node), the six lists, and
        ``parameters`` when they were read (and ``with_parameters``)."""
        out = ContractNode()
        if self.lifecycle_state is not None:
            out[LIFECYCLE] = self.lifecycle_state
        if self.destroyed_at is not None:
            out[DESTROYED_AT] = self.destroyed_at
        for list_name in LISTS:
            out[list_name] = [
                i.to_contract(with_type_hash=with_type_hash, with_qos=with_qos,
                              node_destroyed_at=self.destroyed_at)
                for i in sorted(getattr(self, list_name), key=lambda i: i.name)
            ]
        if with_parameters and self.parameters is not None:
            out[PARAMETERS] = [p.to_contract() for p in sorted(self.parameters, key=lambda p: p.name)]
        return out


# ---------------------------------------------------------------------- the capture


@dataclass
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
    #: nothing, again and again) or "activity" (a steady loop that never waits kept using the
    #: middleware); None before any settle
    settled_by: str | None = None
    ever_waited: bool | None = None
    activity_calls: int | None = None
    virtual_time: VirtualTime | None = None
    #: written as the process ended (states exit/shutdown): whether that was before its final settle
    ended_before_settle: bool | None = None
    include_infrastructure: bool = False
    path: Path | None = None
    raw: Mapping[str, Any] = field(default_factory=dict)
    #: filled in by the runner
    returncode: int | None = None
    stderr: str = ""
    wall_time: float | None = None
    command: list[str] = field(default_factory=list)
    #: other ROS processes the target started (each wrote a capture of its own)
    other_processes: list[OtherProcess] = field(default_factory=list)
    #: the target created no ROS node itself: this capture is of the one ROS process it started
    from_child: OtherProcess | None = None
    #: every interface type the process used, nested ones included, by name (``model.types``);
    #: ``has_types`` is False for captures of middleware versions that did not record them
    types: dict[str, type_model.TypeDescription] = field(default_factory=dict)
    has_types: bool = False
    #: how the runner started the target: "warm" (forked from a warm start server that had
    #: imported rclpy already) or "cold" (a new process); None for a capture read from a file
    started: str | None = None
    #: why a target was started cold (a compiled executable, ``cold_start`` asked for it, the
    #: server still starting, ...); None when it started warm
    start_note: str | None = None
    #: the ROS 2 distribution the target ran on (``ros_env``: jazzy, kilted, ...); None for a
    #: capture read from a file
    ros_distribution: str | None = None
    #: the additive revision of ``format_version`` (1: parameters, lifecycle, probe, created_in)
    format_minor: int = 0
    #: what the middleware asked the nodes' own services after the first settle (None: a capture
    #: of a middleware version that did not)
    probe: Probe | None = None

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
        return _parse(data, include_infrastructure=include_infrastructure, path=Path(path) if path else None)

    @classmethod
    def load(cls, path: str | Path, *, include_infrastructure: bool = False) -> Capture:
        """Read a capture file written by the middleware."""
        path = Path(path)
        try:
            text = untrusted.read_text(path)
        except FileNotFoundError:
            raise CaptureFormatError(path, "the file does not exist") from None
        except untrusted.InputError as exc:
            raise CaptureFormatError(path, exc.reason) from None
        if not text.strip():
            raise CaptureFormatError(path, "the file is empty")
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            if not text.lstrip().startswith("format:"):
                raise CaptureFormatError(path, f"not valid JSON: {exc}") from None
            try:  # RMW_INTROSPECT_FORMAT=yaml
                root = untrusted.compose_yaml(text)
                if root is None:
                    raise CaptureFormatError(path, "the file is empty")
                untrusted.check_tree(root)
                data = untrusted.construct(root)
            except untrusted.InputError as yaml_exc:
                raise CaptureFormatError(path, f"not valid JSON ({exc}) or YAML ({yaml_exc})") from None
        except RecursionError:
            raise CaptureFormatError(path, "nested too deeply") from None
        return cls.from_dict(data, include_infrastructure=include_infrastructure, path=path)

    def with_infrastructure(self, include: bool) -> Capture:
        """The same capture with the infrastructure filter set to ``include``."""
        if include == self.include_infrastructure:
            return self
        other = _parse(self.raw, include_infrastructure=include, path=self.path)
        other.returncode, other.stderr, other.wall_time, other.command = (
            self.returncode, self.stderr, self.wall_time, self.command,
        )
        other.other_processes, other.from_child = self.other_processes, self.from_child
        other.started, other.start_note, other.argv = self.started, self.start_note, self.argv
        other.ros_distribution = self.ros_distribution
        return other

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
        """What a reader of a report should know about how this capture came about."""
        notes: list[str] = []
        if self.from_child is not None:
            notes.append(
                "the target created no ROS node itself; this is the capture of the ROS process it started: "
                + self.from_child.describe()
            )
        if self.other_processes:
            notes.append(
                "the target started other ROS processes, which are not part of this capture (capture each "
                "as a target of its own): " + "; ".join(p.describe() for p in self.other_processes)
            )
        for fqn in self.duplicate_node_names:
            count = sum(1 for raw_node in self.raw_nodes if raw_node.alive and raw_node.fqn == fqn)
            notes.append(
                f"{count} nodes are named {fqn} in one process: ROS 2 cannot tell them apart (their parameter "
                "services collide); the contract lists their interfaces under one entry. Give each node a "
                "name of its own."
            )
        if self.ended_by_itself:
            notes.append(
                "the program ended by itself (status 0) before its final settle: the capture is what was "
                "alive just before its own final teardown"
            )
        elif self.returncode not in (None, 0) and self.settled_once:
            how = f"was killed by signal {-self.returncode}" if self.returncode < 0 else f"exited with status {self.returncode}"
            notes.append(
                f"the program {how} after it had settled (for example a timeout that expired at once in "
                "virtual time): the capture is what it had created until then"
            )
        vt = self.virtual_time
        if vt is not None and vt.enabled and not vt.horizon_reached and (vt.warp_stalled or vt.warp_budget_exhausted):
            notes.append(_horizon_note(vt, self.polls))
        for node in self:
            if node.uses_sim_time:
                notes.append(
                    f"node {node.fqn} uses sim time (use_sim_time): its ROS clock waits for /clock, which never "
                    "arrives in a capture, so its ROS-time timers never fire"
                )
        notes.extend(self._own_service_notes())
        probe = self.probe
        if probe is not None and probe.state == "skipped":
            notes.append(
                "no thread ever waited in an executor, so the middleware could not ask the nodes' own "
                "services: parameters were not read and lifecycle nodes were not driven"
            )
        for node in self:
            if node.parameters_error:
                notes.append(f"the parameters of node {node.fqn} could not be read ({node.parameters_error}); "
                             "they are not compared")
            if node.lifecycle is not None and node.lifecycle.error:
                notes.append(f"lifecycle: {node.lifecycle.error}")
        return notes

    def _own_service_notes(self) -> list[str]:
        """A client of a service that a node of this same process serves: in a capture nothing is
        delivered, so a program that waits for the answer (to a request to its own node, say)
        waits for ever, and what it would create after the answer is not captured."""
        servers: dict[str, list[str]] = {}
        for e in self.endpoints():
            if e.kind == "service":
                servers.setdefault(e.name, []).append(e.node)
        notes = []
        for e in self.endpoints():
            if e.kind != "client" or e.name not in servers:
                continue
            whose = "its own node" if e.node in servers[e.name] else "node " + ", ".join(sorted(set(servers[e.name])))
            notes.append(
                f"node {e.node} has a client of {e.name}, a service of {whose} in this process: requests to it "
                "are never answered in a capture (nothing is delivered), so a program that waits for the answer "
                "keeps waiting, and what it would create after the answer is not in this capture"
            )
        return notes

    def make_values_portable(self, shares: Mapping[str, str]) -> None:
        """Write every package share directory (``shares``: directory → package) in the nodes'
        parameter values as ``$(find-pkg-share PACKAGE)`` (``model.portable``), so that the
        values are the same on every machine."""
        for node in self.nodes.values():
            if node.parameters:
                node.parameters = [replace(p, value=portable.portable_value(p.value, shares)) for p in node.parameters]

    @property
    def polls(self) -> int:
        """Polls of ``rmw_wait`` (timeout 0: ``spin_some``, ``spin_once(timeout_sec=0)``) the process
        made (``quiescence.polls``; 0 for captures that do not say)."""
        quiescence = self.raw.get("quiescence")
        value = quiescence.get("polls", 0) if isinstance(quiescence, Mapping) else 0
        return value if isinstance(value, int) and not isinstance(value, bool) else 0

    @property
    def not_idle(self) -> str | None:
        """Why the middleware last found the process not provably idle (a thread not blocked,
        and in which system call), or None (``quiescence.not_idle``)."""
        quiescence = self.raw.get("quiescence")
        value = quiescence.get("not_idle") if isinstance(quiescence, Mapping) else None
        return value if isinstance(value, str) and value else None

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
                          with_parameters: bool = True) -> ContractNodes:
        """The ``nodes`` mapping of a contract (sorted; see docs/design.md section 2)."""
        return {
            fqn: self.nodes[fqn].to_contract(with_type_hash=with_type_hash, with_qos=with_qos,
                                             with_parameters=with_parameters)
            for fqn in sorted(self.nodes)
        }

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


# ---------------------------------------------------------------------- parsing


def _require(cond: bool, path: Path | None, reason: str) -> None:
    if not cond:
        raise CaptureFormatError(path, reason)


def _parse(data: Any, *, include_infrastructure: bool, path: Path | None) -> Capture:
    _require(isinstance(data, Mapping), path, "the document is not a JSON object")
    fmt = data.get("format")
    _require(
        fmt == FORMAT,
        path,
        f"`format` is {fmt!r}, expected {FORMAT!r} (is this a file written by rmw_introspect_cpp?)",
    )
    version = data.get("format_version")
    _require(
        version in FORMAT_VERSIONS,
        path,
        f"`format_version` {version!r} is not supported by this pytest-rmw-introspect (reads "
        f"{', '.join(map(str, FORMAT_VERSIONS))}); upgrade the plugin or rebuild the middleware",
    )
    raw_nodes_data = data.get("nodes", [])
    raw_eps_data = data.get("endpoints", [])
    _require(isinstance(raw_nodes_data, list), path, "`nodes` is not a list")
    _require(isinstance(raw_eps_data, list), path, "`endpoints` is not a list")

    raw_nodes: list[RawNode] = []
    for i, n in enumerate(raw_nodes_data):
        where = f"nodes[{i}]"
        _require(isinstance(n, Mapping), path, f"{where} is not an object")
        try:
            name = str(n["name"])
            namespace = str(n.get("namespace", "/"))
            raw_nodes.append(
                RawNode(
                    id=int(n["id"]),
                    seq=int(n.get("seq", 0)),
                    name=name,
                    namespace=namespace,
                    fqn=str(n.get("fqn") or _fqn(namespace, name)),
                    enclave=str(n.get("enclave", "/")),
                    destroyed=bool(n.get("destroyed", False)),
                    in_teardown=bool(n.get("in_teardown", False)),
                    created_virtual_ms=_optional_float(n.get("created_virtual_ms")),
                    created_real_ms=_optional_float(n.get("created_real_ms")),
                    destroyed_virtual_ms=_optional_float(n.get("destroyed_virtual_ms")),
                    destroyed_real_ms=_optional_float(n.get("destroyed_real_ms")),
                    parameters=_node_parameters(n, where, path),
                    parameters_error=_optional_str(n, "parameters_error", where, path),
                    lifecycle=_node_lifecycle(n, where, path),
                )
            )
        except (KeyError, TypeError, ValueError, OverflowError) as exc:
            raise CaptureFormatError(path, f"{where}: missing or malformed field {exc}") from None

    endpoints: list[Endpoint] = []
    for i, e in enumerate(raw_eps_data):
        where = f"endpoints[{i}]"
        _require(isinstance(e, Mapping), path, f"{where} is not an object")
        try:
            kind = str(e["kind"])
            _require(kind in KIND_TO_LIST, path, f"{where}: unknown kind {kind!r}")
            qos = e.get("qos") or {}
            _require(isinstance(qos, Mapping), path, f"{where}: `qos` is not an object")
            if kind in ("publisher", "subscription"):
                qos_module.from_capture(qos)  # ValueError: a QoS value the middleware never writes
            endpoints.append(
                Endpoint(
                    seq=int(e.get("seq", 0)),
                    kind=kind,
                    node_id=int(e["node_id"]),
                    node=str(e.get("node", "")),
                    name=str(e["name"]),
                    type=str(e["type"]),
                    type_hash=e.get("type_hash") or None,
                    qos=dict(qos),
                    typesupport=e.get("typesupport"),
                    destroyed=bool(e.get("destroyed", False)),
                    in_teardown=bool(e.get("in_teardown", False)),
                    created_virtual_ms=_optional_float(e.get("created_virtual_ms")),
                    created_real_ms=_optional_float(e.get("created_real_ms")),
                    destroyed_virtual_ms=_optional_float(e.get("destroyed_virtual_ms")),
                    destroyed_real_ms=_optional_float(e.get("destroyed_real_ms")),
                    created_in=_optional_str(e, "created_in", where, path),
                )
            )
        except (KeyError, TypeError, ValueError, OverflowError) as exc:
            raise CaptureFormatError(path, f"{where}: missing or malformed field {exc}") from None

    argv = data.get("argv") or []
    _require(isinstance(argv, list) and all(isinstance(a, str) for a in argv), path, "`argv` is not a list of strings")
    for key in ("pid", "settle_ms", "time_to_settle_ms", "elapsed_ms", "activity_calls"):
        value = data.get(key)
        _require(value is None or (isinstance(value, (int, float)) and not isinstance(value, bool)), path,
                 f"`{key}` is not a number")
    for key in ("state", "settled_by", "rmw_implementation"):
        _require(data.get(key) is None or isinstance(data.get(key), str), path, f"`{key}` is not a string")
    _require(data.get("ever_waited") is None or isinstance(data.get("ever_waited"), bool), path,
             "`ever_waited` is not true or false")
    try:
        types = type_model.from_capture(data.get("types"))
        probe = parameter_model.probe_from_capture(data.get("probe"))
    except ValueError as exc:
        raise CaptureFormatError(path, str(exc)) from None
    minor = data.get("format_minor", 0)
    _require(isinstance(minor, int) and not isinstance(minor, bool) and minor >= 0, path,
             "`format_minor` is not a non-negative integer")

    capture = Capture(
        nodes=build_view(raw_nodes, endpoints, include_infrastructure=include_infrastructure),
        raw_nodes=raw_nodes,
        raw_endpoints=endpoints,
        state=str(data.get("state", "unknown")),
        format_version=int(version),
        rmw_implementation=data.get("rmw_implementation"),
        pid=data.get("pid"),
        argv=list(argv),
        settle_ms=data.get("settle_ms"),
        time_to_settle_ms=data.get("time_to_settle_ms"),
        elapsed_ms=data.get("elapsed_ms"),
        settled_by=data.get("settled_by"),
        ever_waited=data.get("ever_waited"),
        activity_calls=data.get("activity_calls"),
        virtual_time=_virtual_time(data.get("time"), path),
        ended_before_settle=(data["ended"].get("before_settle") if isinstance(data.get("ended"), Mapping) else None),
        include_infrastructure=include_infrastructure,
        path=path,
        raw=data,
        types=types,
        has_types=data.get("types") is not None,
        format_minor=minor,
        probe=probe,
    )
    return capture


def _node_parameters(n: Mapping[str, Any], where: str, path: Path | None) -> tuple[Parameter, ...] | None:
    try:
        return parameter_model.parameters_from_capture(n.get("parameters"), f"{where}.parameters")
    except ValueError as exc:
        raise CaptureFormatError(path, str(exc)) from None


def _node_lifecycle(n: Mapping[str, Any], where: str, path: Path | None) -> Lifecycle | None:
    try:
        return parameter_model.lifecycle_from_capture(n.get("lifecycle"), f"{where}.lifecycle")
    except ValueError as exc:
        raise CaptureFormatError(path, str(exc)) from None


def _optional_str(record: Mapping[str, Any], key: str, where: str, path: Path | None) -> str | None:
    value = record.get(key)
    _require(value is None or isinstance(value, str), path, f"{where}.{key} is not a string")
    return value


def _destroyed_text(age: float | None) -> str:
    return "" if age is None else f" (destroyed by the program at {age:g} s)"


def _destroyed_at(endpoints: tuple[Endpoint, ...]) -> float | None:
    """When the last of ``endpoints`` was destroyed by the program (None: one lives to the end)."""
    if not endpoints or any(e.destroyed_at is None for e in endpoints):
        return None
    return max(e.destroyed_at for e in endpoints if e.destroyed_at is not None)


def _optional_float(value: Any) -> float | None:
    return None if value is None else float(value)


# A loop that returns from rmw_wait at least this often (on average) polls without pausing; a
# slower one sleeps between its polls (sleep_for(10ms) is 100 a second, a 2 Hz rate 2).
_BUSY_POLLS_PER_SECOND = 500


def _horizon_note(vt: VirtualTime, polls: int) -> str:
    """What a capture says when the warp stopped before the horizon (stalled, or its budget
    spent), and what was seen."""
    where = (f"virtual time stopped at {vt.virtual_elapsed_ms / 1000:.3g} s of the {vt.horizon_ms / 1000:g} s "
             f"horizon after {vt.jumps} jumps")
    later = "; interfaces created later are not in the capture"
    if vt.warp_stalled:
        return f"{where}: the program kept running but never waited with a timeout: {_stalled_loop(vt, polls)}" + later
    if vt.jumps >= 1000:
        why = "each jump is one period of a very fast timer"
    elif polls:
        why = (f"the program kept running between its waits: {polls} returns from rmw_wait without waiting (polls, "
               "or a spin_once loop running a task that awaits an answer that never comes)")
    else:
        why = "the program kept running between its waits (a loop that sleeps or polls besides its timers)"
    return f"{where}: the warp used its real-time budget ({why})" + later


def _stalled_loop(vt: VirtualTime, polls: int) -> str:
    """Which loop kept a stalled warp from advancing, from what the middleware counted in it."""
    sleeps = "sleep_for, time.sleep, a WallRate or Rate loop"
    if vt.warp_polls is None or vt.warp_real_ms is None:  # a capture that does not say
        polled = (f" ({polls} zero-timeout polls of its executor, or waits that returned at once on a guard "
                  "condition it had just triggered itself)" if polls else "")
        return (f"it polls{polled} (spin_some, spin_once(timeout_sec=0)), spins a task that awaits an answer that "
                f"never comes (spin_once with a pending call_async), or sleeps on its own clock ({sleeps}), which "
                "virtual time cannot advance")
    seconds = vt.warp_real_ms / 1000
    if vt.warp_polls == 0:
        return (f"in {seconds:.2g} s it made {vt.warp_activity or 0} calls into ROS (publish, take, graph queries) "
                f"and never waited in an executor: a loop that sleeps on its own clock ({sleeps}) without spinning, "
                "which virtual time cannot advance")
    rate = vt.warp_polls / seconds if seconds > 0 else float("inf")
    counted = (f"{vt.warp_polls} zero-timeout poll{'s' if vt.warp_polls != 1 else ''} of its executor in "
               f"{seconds:.2g} s (or waits that returned at once on a guard condition it had just triggered itself)")
    if rate >= _BUSY_POLLS_PER_SECOND:
        return (f"{counted}, without pausing: a busy loop at full CPU that polls its executor (spin_some or "
                "spin_once(timeout_sec=0) until something is done) or spins a task that awaits an answer that "
                "never comes (spin_once with a pending call_async); in a capture no answer or message arrives, so "
                "it never ends, and it has no deadline virtual time could jump to")
    return (f"{counted}, one every {1000 / rate:.3g} ms: between its polls it sleeps on the real clock ({sleeps}), "
            "which virtual time does not advance")


def _virtual_time(data: Any, path: Path | None) -> VirtualTime | None:
    if data is None:
        return None
    _require(isinstance(data, Mapping), path, "`time` is not an object")
    try:
        return VirtualTime(
            horizon_ms=float(data.get("horizon_ms", 0)),
            virtual_elapsed_ms=float(data.get("virtual_elapsed_ms", 0)),
            real_elapsed_ms=float(data.get("real_elapsed_ms", 0)),
            jumps=int(data.get("jumps", 0)),
            warp_ms=float(data.get("warp_ms", 0)),
            horizon_reached=bool(data.get("horizon_reached", False)),
            warp_budget_exhausted=bool(data.get("warp_budget_exhausted", False)),
            warp_stalled=bool(data.get("warp_stalled", False)),
            warp_real_ms=_optional_float(data.get("warp_real_ms")),
            warp_polls=None if data.get("warp_polls") is None else int(data["warp_polls"]),
            warp_activity=None if data.get("warp_activity") is None else int(data["warp_activity"]),
        )
    except (TypeError, ValueError, OverflowError) as exc:
        raise CaptureFormatError(path, f"`time`: malformed field ({exc})") from None


def _fqn(namespace: str, name: str) -> str:
    return ("/" if namespace in ("", "/") else namespace.rstrip("/") + "/") + name


def is_infrastructure(endpoint: Endpoint, node_fqn: str) -> bool:
    """Whether ``endpoint`` of the node ``node_fqn`` is one the ROS client library adds by itself."""
    name, kind = endpoint.name, endpoint.kind
    rosout, parameter_events = INFRASTRUCTURE_TOPICS
    if name == rosout and kind == "publisher":
        return True
    if name == parameter_events and kind in ("publisher", "subscription"):
        return True
    prefix = node_fqn.rstrip("/") + "/"
    if not name.startswith(prefix):
        return False
    leaf = name[len(prefix):]
    if kind == "service" and (leaf in PARAMETER_SERVICES or leaf in LIFECYCLE_SERVICES or leaf in LOGGER_SERVICES):
        return True
    return kind == "publisher" and leaf in LIFECYCLE_TOPICS


def _action_part(name: str) -> tuple[str, str] | None:
    """``/fib/_action/send_goal`` → (``/fib``, ``send_goal``)."""
    base, sep, part = name.rpartition("/_action/")
    if not sep or not base or part not in ACTION_SERVICES + ACTION_TOPICS:
        return None
    return base, part


def _action_type(part: str, type_name: str) -> str | None:
    suffix = {"send_goal": "_SendGoal", "get_result": "_GetResult", "feedback": "_FeedbackMessage"}.get(part)
    if suffix and type_name.endswith(suffix):
        return type_name[: -len(suffix)]
    return None


def _group_actions(eps: list[Endpoint], server: bool) -> tuple[list[Interface], list[Endpoint]]:
    """Group the action endpoints of one node; return (actions, remaining endpoints)."""
    service_kind, topic_kind = ("service", "publisher") if server else ("client", "subscription")
    parts: dict[str, dict[str, Endpoint]] = {}
    for e in eps:
        found = _action_part(e.name)
        if found is None:
            continue
        base, part = found
        expected_kind = service_kind if part in ACTION_SERVICES else topic_kind
        if e.kind != expected_kind:
            continue
        parts.setdefault(base, {}).setdefault(part, e)

    actions: list[Interface] = []
    used: set[int] = set()
    for base, found_parts in parts.items():
        # an action needs at least its goal or result service (which carry the action type)
        action_type = None
        for part in ("send_goal", "get_result", "feedback"):
            if part in found_parts:
                action_type = _action_type(part, found_parts[part].type)
                if action_type:
                    break
        if action_type is None or not ({"send_goal", "get_result"} & set(found_parts)):
            continue
        hashes: dict[str, str] = {}
        for part in ACTION_HASHED_PARTS:
            part_hash = found_parts[part].type_hash if part in found_parts else None
            if part_hash:
                hashes[part] = part_hash
        members = tuple(found_parts[p] for p in ACTION_SERVICES + ACTION_TOPICS if p in found_parts)
        used.update(id(m) for m in members)
        actions.append(Interface(name=base, type=action_type, type_hash=hashes or None, qos=None, endpoints=members))
    remaining = [e for e in eps if id(e) not in used]
    return actions, remaining


def _add_parameters(node: Node, raw_node: RawNode, include_infrastructure: bool) -> None:
    """The parameters of ``raw_node`` into ``node`` (two raw nodes of one name: the union, the
    first one's entry winning), sorted by name."""
    if raw_node.parameters is None:
        if raw_node.parameters_error and not node.parameters_error:
            node.parameters_error = raw_node.parameters_error
        return
    have = {p.name for p in node.parameters or ()}
    wanted = [p for p in raw_node.parameters
              if (include_infrastructure or not p.infrastructure) and p.name not in have]
    node.parameters = sorted([*(node.parameters or ()), *wanted], key=lambda p: p.name)


def _contract_qos(raw: Mapping[str, Any]) -> QosFields:
    return qos_module.from_capture(raw)


def build_view(
    raw_nodes: list[RawNode],
    endpoints: list[Endpoint],
    *,
    include_infrastructure: bool = False,
) -> dict[str, Node]:
    """The contract view: the nodes alive at the end or destroyed by the program
    (``RawNode.in_view``), by fully qualified name, with their grouped interfaces."""
    live_nodes = [n for n in raw_nodes if n.in_view]
    by_id = {n.id: n for n in live_nodes}
    nodes: dict[str, Node] = {}
    for n in sorted(live_nodes, key=lambda n: n.seq):
        node = nodes.get(n.fqn)
        if node is None:
            node = nodes[n.fqn] = Node(fqn=n.fqn, name=n.name, namespace=n.namespace, raw=(n,))
        else:  # two nodes of the same name in one process: one contract entry
            node.raw = node.raw + (n,)
        _add_parameters(node, n, include_infrastructure)
        if n.lifecycle is not None and node.lifecycle is None:
            node.lifecycle = n.lifecycle

    per_node: dict[str, list[Endpoint]] = {fqn: [] for fqn in nodes}
    for e in sorted(endpoints, key=lambda e: e.seq):
        owner = by_id.get(e.node_id)
        if owner is None:
            continue  # endpoint of a destroyed (or unknown) node
        node = nodes[owner.fqn]
        node.endpoints = node.endpoints + (e,)
        if not e.in_view:
            continue
        if not include_infrastructure and is_infrastructure(e, owner.fqn):
            continue
        per_node[owner.fqn].append(e)

    for fqn, eps in per_node.items():
        node = nodes[fqn]
        node.action_servers, eps = _group_actions(eps, server=True)
        node.action_clients, eps = _group_actions(eps, server=False)
        seen: dict[tuple[str, str], int] = {}
        for e in eps:
            list_name = KIND_TO_LIST[e.kind]
            key = (list_name, e.name)
            target_list: list[Interface] = getattr(node, list_name)
            if key in seen:
                # the same name twice in one list (e.g. two publishers on one topic): one
                # contract entry; the raw endpoints stay reachable through it
                idx = seen[key]
                first = target_list[idx]
                target_list[idx] = Interface(first.name, first.type, first.type_hash, first.qos, first.endpoints + (e,))
                continue
            is_topic = e.kind in ("publisher", "subscription")
            seen[key] = len(target_list)
            target_list.append(
                Interface(
                    name=e.name,
                    type=e.type,
                    type_hash=e.type_hash,
                    qos=_contract_qos(e.qos) if is_topic else None,
                    endpoints=(e,),
                )
            )
        for list_name in LISTS:
            getattr(node, list_name).sort(key=lambda i: i.name)
    return nodes
