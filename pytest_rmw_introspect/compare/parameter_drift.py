"""A node's parameters and lifecycle state, expected (contract) against actual (capture or a
newer contract) → classified changes. ``compare.drift`` turns them into DriftItems; the rule
table with the reasoning behind each severity is docs/drift-rules.md ("Parameter rules",
"Lifecycle rules").

Parameters are judged from the side of whoever sets them: launch files, parameter files,
``--ros-args -p``, ``ros2 param set``, reconfigure tools and other nodes calling the parameter
services. A parameter that disappears or refuses values it accepted before breaks them
(silently, for start-up overrides: ROS 2 ignores overrides of undeclared parameters); a changed
default changes the behaviour of every system that does not set it.

What a side does not state is not compared: a node entry without ``parameters`` (written before
parameters were recorded, or by hand), a parameter entry without ``default_value``. A node entry
states whether it is a lifecycle node when it has ``lifecycle`` or ``parameters``.
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any, Literal

from ..model import parameters as parameter_model
from ..model import untrusted
from ..model.contract_shapes import ContractNode, ContractNodes, ParameterEntry
from ..model.parameters import ParameterRange, RangeKey, format_value
from ..model.vocabulary import LIFECYCLE, LIFECYCLE_TRANSITIONS, LIFECYCLE_UNKNOWN, PARAMETERS, Severity
from .options import ComparisonOptions
from .similarity import typo_distance

_B, _R, _S = Severity.BREAKING, Severity.RISKY, Severity.SAFE

#: rule id → (severity, what changed)
RULES: dict[str, tuple[Severity, str]] = {
    "PARAM_REMOVED": (_B, "parameter removed"),
    "PARAM_ADDED": (_S, "parameter added (with a default value)"),
    "PARAM_ADDED_WITHOUT_VALUE": (_R, "parameter added without a default value"),
    "PARAM_ADDED_SUSPICIOUS": (_R, "parameter added whose name looks like a typo of another one, or like garbage"),
    "PARAM_RENAMED": (_B, "parameter renamed (one removed, one of the same type added)"),
    "PARAM_TYPE_CHANGED": (_B, "parameter type changed"),
    "PARAM_DEFAULT_CHANGED": (_R, "parameter default value changed"),
    "PARAM_READ_ONLY_ADDED": (_B, "parameter made read-only"),
    "PARAM_READ_ONLY_REMOVED": (_S, "parameter no longer read-only"),
    "PARAM_DYNAMIC_TYPING_ADDED": (_S, "parameter accepts values of any type (dynamic_typing set)"),
    "PARAM_DYNAMIC_TYPING_REMOVED": (_R, "parameter no longer accepts values of another type (dynamic_typing unset)"),
    "PARAM_RANGE_NARROWED": (_R, "parameter range narrowed, added, or moved"),
    "PARAM_RANGE_WIDENED": (_S, "parameter range widened or removed"),
    "PARAM_DESCRIPTION_CHANGED": (_S, "parameter description changed"),
    "PARAM_CONSTRAINTS_CHANGED": (_S, "parameter additional_constraints text changed"),
    "PARAM_DECLARED_LATER": (_R, "parameter declared in a later lifecycle transition"),
    "PARAM_DECLARED_EARLIER": (_S, "parameter declared earlier (at start-up or in an earlier transition)"),
    "PARAMS_NOT_READ": (_R, "the contract lists the node's parameters, the capture has none"),
    "LIFECYCLE_ADDED": (_B, "node became a lifecycle (managed) node"),
    "LIFECYCLE_REMOVED": (_B, "node is no longer a lifecycle (managed) node"),
    "LIFECYCLE_STATE_CHANGED": (_R, "lifecycle node captured in another state than the contract describes"),
}

#: ``DriftItem.change`` of a node's lifecycle item
LIFECYCLE_CHANGE = LIFECYCLE
#: the attributes of a parameter entry that are compared, in report order
ATTRIBUTES: tuple[str, ...] = (
    "type", "default_value", "read_only", "dynamic_typing", "integer_range", "floating_point_range",
    "description", "additional_constraints", "declared_in",
)


@dataclass(frozen=True)
class Change:
    """One difference: ``kind`` is ``parameters`` (``name`` a parameter) or ``node`` (``name``
    the node: its lifecycle, or parameters that were not read); ``change`` is ``added``,
    ``removed``, an attribute of :data:`ATTRIBUTES`, ``lifecycle`` or ``parameters``."""

    kind: str
    name: str
    change: str
    old: Any
    new: Any
    rule: str
    message: str


def states_lifecycle(node: ContractNode) -> bool:
    """Whether a contract node entry says if it is a lifecycle node: it has ``lifecycle`` (it is
    one) or ``parameters`` (written by a version that records both: it is not one)."""
    return LIFECYCLE in node or PARAMETERS in node


# ---------------------------------------------------------------------- lifecycle


def compare_lifecycle(node: str, expected: ContractNode, actual: ContractNode) -> list[Change]:
    """The lifecycle of one node present on both sides."""
    if not states_lifecycle(expected) or not states_lifecycle(actual):
        return []
    old, new = expected.get(LIFECYCLE), actual.get(LIFECYCLE)
    if old is None and new is not None:
        return [Change("node", node, LIFECYCLE_CHANGE, None, new, "LIFECYCLE_ADDED",
                       f"{node} is now a lifecycle (managed) node (captured {new}): it creates its interface only "
                       "once a lifecycle manager configures and activates it; a system that starts it without one "
                       "gets none of it")]
    if old is not None and new is None:
        return [Change("node", node, LIFECYCLE_CHANGE, old, None, "LIFECYCLE_REMOVED",
                       f"{node} is no longer a lifecycle (managed) node: a lifecycle manager that drives it finds no "
                       f"{node}/change_state service and fails to bring the system up")]
    if old != new and LIFECYCLE_UNKNOWN not in (old, new):
        return [Change("node", node, LIFECYCLE_CHANGE, old, new, "LIFECYCLE_STATE_CHANGED",
                       f"the contract describes {node} {old}, the capture reached {new}: the interfaces are compared "
                       "across two states (check the target's `lifecycle:` option, or how the node drives itself)")]
    return []


# ---------------------------------------------------------------------- parameters


def _visible(entries: Iterable[ParameterEntry], options: ComparisonOptions) -> dict[str, ParameterEntry]:
    return {str(e.get("name")): e for e in entries if not options.ignores_parameter(str(e.get("name")))}


def compare_parameters(node: str, expected: ContractNode, actual: ContractNode,
                       options: ComparisonOptions) -> list[Change]:
    """The parameters of one node present on both sides (nothing when the contract does not
    state them, or ``ignore_parameters`` is true)."""
    if options.ignore_parameters is True or PARAMETERS not in expected:
        return []
    old = _visible(expected[PARAMETERS], options)
    if PARAMETERS not in actual:
        if not old:
            return []
        return [Change("node", node, PARAMETERS, sorted(old), None, "PARAMS_NOT_READ",
                       f"the contract lists {len(old)} parameter(s) of {node} but the capture has none: they could "
                       "not be read (see the notes) or the node no longer offers its parameter services, so they "
                       "were not compared (`ignore_parameters: true` or the target option `read_parameters: false` "
                       "stop comparing them)")]
    new = _visible(actual[PARAMETERS], options)
    changes: list[Change] = []
    for name in sorted(set(old) - set(new)):
        changes.append(removed(name, old[name]))
    for name in sorted(set(new) - set(old)):
        changes.append(added(name, new[name], others=[other for other in new if other != name]))
    for name in sorted(set(old) & set(new)):
        changes += _changed(name, old[name], new[name], options)
    return changes


def removed(name: str, entry: ParameterEntry) -> Change:
    return Change(PARAMETERS, name, "removed", dict(entry), None, "PARAM_REMOVED",
                  f"parameter removed: launch files, parameter files and -p overrides that set {name} are silently "
                  "ignored, and `ros2 param set` of it fails")


def added(name: str, entry: ParameterEntry, others: Iterable[str] = ()) -> Change:
    """A new parameter; ``others``: the node's other parameters (a name one typo away from one
    of them is not SAFE: it is usually an override that created it, ``automatically_declare_
    parameters_from_overrides``, or a declaration with a typo)."""
    type_name = entry.get("type") or "no type"
    if "default_value" in entry and entry["default_value"] is None and entry.get("type") is not None:
        return Change(PARAMETERS, name, "added", None, dict(entry), "PARAM_ADDED_WITHOUT_VALUE",
                      f"new parameter {name} ({type_name}) without a default value: launch and parameter files must "
                      "now set it (rclcpp's declare_parameter<T>(name) throws when nothing sets it)")
    value = f", default {format_value(entry['default_value'])}" if "default_value" in entry else ""
    suspicion = _suspicion(name, others)
    if suspicion:
        return Change(PARAMETERS, name, "added", None, dict(entry), "PARAM_ADDED_SUSPICIOUS",
                      f"new parameter {name} ({type_name}{value}) {suspicion}: check the launch and parameter files "
                      "and the node's declarations")
    return Change(PARAMETERS, name, "added", None, dict(entry), "PARAM_ADDED",
                  f"new parameter {name} ({type_name}{value}): nothing sets it yet, it starts at its default")


_PARAMETER_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z0-9_/][A-Za-z0-9_/-]*)*")


def _numbered_siblings(a: str, b: str) -> bool:
    """``gain_x`` / ``gain_y``, ``joint1`` / ``joint2``: one axis or index apart, not a typo."""
    differing = [(x, y) for x, y in zip(a, b, strict=False) if x != y]
    return len(a) == len(b) and len(differing) == 1 and all(c in "0123456789xyzXYZ" for c in differing[0])


def _suspicion(name: str, others: Iterable[str]) -> str | None:
    if not _PARAMETER_NAME.fullmatch(name):
        return "has a name that is no parameter name a node would declare (characters, empty parts)"
    for other in sorted(others):
        if _numbered_siblings(name, other):
            continue
        distance = typo_distance(name, other, shortest=max(len(name), len(other)))
        if distance is not None:
            return f"is {distance} character(s) from {other}: it looks like a typo of it"
    return None


def _range(entry: ParameterEntry, key: RangeKey) -> ParameterRange | None:
    try:
        return parameter_model.entry_range(entry, key)
    except (KeyError, TypeError, ValueError):
        return None


def _value(entry: ParameterEntry) -> Any:
    try:
        return parameter_model.normalize_value(entry.get("type"), entry.get("default_value"))
    except ValueError:
        return entry.get("default_value")


def _changed(name: str, old: ParameterEntry, new: ParameterEntry, options: ComparisonOptions) -> list[Change]:
    def change(attribute: str, old_value: Any, new_value: Any, rule: str, message: str) -> Change:
        return Change(PARAMETERS, name, attribute, old_value, new_value, rule, message)

    out: list[Change] = []
    old_type, new_type = old.get("type"), new.get("type")
    retyped = old_type != new_type
    compare_values = ("default_value" in old and "default_value" in new and not options.ignores_parameter_value(name))
    if retyped and not new.get("dynamic_typing"):
        out.append(change("type", old_type, new_type, "PARAM_TYPE_CHANGED",
                          f"type changed from {old_type} to {new_type}: overrides of the old type are refused "
                          "(InvalidParameterTypeException at start-up; `ros2 param set` fails)"))
    elif compare_values and (retyped or not parameter_model.same_value(_value(old), _value(new))):
        retyped_text = f" (and its type {old_type} -> {new_type}, which dynamic typing accepts)" if retyped else ""
        old_text, new_text = format_value(_value(old)), format_value(_value(new))
        out.append(change("default_value", old.get("default_value"), new.get("default_value"),
                          "PARAM_DEFAULT_CHANGED",
                          f"default value {old_text} -> {new_text}{_first_difference(_value(old), _value(new), old_text)}"
                          f"{retyped_text}: "
                          "systems that rely on the default behave differently (those that set it are unaffected)"))
    for flag, added_rule, removed_rule, added_text, removed_text in (
        ("read_only", "PARAM_READ_ONLY_ADDED", "PARAM_READ_ONLY_REMOVED",
         "now read-only: setting it at run time (`ros2 param set`, reconfigure tools, other nodes) fails; "
         "start-up overrides still apply",
         "no longer read-only: it can now be set at run time"),
        ("dynamic_typing", "PARAM_DYNAMIC_TYPING_ADDED", "PARAM_DYNAMIC_TYPING_REMOVED",
         "dynamic typing allowed: values of any type are accepted",
         f"dynamic typing removed: overrides and set calls of another type than {new_type} are refused"),
    ):
        was, now = bool(old.get(flag)), bool(new.get(flag))
        if was != now:
            out.append(change(flag, was, now, added_rule if now else removed_rule, added_text if now else removed_text))
    if not retyped:
        range_keys: tuple[RangeKey, ...] = ("integer_range", "floating_point_range")
        for key in range_keys:
            judged = _range_change(_range(old, key), _range(new, key), key.replace("_", " "))
            if judged is not None:
                rule, message = judged
                out.append(change(key, old.get(key), new.get(key), rule, message))
    text_rules: tuple[tuple[Literal["description", "additional_constraints"], str], ...] = (
        ("description", "PARAM_DESCRIPTION_CHANGED"), ("additional_constraints", "PARAM_CONSTRAINTS_CHANGED"))
    for text_key, rule in text_rules:
        was_text, now_text = old.get(text_key) or "", new.get(text_key) or ""
        if was_text != now_text:
            out.append(change(text_key, was_text, now_text, rule,
                              f"{text_key.replace('_', ' ')} {_short(was_text)} -> {_short(now_text)}"))
    was_in, now_in = old.get("declared_in"), new.get("declared_in")
    if was_in != now_in:
        later = _transition_rank(now_in) >= _transition_rank(was_in)
        start = "start-up"
        if later:
            out.append(change("declared_in", was_in, now_in, "PARAM_DECLARED_LATER",
                              f"now declared in {now_in or start} instead of {was_in or start}: until then it does not "
                              "exist and setting it fails (start-up overrides still apply once it is declared)"))
        else:
            out.append(change("declared_in", was_in, now_in, "PARAM_DECLARED_EARLIER",
                              f"now declared in {now_in or start} instead of {was_in or start}: it exists earlier"))
    return out


def _short(text: str, limit: int = 60) -> str:
    if not text:
        return "(none)"
    return untrusted.shorten_with_digest(text, limit)


def _first_difference(old: Any, new: Any, old_text: str) -> str:
    """Where two long strings shown cut (:func:`format_value`) first differ, or nothing."""
    if not (isinstance(old, str) and isinstance(new, str)) or old_text == repr(old):
        return ""
    index = len(os.path.commonprefix([old, new]))
    return f" (they differ from character {index + 1:,} on)"


def _transition_rank(label: str | None) -> int:
    if label is None:
        return 0
    if label in LIFECYCLE_TRANSITIONS:
        return 1 + LIFECYCLE_TRANSITIONS.index(label)
    return 1 + len(LIFECYCLE_TRANSITIONS)


# ---------------------------------------------------------------------- ranges


def _close(a: float, b: float) -> bool:
    return math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-12)


def _valid(r: ParameterRange, value: float) -> bool:
    """Whether ``value`` is valid under ``r`` (rcl_interfaces: both bounds always valid; with a
    step, the values ``from_value + k * step``)."""
    low, high = min(r.from_value, r.to_value), max(r.from_value, r.to_value)
    if value < low and not _close(value, low) or value > high and not _close(value, high):
        return False
    if not r.step or _close(value, r.from_value) or _close(value, r.to_value):
        return True
    ratio = (value - r.from_value) / r.step
    return _close(ratio, round(ratio))


def contains(outer: ParameterRange, inner: ParameterRange) -> bool:
    """Whether every value valid under ``inner`` is valid under ``outer``."""
    values = (inner.from_value, inner.to_value)
    if any(isinstance(v, float) and math.isnan(v) for v in (*values, *outer.to_contract().values())):
        return False
    if not all(_valid(outer, v) for v in values):
        return False
    if not outer.step:
        return True
    if not inner.step:  # inner is continuous, outer is not: only when inner holds just its bounds
        return _close(inner.from_value, inner.to_value)
    if inner.from_value == inner.to_value or abs(inner.step) >= abs(inner.to_value - inner.from_value):
        return True  # the bounds are inner's only values
    ratio = inner.step / outer.step
    return _close(ratio, round(ratio)) and round(ratio) != 0


def _range_change(old: ParameterRange | None, new: ParameterRange | None, word: str) -> tuple[str, str] | None:
    if old == new:
        return None
    if new is None:
        assert old is not None
        return "PARAM_RANGE_WIDENED", f"{word} {old.describe()} removed: every value of the type is accepted"
    if old is None:
        return ("PARAM_RANGE_NARROWED", f"{word} {new.describe()} added: values outside it, accepted before (in "
                "launch and parameter files, `ros2 param set`), are now refused")
    if contains(new, old):
        return "PARAM_RANGE_WIDENED", f"{word} {old.describe()} -> {new.describe()}: every value valid before still is"
    return ("PARAM_RANGE_NARROWED", f"{word} {old.describe()} -> {new.describe()}: values valid before (in launch and "
            "parameter files, `ros2 param set`) may now be refused")


# ---------------------------------------------------------------------- golden contracts


def keep_ignored(expected_nodes: Mapping[str, ContractNode] | None, actual_nodes: Mapping[str, ContractNode],
                 options: ComparisonOptions) -> ContractNodes:
    """``actual_nodes`` (what a golden is written from) with the ignored parameters as the
    contract has them: ``ignore_parameters: true`` keeps the node's ``parameters`` as written
    (none when it has none), ignored names keep their entries (or are left out), and
    ``ignore_parameter_values`` keeps the written ``default_value`` (or leaves it out). A node
    whose parameters the capture could not read keeps the contract's too (the capture does not
    say they are gone; ``PARAMS_NOT_READ`` stays until they can be read or are ignored)."""
    out: ContractNodes = {}
    for fqn, node in actual_nodes.items():
        node = node.copy()
        old_node = (expected_nodes or {}).get(fqn) or ContractNode()
        if PARAMETERS not in node and PARAMETERS in old_node:
            node[PARAMETERS] = [e.copy() for e in old_node[PARAMETERS]]
        elif options.ignore_parameters is True:
            node.pop(PARAMETERS, None)
            if PARAMETERS in old_node:
                node[PARAMETERS] = [e.copy() for e in old_node[PARAMETERS]]
        elif PARAMETERS in node:
            old_entries = {e.get("name"): e for e in old_node.get(PARAMETERS) or []}
            entries: list[ParameterEntry] = []
            for entry in node[PARAMETERS]:
                if options.ignores_parameter(entry["name"]):
                    continue
                entry = entry.copy()
                if options.ignores_parameter_value(entry["name"]):
                    entry.pop("default_value", None)
                    old = old_entries.get(entry["name"])
                    if old is not None and "default_value" in old:
                        entry["default_value"] = old["default_value"]
                entries.append(entry)
            entries += [e.copy() for name, e in old_entries.items() if options.ignores_parameter(str(name))]
            node[PARAMETERS] = sorted(entries, key=lambda e: str(e.get("name")))
        out[fqn] = node
    return out


def gains(expected_nodes: Mapping[str, ContractNode], golden_nodes: Mapping[str, ContractNode]) -> list[str]:
    """What writing ``golden_nodes`` would add to a contract whose nodes do not state it yet
    (``/n parameters``, ``/n lifecycle``), for nodes both have: a contract written before
    parameters and lifecycle states were recorded matches, but is incomplete."""
    out = []
    for fqn, node in golden_nodes.items():
        old = expected_nodes.get(fqn)
        if old is None:
            continue
        for key in (LIFECYCLE, PARAMETERS):
            if key in node and key not in old:
                out.append(f"{fqn} {key}")
    return out
