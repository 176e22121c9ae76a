"""A node's parameters and lifecycle state: the capture's records and the contract's entries.

After the first settle the middleware asks every node's own parameter services (and drives
lifecycle nodes; rmw_introspect_cpp/README.md, "Parameters and lifecycle"). A capture node then
has ``parameters`` (``[{name, type, value, read_only, dynamic_typing, description,
additional_constraints, integer_range, floating_point_range, declared_in}]`` or null),
``parameters_error`` and ``lifecycle`` (``{target, initial_state, state, transitions, error}``
or null); :func:`parameters_from_capture` and :func:`lifecycle_from_capture` read them into
:class:`Parameter` and :class:`Lifecycle` (``ValueError`` naming the field for anything the
middleware never writes).

In a contract (docs/design.md section 2) a node has ``parameters:``, a list of entries::

    - name: depth                  # required
      type: integer                # required: bool, integer, double, string, byte_array,
                                   #   bool_array, integer_array, double_array, string_array
      default_value: 5             # the value the node starts with under the contract's target
      read_only: true              # written when true
      dynamic_typing: true         # written when true
      description: queue depth     # written when not empty
      additional_constraints: ...  # written when not empty
      integer_range: {from_value: 1, to_value: 10, step: 1}      # written when set
      floating_point_range: {from_value: 0.0, to_value: 1.0, step: 0.0}
      declared_in: configure       # written when the node declared it in a transition

and ``lifecycle:`` (a managed node only), the state the contract describes it in: one of
:data:`~.vocabulary.LIFECYCLE_STATES`, or ``unknown`` (captured with ``lifecycle: none``).
:func:`check_contract_parameters` validates entries beyond the JSON Schema (the value fits
the type, names are unique); :func:`normalize_value` gives the one form both sides are compared
in (doubles as floats, NaN and infinities as floats).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal, get_args

from ..errors import EntryProblem
from . import untrusted
from .contract_shapes import ParameterEntry, RangeEntry
from .vocabulary import LIFECYCLE_TARGETS, PARAMETER_TYPES, is_infrastructure_parameter

#: keys of a contract parameter entry, in the order they are written
ENTRY_KEYS: tuple[str, ...] = (
    "name",
    "type",
    "default_value",
    "read_only",
    "dynamic_typing",
    "description",
    "additional_constraints",
    "integer_range",
    "floating_point_range",
    "declared_in",
)
RangeField = Literal["from_value", "to_value", "step"]
RANGE_KEYS: tuple[RangeField, ...] = get_args(RangeField)
#: the keys of a parameter entry that hold a range
RangeKey = Literal["integer_range", "floating_point_range"]
#: what the capture writes for the doubles JSON cannot hold
_SPECIAL_DOUBLES = {"nan": math.nan, "inf": math.inf, "-inf": -math.inf}


# ---------------------------------------------------------------------- values


def flatten(value: Any, prefix: str = "") -> dict[str, Any]:
    """A nested parameter mapping as ROS names its parameters, dotted (``{a: {b: 1}}`` is
    ``{"a.b": 1}``); a value that is not a mapping gives nothing."""
    out: dict[str, Any] = {}
    if isinstance(value, Mapping):
        for key, inner in value.items():
            if isinstance(inner, Mapping):
                out.update(flatten(inner, f"{prefix}{key}."))
            else:
                out[f"{prefix}{key}"] = inner
    return out


def _is_int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _double(value: Any, where: str) -> float:
    if isinstance(value, str) and value in _SPECIAL_DOUBLES:
        return _SPECIAL_DOUBLES[value]
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return float(value)
    raise ValueError(f"{where}: {untrusted.shorten(value)} is not a double")


def normalize_value(type_name: str | None, value: Any, where: str = "value") -> Any:
    """``value`` checked against ``type_name`` and in the form both sides are compared in:
    doubles as ``float`` (``"nan"``, ``"inf"``, ``"-inf"``, and integers written for a double,
    become floats), arrays as lists. ``None`` (no value) stays ``None``. Raises ValueError
    naming ``where`` when the value does not fit the type."""
    if value is None:
        return None
    if type_name is None:
        raise ValueError(f"{where}: a parameter without a type has no value, got {untrusted.shorten(value)}")
    if type_name == "bool":
        if isinstance(value, bool):
            return value
    elif type_name == "integer":
        if _is_int(value):
            return value
    elif type_name == "double":
        return _double(value, where)
    elif type_name == "string":
        if isinstance(value, str):
            return value
    elif type_name.endswith("_array"):
        if not isinstance(value, (list, tuple)):
            raise ValueError(f"{where}: {type_name} value {untrusted.shorten(value)} is not a list")
        element = type_name[: -len("_array")]
        if element == "byte":
            if all(_is_int(v) and 0 <= v <= 255 for v in value):
                return list(value)
            raise ValueError(f"{where}: a byte_array holds integers from 0 to 255, got {untrusted.shorten(list(value))}")
        return [normalize_value(element, v, f"{where}[{i}]") for i, v in enumerate(value)]
    else:
        raise ValueError(f"{where}: unknown parameter type {type_name!r}; known: {', '.join(PARAMETER_TYPES)}")
    raise ValueError(f"{where}: {untrusted.shorten(value)} is not {'an' if type_name == 'integer' else 'a'} {type_name}")


def same_value(a: Any, b: Any) -> bool:
    """Equality of normalized values, with NaN equal to NaN and ``1 == 1.0`` kept apart from
    ``True == 1`` (a bool is never a number here)."""
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(same_value(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, bool) or isinstance(b, bool):
        return isinstance(a, bool) and isinstance(b, bool) and a == b
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    return bool(a == b)


def format_value(value: Any) -> str:
    """A value for people: YAML-like (``true``, ``1.5``, ``'text'``, ``[1, 2]``, ``.nan``, none)."""
    if value is None:
        return "(no value)"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        if math.isnan(value):
            return ".nan"
        if math.isinf(value):
            return ".inf" if value > 0 else "-.inf"
        return repr(value)
    if isinstance(value, str):
        return untrusted.shorten_with_digest(value)  # a megabyte value stays a short line
    if isinstance(value, list):
        shown = ", ".join(format_value(v) for v in value[:8])
        if len(shown) > 120:  # long items: the list as a whole, cut with its digest
            return untrusted.shorten_with_digest(value)
        return f"[{shown}{', ...' if len(value) > 8 else ''}]"
    text = str(value)
    return text if len(text) <= 80 else untrusted.shorten_with_digest(value)


# ---------------------------------------------------------------------- records


@dataclass(frozen=True)
class ParameterRange:
    """An ``integer_range`` or ``floating_point_range`` of a parameter descriptor (rcl_interfaces
    ``IntegerRange`` / ``FloatingPointRange``): values from ``from_value`` to ``to_value``, in
    steps of ``step`` from ``from_value`` (0: any value; both bounds are always valid)."""

    from_value: int | float
    to_value: int | float
    step: int | float

    def to_contract(self) -> RangeEntry:
        return {"from_value": self.from_value, "to_value": self.to_value, "step": self.step}

    def describe(self) -> str:
        step = f" step {format_value(self.step)}" if self.step else ""
        return f"[{format_value(self.from_value)}, {format_value(self.to_value)}]{step}"


@dataclass(frozen=True)
class Parameter:
    """One parameter of a node as its own services answered (``describe_parameters`` and
    ``get_parameters``). ``type`` is the NoDL spelling (None: neither a value nor a declared
    type); ``value`` the value when read (overrides from ``--ros-args -p`` and parameter files
    applied; None: declared with a type only), doubles as floats, arrays as lists;
    ``declared_in``: None when it was there at the first read, else the lifecycle transition
    after which it appeared (``configure``)."""

    name: str
    type: str | None
    value: Any = None
    read_only: bool = False
    dynamic_typing: bool = False
    description: str = ""
    additional_constraints: str = ""
    integer_range: ParameterRange | None = None
    floating_point_range: ParameterRange | None = None
    declared_in: str | None = None

    @property
    def infrastructure(self) -> bool:
        """Declared by the client library itself (``use_sim_time``, ...: vocabulary)."""
        return is_infrastructure_parameter(self.name)

    def to_contract(self, *, with_value: bool = True) -> ParameterEntry:
        """The contract entry: ``name``, ``type``, ``default_value`` (unless ``with_value`` is
        False), and the descriptor's fields that differ from their defaults."""
        entry: ParameterEntry = {"name": self.name, "type": self.type}
        if with_value:
            entry["default_value"] = list(self.value) if isinstance(self.value, list) else self.value
        if self.read_only:
            entry["read_only"] = True
        if self.dynamic_typing:
            entry["dynamic_typing"] = True
        if self.description:
            entry["description"] = self.description
        if self.additional_constraints:
            entry["additional_constraints"] = self.additional_constraints
        if self.integer_range is not None:
            entry["integer_range"] = self.integer_range.to_contract()
        if self.floating_point_range is not None:
            entry["floating_point_range"] = self.floating_point_range.to_contract()
        if self.declared_in is not None:
            entry["declared_in"] = self.declared_in
        return entry


@dataclass(frozen=True)
class Transition:
    """One ``change_state`` request the middleware sent: ``result`` is ``success``,
    ``failure`` (answered success=false: the callback returned FAILURE or ERROR, or raised),
    ``no_answer`` or ``pending`` (in flight when the capture was written)."""

    id: int
    label: str
    result: str
    success: bool | None = None


@dataclass(frozen=True)
class Lifecycle:
    """How the middleware drove a lifecycle (managed) node. ``target``: the target option
    (``active``, ``inactive``, ``unconfigured``, ``none``); ``initial_state`` / ``state``: the
    ``get_state`` answers before and after driving (None when not read: target ``none``);
    ``error``: a failed transition or a request without an answer, naming node and transition."""

    target: str
    initial_state: str | None = None
    state: str | None = None
    transitions: tuple[Transition, ...] = ()
    error: str | None = None

    @property
    def failed_transition(self) -> Transition | None:
        """The transition that did not succeed (the driving stops there), if any."""
        for transition in self.transitions:
            if transition.result != "success":
                return transition
        return None


@dataclass(frozen=True)
class Probe:
    """The middleware's questions to the nodes (``probe`` in the capture): ``state`` is
    ``off``, ``pending``, ``running``, ``done`` or ``skipped`` (no executor ever waited, so no
    node could be asked); ``unanswered``: requests without an answer."""

    state: str
    parameters: bool
    lifecycle: str
    answer_timeout_ms: int = 0
    requests: int = 0
    unanswered: int = 0


# ---------------------------------------------------------------------- reading captures


def _string(value: Any, where: str, *, optional: bool = False) -> str | None:
    if value is None and optional:
        return None
    if not isinstance(value, str):
        raise ValueError(f"{where} is not a string")
    return value


def _flag(data: Mapping[str, Any], key: str, where: str) -> bool:
    value = data.get(key, False)
    if not isinstance(value, bool):
        raise ValueError(f"{where}.{key} is not true or false")
    return value


def _range(data: Any, where: str, *, integer: bool) -> ParameterRange | None:
    if data is None:
        return None
    if not isinstance(data, Mapping):
        raise ValueError(f"{where} is not an object")
    values: list[int | float] = []
    for key in RANGE_KEYS:
        if key not in data:
            raise ValueError(f"{where}.{key} is missing")
        value = data[key]
        if integer:
            if not _is_int(value):
                raise ValueError(f"{where}.{key} is not an integer")
            values.append(value)
        else:
            values.append(_double(value, f"{where}.{key}"))
    if values[2] < 0 or (isinstance(values[2], float) and math.isnan(values[2])):
        raise ValueError(f"{where}.step must not be negative")
    return ParameterRange(*values)


def parameter_from_capture(data: Any, where: str) -> Parameter:
    """One entry of a capture node's ``parameters`` (raises ValueError naming ``where``)."""
    if not isinstance(data, Mapping):
        raise ValueError(f"{where} is not an object")
    name = _string(data.get("name"), f"{where}.name")
    assert name is not None
    if not name:
        raise ValueError(f"{where}.name is empty")
    type_name = data.get("type")
    if type_name is not None and type_name not in PARAMETER_TYPES:
        raise ValueError(f"{where}.type {type_name!r} is not one of {', '.join(PARAMETER_TYPES)}")
    return Parameter(
        name=name,
        type=type_name,
        value=normalize_value(type_name, data.get("value"), f"{where}.value"),
        read_only=_flag(data, "read_only", where),
        dynamic_typing=_flag(data, "dynamic_typing", where),
        description=_string(data.get("description", ""), f"{where}.description") or "",
        additional_constraints=_string(data.get("additional_constraints", ""), f"{where}.additional_constraints") or "",
        integer_range=_range(data.get("integer_range"), f"{where}.integer_range", integer=True),
        floating_point_range=_range(data.get("floating_point_range"), f"{where}.floating_point_range", integer=False),
        declared_in=_string(data.get("declared_in"), f"{where}.declared_in", optional=True),
    )


def parameters_from_capture(data: Any, where: str) -> tuple[Parameter, ...] | None:
    """A capture node's ``parameters``: None when not read, else the parameters in the order
    the node listed them (raises ValueError)."""
    if data is None:
        return None
    if not isinstance(data, list):
        raise ValueError(f"{where} is not a list")
    return tuple(parameter_from_capture(p, f"{where}[{i}]") for i, p in enumerate(data))


def lifecycle_from_capture(data: Any, where: str) -> Lifecycle | None:
    """A capture node's ``lifecycle``: None for a node without the lifecycle services."""
    if data is None:
        return None
    if not isinstance(data, Mapping):
        raise ValueError(f"{where} is not an object")
    target = data.get("target")
    if target not in LIFECYCLE_TARGETS:
        raise ValueError(f"{where}.target {target!r} is not one of {', '.join(LIFECYCLE_TARGETS)}")
    transitions_data = data.get("transitions") or []
    if not isinstance(transitions_data, list):
        raise ValueError(f"{where}.transitions is not a list")
    transitions = []
    for i, t in enumerate(transitions_data):
        at = f"{where}.transitions[{i}]"
        if not isinstance(t, Mapping):
            raise ValueError(f"{at} is not an object")
        if not _is_int(t.get("id")):
            raise ValueError(f"{at}.id is not an integer")
        success = t.get("success")
        if success is not None and not isinstance(success, bool):
            raise ValueError(f"{at}.success is not true, false or null")
        label = _string(t.get("label"), f"{at}.label")
        result = _string(t.get("result"), f"{at}.result")
        assert label is not None and result is not None
        transitions.append(Transition(id=t["id"], label=label, result=result, success=success))
    return Lifecycle(
        target=target,
        initial_state=_string(data.get("initial_state"), f"{where}.initial_state", optional=True),
        state=_string(data.get("state"), f"{where}.state", optional=True),
        transitions=tuple(transitions),
        error=_string(data.get("error"), f"{where}.error", optional=True),
    )


def probe_from_capture(data: Any) -> Probe | None:
    """The capture's ``probe`` (None in captures of middleware versions without it)."""
    if data is None:
        return None
    if not isinstance(data, Mapping):
        raise ValueError("`probe` is not an object")
    state = _string(data.get("state"), "`probe.state`")
    lifecycle = _string(data.get("lifecycle", "none"), "`probe.lifecycle`")
    assert state is not None and lifecycle is not None
    counts = {}
    for key in ("answer_timeout_ms", "requests", "unanswered"):
        value = data.get(key, 0)
        if not _is_int(value) or value < 0:
            raise ValueError(f"`probe.{key}` is not a count")
        counts[key] = value
    parameters = data.get("parameters", False)
    if not isinstance(parameters, bool):
        raise ValueError("`probe.parameters` is not true or false")
    return Probe(state=state, parameters=parameters, lifecycle=lifecycle, **counts)


# ---------------------------------------------------------------------- contract entries


def check_contract_parameters(entries: Sequence[Mapping[str, Any]]) -> None:
    """Semantic checks of a contract node's ``parameters`` after the schema: a name at most
    once, a ``default_value`` of the stated type, a range that fits the type (raises
    :class:`EntryProblem`)."""
    first: dict[str, int] = {}
    for i, entry in enumerate(entries):
        name = entry["name"]
        if name in first:
            raise EntryProblem([i, "name"], f"duplicate parameter {name!r} (also at parameters[{first[name]}]); "
                                            "each parameter may appear once per node")
        first[name] = i
        type_name = entry.get("type")
        if "default_value" in entry:
            try:
                normalize_value(type_name, entry["default_value"], "default_value")
            except ValueError as exc:
                raise EntryProblem([i, "default_value"], f"parameter {name!r}: {str(exc).split(': ', 1)[-1]}"
                                   ) from None
        for key, fits in (("integer_range", ("integer", "integer_array")),
                          ("floating_point_range", ("double", "double_array"))):
            if entry.get(key) is not None and type_name not in fits and not entry.get("dynamic_typing"):
                raise EntryProblem([i, key], f"parameter {name!r} of type {type_name} cannot have an {key} "
                                             f"(only {' and '.join(fits)} parameters can)")


def entry_range(entry: ParameterEntry, key: RangeKey) -> ParameterRange | None:
    """The range ``key`` of a contract entry as a :class:`ParameterRange` (None: no range)."""
    data = entry.get(key)
    if not isinstance(data, Mapping):
        return None
    integer = key == "integer_range"
    values: list[int | float] = [data[k] if integer else _double(data[k], k) for k in RANGE_KEYS]
    return ParameterRange(*values)
