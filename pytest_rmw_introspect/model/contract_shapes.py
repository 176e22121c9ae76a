"""The shapes of a contract's mappings, as types: a node, an interface entry, a QoS, a
parameter entry, the ``options:`` and ``target:`` blocks, a system contract's ``launch:`` block
and process entry; and :func:`empty_node`.

These are what the JSON Schema (``schema/contract.schema.json``, and ``model.system_contract``'s
schema built from it) has accepted, so they are used only where a mapping has been validated or
built by the package itself: YAML just read stays ``Mapping[str, Any]`` until the schema has
passed it. Keys a contract may leave out are ``NotRequired`` (``total=False``). Typing only: at
run time each is a plain ``dict``.

The ``options:`` and ``target:`` keys are those of ``model.option_tables`` (a unit test checks
that both agree); what each value means is decided where it is used (``compare.options``,
``run.target``).
"""

# No ``from __future__ import annotations`` here: TypedDict reads ``Required`` from evaluated
# annotations, and the tests compare the required keys with the schema's.
from collections.abc import Mapping, Sequence
from typing import Literal, Required, TypedDict, Union

from .vocabulary import LISTS

#: A parameter value in a contract: a scalar, a list of scalars (byte_array: integers), or None
#: (declared with a type only).
ParameterValue = Union[bool, int, float, str, list[bool], list[int], list[float], list[str], None]


class QosFields(TypedDict, total=False):
    """A QoS written as fields (NoDL v2 spellings), optionally on top of a named ``profile``;
    a field left out has the profile's value (``model.qos``). ``qos.expand`` gives the explicit
    form: every field but ``profile``, canonical (two QoS mean the same exactly when their
    explicit forms are equal)."""

    profile: str
    history: str
    depth: int
    reliability: str
    durability: str
    liveliness: str
    deadline_ns: int
    lifespan_ns: int
    liveliness_lease_duration_ns: int
    avoid_ros_namespace_conventions: bool


#: A topic's ``qos:`` in a contract: a profile name or fields (every field after
#: ``Contract.expanded_nodes``).
ContractQos = Union[str, QosFields]


class ActionTypeHash(TypedDict, total=False):
    """An action's ``type_hash``: one hash per definition-dependent part."""

    send_goal: str
    get_result: str
    feedback: str


class InterfaceEntry(TypedDict, total=False):
    """One entry of a node's six lists. ``qos`` only for topics; ``type_hash`` a string, or
    :class:`ActionTypeHash` for an action; ``destroyed_at`` only for an entry the program
    destroyed while it ran."""

    name: Required[str]
    type: Required[str]
    type_hash: str | ActionTypeHash
    qos: ContractQos
    destroyed_at: float


class RangeEntry(TypedDict):
    """A parameter's ``integer_range`` or ``floating_point_range``."""

    from_value: int | float
    to_value: int | float
    step: int | float


class ParameterEntry(TypedDict, total=False):
    """One entry of a node's ``parameters`` (``model.parameters``; ``type`` None: neither a
    value nor a declared type)."""

    name: Required[str]
    type: Required[str | None]
    default_value: ParameterValue
    read_only: bool
    dynamic_typing: bool
    description: str
    additional_constraints: str
    integer_range: RangeEntry
    floating_point_range: RangeEntry
    declared_in: str


class ContractNode(TypedDict, total=False):
    """One node of a contract's ``nodes:``. As loaded (``model.contract.normalize_nodes``) it
    has the six lists always; ``parameters`` left out are not compared; ``lifecycle`` only for a
    managed node, ``destroyed_at`` only for a node the program destroyed, ``unstable_name`` (why
    its name changes every run) only for a node keyed by a pattern (``model.unstable_names``)."""

    unstable_name: str
    lifecycle: str
    destroyed_at: float
    publishers: list[InterfaceEntry]
    subscriptions: list[InterfaceEntry]
    service_servers: list[InterfaceEntry]
    service_clients: list[InterfaceEntry]
    action_servers: list[InterfaceEntry]
    action_clients: list[InterfaceEntry]
    parameters: list[ParameterEntry]


#: A contract's ``nodes:``: fully qualified node name → node.
ContractNodes = dict[str, ContractNode]


def empty_node() -> ContractNode:
    """A node with the six lists, all empty (what ``contract.normalize_nodes`` makes of ``/n: null``)."""
    node = ContractNode()
    for list_name in LISTS:
        node[list_name] = []
    return node


class ContractOptions(TypedDict, total=False):
    """A contract's ``options:`` block (``option_tables.COMPARISON``; ``system_fail_on`` in a
    system contract only)."""

    ignore_type_hash: bool
    ignore_qos: bool | list[str]
    allow_extra: bool
    include_infrastructure: bool
    fail_on: str
    include_types: bool
    ignore_parameters: bool | list[str]
    ignore_parameter_values: bool | list[str]
    rules: Mapping[str, str]  # issue 49: rule id or fnmatch pattern → off | note | safe | risky | breaking
    system_fail_on: str


class TargetBlock(TypedDict, total=False):
    """A contract's ``target:`` block (``option_tables.TARGET``): what to run and how. (Its
    containers are read-only types, so that a ``list[str]`` or ``dict[str, str]`` fits.)"""

    package: str
    executable: str
    command: str | Sequence[str | int | float]
    script: str
    module: str
    entry_point: str
    arguments: Sequence[str | int | float]
    namespace: str
    node_name: str
    remappings: Mapping[str, str] | Sequence[str]
    parameters: Mapping[str, object]
    params_file: str
    env: Mapping[str, str | int | float | bool]
    cwd: str
    settle: float
    timeout: float
    horizon: float
    cold_start: bool
    lifecycle: Literal["active", "inactive", "unconfigured", "none"]
    read_parameters: bool
    stimuli: Sequence[str] | str


class LaunchBlock(TypedDict, total=False):
    """A system contract's ``launch:`` block: the launch file that starts the system."""

    package: str
    file: str
    path: str
    arguments: Mapping[str, str | int | float | bool]
    allow_unsupported: bool


class StandInEntry(TypedDict, total=False):
    """One entry of a system contract's ``stand_ins:``: a launched process (``executable``, and
    ``package``, ``name`` to tell it apart) not run where the system is checked, and the node
    contract or NoDL document (``contract``) its interfaces come from instead."""

    package: str | None
    executable: Required[str]
    name: str | None
    contract: Required[str]
    reason: str


class ProcessEntry(TypedDict, total=False):
    """One process of a system contract's ``processes:``, in launch order: what ran
    (``package`` None or left out: a bare executable), the node name the launch file gives
    (None or left out: the program's own) and the nodes it created."""

    package: str | None
    executable: Required[str]
    name: str | None
    nodes: Required[list[str]]
