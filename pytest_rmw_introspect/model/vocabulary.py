"""The words every layer shares, defined once: interface lists, their labels, action parts,
what the client libraries add by themselves (infrastructure endpoints and parameters),
parameter types and lifecycle states, severities and the ``fail_on`` thresholds.

A node's interface is six lists (the NoDL v2 names) plus its parameters and, for a managed
node, the lifecycle state it is described in. The middleware records four raw endpoint kinds;
actions are grouped from their services and topics. Drift and compatibility checks rate what they find
with a :class:`Severity`; ``fail_on`` names the least severe one that fails.
"""

from __future__ import annotations

import enum
from typing import Final, Literal, get_args

from ..errors import OptionError

#: The name of one of a node's six interface lists (a key of a contract node), in contract order.
ListName = Literal["publishers", "subscriptions", "service_servers", "service_clients", "action_servers",
                   "action_clients"]

#: The six interface lists of a node, in contract order.
LISTS: tuple[ListName, ...] = get_args(ListName)
TOPIC_LISTS: tuple[ListName, ...] = ("publishers", "subscriptions")
SERVICE_LISTS: tuple[ListName, ...] = ("service_servers", "service_clients")
ACTION_LISTS: tuple[ListName, ...] = ("action_servers", "action_clients")
#: Lists whose peers depend on them (they offer something). The others request.
OFFERING_LISTS: frozenset[ListName] = frozenset({"publishers", "service_servers", "action_servers"})
#: Requesting list → the list that provides to it.
PROVIDER_OF: dict[str, ListName] = {
    "subscriptions": "publishers",
    "service_clients": "service_servers",
    "action_clients": "action_servers",
}

#: A node's parameters in a contract (beside the six lists; drift items of kind ``parameters``).
PARAMETERS: Final = "parameters"
#: A managed node's lifecycle state in a contract (a key of the node, drift of kind ``node``).
LIFECYCLE: Final = "lifecycle"
#: When the program itself destroyed a node or an interface, in seconds of its virtual age (a key
#: of a node and of an interface entry; absent: alive to the end). See docs/design.md section 2.
DESTROYED_AT: Final = "destroyed_at"
#: Two ``destroyed_at`` ages this close (seconds) are the same destruction: a virtual age includes
#: the real time the program ran before and between its waits (start-up: warm or cold), which
#: differs a little from run to run.
DESTROYED_AT_TOLERANCE_S = 0.5

#: Singular words for people, per list (and ``node`` for drift of a whole node).
LABELS: dict[str, str] = {
    "node": "node",
    PARAMETERS: "parameter",
    "publishers": "publisher",
    "subscriptions": "subscription",
    "service_servers": "service server",
    "service_clients": "service client",
    "action_servers": "action server",
    "action_clients": "action client",
}

#: Raw endpoint kind (as the middleware records it) → interface list.
KIND_TO_LIST: dict[str, ListName] = {
    "publisher": "publishers",
    "subscription": "subscriptions",
    "service": "service_servers",
    "client": "service_clients",
}

#: Raw endpoint kinds (as the middleware records them) of a topic's ends.
TOPIC_KINDS: tuple[str, ...] = ("publisher", "subscription")

#: The services and topics an action is made of (``/fib/_action/send_goal``, ...).
ACTION_SERVICES: tuple[str, ...] = ("send_goal", "cancel_goal", "get_result")
ACTION_TOPICS: tuple[str, ...] = ("feedback", "status")
#: The parts whose type depends on the action definition: the keys of an action's type_hash,
#: each with the word people use for it.
ACTION_HASHED_PARTS: dict[str, str] = {
    "send_goal": "goal",
    "get_result": "result",
    "feedback": "feedback",
}


# ---------------------------------------------------------------------- infrastructure
# What rcl, rclpy and rclcpp create by themselves in every node: left out of contracts unless
# ``include_infrastructure`` (model/capture.py filters with these).

#: Topics every node uses: ``/rosout`` (its log publisher), ``/parameter_events``.
INFRASTRUCTURE_TOPICS: tuple[str, ...] = ("/rosout", "/parameter_events")
#: ``<node>/<service>``: the parameter services and (Jazzy) the type description service, each
#: with its type. Every node serves them: the system rules take them as present for every node.
PARAMETER_SERVICE_TYPES: dict[str, str] = {
    "describe_parameters": "rcl_interfaces/srv/DescribeParameters",
    "get_parameter_types": "rcl_interfaces/srv/GetParameterTypes",
    "get_parameters": "rcl_interfaces/srv/GetParameters",
    "list_parameters": "rcl_interfaces/srv/ListParameters",
    "set_parameters": "rcl_interfaces/srv/SetParameters",
    "set_parameters_atomically": "rcl_interfaces/srv/SetParametersAtomically",
    "get_type_description": "type_description_interfaces/srv/GetTypeDescription",
}
PARAMETER_SERVICES: tuple[str, ...] = tuple(PARAMETER_SERVICE_TYPES)
#: ``<node>/<service>`` and ``<node>/<topic>`` of a lifecycle (managed) node, each with its type.
LIFECYCLE_SERVICE_TYPES: dict[str, str] = {
    "change_state": "lifecycle_msgs/srv/ChangeState",
    "get_state": "lifecycle_msgs/srv/GetState",
    "get_available_states": "lifecycle_msgs/srv/GetAvailableStates",
    "get_available_transitions": "lifecycle_msgs/srv/GetAvailableTransitions",
    "get_transition_graph": "lifecycle_msgs/srv/GetAvailableTransitions",
}
LIFECYCLE_SERVICES: tuple[str, ...] = tuple(LIFECYCLE_SERVICE_TYPES)
LIFECYCLE_TOPIC_TYPES: dict[str, str] = {"transition_event": "lifecycle_msgs/msg/TransitionEvent"}
LIFECYCLE_TOPICS: tuple[str, ...] = tuple(LIFECYCLE_TOPIC_TYPES)
#: per-node services of enable_logger_service (rclcpp NodeOptions, rclpy Node(enable_logger_service=True))
LOGGER_SERVICES: tuple[str, ...] = ("get_logger_levels", "set_logger_levels")
#: Parameters the client libraries declare in every node (rclpy and rclcpp: ``use_sim_time``,
#: ``start_type_description_service``).
INFRASTRUCTURE_PARAMETERS: frozenset[str] = frozenset({"use_sim_time", "start_type_description_service"})
#: rclcpp's QoS overrides of the infrastructure topics (and of ``/clock``, which its time source
#: subscribes to with ``use_sim_time``): ``qos_overrides./parameter_events.publisher.depth``, ...
#: A node's ``qos_overrides.*`` parameters of its own topics are part of its interface.
INFRASTRUCTURE_PARAMETER_PREFIXES: tuple[str, ...] = tuple(
    f"qos_overrides.{topic}." for topic in (*INFRASTRUCTURE_TOPICS, "/clock"))


def is_infrastructure_parameter(name: str) -> bool:
    """Whether the parameter ``name`` is one the client library declares by itself."""
    return name in INFRASTRUCTURE_PARAMETERS or name.startswith(INFRASTRUCTURE_PARAMETER_PREFIXES)


# ---------------------------------------------------------------------- parameters and lifecycle

#: Parameter types, NoDL spellings (rcl_interfaces ParameterType without the PARAMETER_ prefix).
PARAMETER_TYPES: tuple[str, ...] = (
    "bool",
    "integer",
    "double",
    "string",
    "byte_array",
    "bool_array",
    "integer_array",
    "double_array",
    "string_array",
)
#: The primary lifecycle states (``lifecycle_msgs/msg/State`` labels), in the order a node is
#: brought up; ``unknown``: a managed node whose state was not read (target ``lifecycle: none``).
LIFECYCLE_STATES: tuple[str, ...] = ("unconfigured", "inactive", "active", "finalized")
LIFECYCLE_UNKNOWN = "unknown"
#: The target option ``lifecycle``: how far the middleware drives managed nodes (``none``: it
#: leaves them alone). The default is ``active``.
LIFECYCLE_TARGETS: tuple[str, ...] = ("active", "inactive", "unconfigured", "none")
DEFAULT_LIFECYCLE_TARGET = "active"
#: The transitions the middleware drives, in order, each with the state it starts from; a
#: parameter's ``declared_in`` is one of them.
TRANSITION_FROM_STATE: dict[str, str] = {"configure": "unconfigured", "activate": "inactive"}
LIFECYCLE_TRANSITIONS: tuple[str, ...] = tuple(TRANSITION_FROM_STATE)


class Severity(enum.IntEnum):
    """How much a change or a mismatch can hurt the node's peers. ``NOTE`` is below every
    ``fail_on`` threshold: shown in every report, never failing, never drift a golden update
    must accept (a dead remapping, a file of the robot the capture machine lacks)."""

    NOTE = -1
    SAFE = 0
    RISKY = 1
    BREAKING = 2


#: ``fail_on`` words (contract options, ini, command lines) → the least severity that fails.
THRESHOLDS: dict[str, Severity] = {
    "any": Severity.SAFE,
    "risky": Severity.RISKY,
    "breaking": Severity.BREAKING,
}
FAIL_ON: tuple[str, ...] = tuple(THRESHOLDS)
#: the levels the option ``rules`` gives a rule (``compare.rule_levels``): ``off`` drops its findings
RULE_LEVELS: tuple[str, ...] = ("off", "note", "safe", "risky", "breaking")
THRESHOLD_WORDS: dict[Severity, str] = {severity: word for word, severity in THRESHOLDS.items()}


def parse_threshold(text: str) -> Severity:
    """'any' | 'risky' | 'breaking' (any case) → Severity; OptionError otherwise."""
    if isinstance(text, str) and text.strip().lower() in THRESHOLDS:
        return THRESHOLDS[text.strip().lower()]
    raise OptionError(f"invalid fail threshold {text!r}: expected one of {', '.join(THRESHOLDS)}")
