"""The contract view of a capture: its nodes with their interfaces, as a contract lists them.

:func:`build_view` turns the raw records of a capture file (``model.capture_file``) into a
mapping of each node's fully qualified name to a :class:`Node` with six lists of
:class:`Interface` (publishers, subscriptions, service servers, service clients, action
servers, action clients), where

* actions are grouped from their ``<a>/_action/...`` services and topics,
* infrastructure endpoints (``/rosout``, ``/parameter_events``, parameter services,
  ``get_type_description``, lifecycle services and ``transition_event``) are left out unless
  ``include_infrastructure=True`` (:func:`is_infrastructure`),
* nodes and endpoints the program itself destroyed while it ran are kept, with their virtual
  age at destruction (``destroyed_at``, seconds: they belong to the interface the program
  offered until then); those destroyed in the run of destructions that ended the program
  (``in_teardown``) count as alive until its own final teardown; captures older than
  ``format_minor`` 4 do not say when an entity was destroyed, so their destroyed entities are
  left out (they stay in the capture's ``raw_*``),
* hidden names (a segment starting with ``_``) are kept,

and each node has its ``parameters`` (as its own parameter services answered the middleware;
the ones the client library declares by itself, ``use_sim_time`` and the like, left out unless
``include_infrastructure``; None when they were not read) and, for a lifecycle node, its
``lifecycle`` record (how the middleware drove it and the state it reached).
``Node.to_contract`` gives a node's entry of a contract's ``nodes`` mapping (docs/design.md
section 2).
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any, cast

from . import qos as qos_module
from .capture_file import Endpoint, RawNode
from .contract_shapes import ActionTypeHash, ContractNode, InterfaceEntry, QosFields
from .parameters import Lifecycle, Parameter
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
    TOPIC_KINDS,
)

SIM_CLOCK_TYPE = "rosgraph_msgs/msg/Clock"


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


def _destroyed_at(endpoints: tuple[Endpoint, ...]) -> float | None:
    """When the last of ``endpoints`` was destroyed by the program (None: one lives to the end)."""
    if not endpoints or any(e.destroyed_at is None for e in endpoints):
        return None
    return max(e.destroyed_at for e in endpoints if e.destroyed_at is not None)


def is_infrastructure(endpoint: Endpoint, node_fqn: str) -> bool:
    """Whether ``endpoint`` of the node ``node_fqn`` is one the ROS client library adds by itself."""
    name, kind = endpoint.name, endpoint.kind
    rosout, parameter_events = INFRASTRUCTURE_TOPICS
    if name == rosout and kind == "publisher":
        return True
    if name == parameter_events and kind in TOPIC_KINDS:
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


def _service_qos(endpoint: Endpoint) -> QosFields | None:
    """A service server's or client's QoS where it matters (``qos.service_from_capture``); None
    for anything else, or a QoS the rules cannot read."""
    if endpoint.kind not in ("service", "client"):
        return None
    try:
        return qos_module.service_from_capture(endpoint.qos)
    except ValueError:
        return None


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
            is_topic = e.kind in TOPIC_KINDS
            seen[key] = len(target_list)
            target_list.append(
                Interface(
                    name=e.name,
                    type=e.type,
                    type_hash=e.type_hash,
                    qos=_contract_qos(e.qos) if is_topic else _service_qos(e),
                    endpoints=(e,),
                )
            )
        for list_name in LISTS:
            getattr(node, list_name).sort(key=lambda i: i.name)
    return nodes
