"""Comparison options: what each value means, and how a set of layers becomes the options a
comparison uses.

The options themselves (names, types, defaults, help, the front ends that expose them) are the
table ``model.option_tables.COMPARISON``; ``options_reference.render_markdown("comparison")``
renders it. Their precedence is ``model.option_tables.PRECEDENCE``, applied by
``check.pipeline.Layers``; :func:`resolve` folds layers already in that order.
"""

from __future__ import annotations

import fnmatch
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from ..errors import OptionError
from ..model.option_tables import COMPARISON, Shape
from ..model.qos import FIELDS as QOS_FIELDS
from ..model.vocabulary import Severity, parse_threshold
from . import rule_levels
from .rule_levels import RuleLevel

#: every comparison option, in table order
OPTION_KEYS = COMPARISON.names()
_TRUE = ("1", "true", "yes", "on", "all")
_FALSE = ("0", "false", "no", "off", "")


@dataclass(frozen=True)
class ComparisonOptions:
    """How a capture (or a newer contract) is compared with a contract (``option_tables.COMPARISON``:
    a unit test checks that these defaults are the table's);
    :func:`pytest_rmw_introspect.compare.drift.compare` takes it as it is."""

    ignore_type_hash: bool = False
    ignore_qos: frozenset[str] | bool = frozenset()  # True: every QoS field
    allow_extra: bool = False  # the contract is a minimum: additions are not drift
    include_infrastructure: bool = False
    fail_on: str = "any"
    #: the contract keeps a generated ``types:`` section (docs/design.md section 2): written by
    #: --update-golden, its absence is drift. A contract that has one is compared with it and
    #: keeps it up to date whatever this says.
    include_types: bool = False
    #: True: parameters are not compared at all; else the name patterns of those not compared
    ignore_parameters: frozenset[str] | bool = frozenset()
    #: True: no parameter's default value is compared; else the name patterns whose values are not
    ignore_parameter_values: frozenset[str] | bool = frozenset()
    #: the least severe system problem that fails a system contract's check (its compatibility
    #: rules; a node contract has none)
    system_fail_on: str = "breaking"
    #: the middleware whose QoS rules judge contracts that do not say (``model.middlewares``; None:
    #: the DDS rules of rmw_dds_common)
    rmw: str | None = None
    #: the project's levels of rules (``compare.rule_levels``), every layer's keys merged
    rules: tuple[RuleLevel, ...] = ()

    def ignores_parameter(self, name: str) -> bool:
        """Whether the parameter ``name`` is not compared at all (``ignore_parameters``)."""
        return _matches(self.ignore_parameters, name)

    def ignores_parameter_value(self, name: str) -> bool:
        """Whether the default value of the parameter ``name`` is not compared."""
        return _matches(self.ignore_parameter_values, name)

    def threshold(self) -> Severity:
        """The least severity that fails (``fail_on``)."""
        return parse_threshold(self.fail_on)

    def system_threshold(self) -> Severity:
        """The least severity of a system problem that fails (``system_fail_on``)."""
        return parse_threshold(self.system_fail_on)

    @property
    def ignores_all_qos(self) -> bool:
        return self.ignore_qos is True


def _bool(value: Any, key: str, source: str) -> bool:
    if isinstance(value, bool):
        return value
    if isinstance(value, str) and value.strip().lower() in _TRUE + _FALSE:
        return value.strip().lower() in _TRUE
    raise OptionError(f"{source}: `{key}` must be true or false, got {value!r}")


def _all_none_or_words(value: Any) -> Any:
    """``true`` / ``all`` → True, ``false`` / ``none`` / empty → an empty set, one string of
    words separated by commas or spaces → the list of words; anything else as it is."""
    if isinstance(value, bool):
        return True if value else frozenset()
    if isinstance(value, str):
        text = value.strip().lower()
        if text in _TRUE:
            return True
        if text in _FALSE or text == "none":
            return frozenset()
        return [v.strip() for v in value.replace(" ", ",").split(",") if v.strip()]
    return value


def _ignore_qos(value: Any, source: str) -> frozenset[str] | bool:
    value = _all_none_or_words(value)
    if value is True:
        return True
    if isinstance(value, (list, tuple, set, frozenset)):
        fields = frozenset(str(v) for v in value)
        unknown = sorted(fields - set(QOS_FIELDS))
        if unknown:
            raise OptionError(
                f"{source}: `ignore_qos` names unknown QoS field(s) {', '.join(unknown)}; "
                f"known: {', '.join(QOS_FIELDS)} (or true for all)"
            )
        return fields
    raise OptionError(f"{source}: `ignore_qos` must be true/false or a list of QoS fields, got {value!r}")


def _matches(patterns: frozenset[str] | bool, name: str) -> bool:
    if patterns is True or patterns is False:
        return bool(patterns)
    return any(fnmatch.fnmatchcase(name, pattern) for pattern in patterns)


def _patterns(value: Any, key: str, source: str) -> frozenset[str] | bool:
    """``true`` / ``all`` (everything), ``false`` / ``none`` (nothing), or name patterns: a list,
    or one string with patterns separated by commas or spaces."""
    value = _all_none_or_words(value)
    if value is True:
        return True
    if isinstance(value, (list, tuple, set, frozenset)) and all(isinstance(v, str) and v.strip() for v in value):
        return frozenset(v.strip() for v in value)
    raise OptionError(f"{source}: `{key}` must be true/false or a list of parameter names or patterns "
                      f"(fnmatch globs such as qos_overrides.*), got {value!r}")


def _choice(value: Any, key: str, source: str) -> str:
    choices = COMPARISON[key].choices
    if isinstance(value, str) and value.strip().lower() in choices:
        return value.strip().lower()
    raise OptionError(f"{source}: `{key}` must be one of {', '.join(choices)}, got {value!r}")


def parse_one(key: str, value: Any, source: str) -> Any:
    """Validate one option value (from any source)."""
    if key not in OPTION_KEYS:
        raise OptionError(f"{source}: unknown option {key!r}; known: {', '.join(OPTION_KEYS)}")
    if key == "ignore_qos":
        return _ignore_qos(value, source)
    if key == "rules":
        return rule_levels.parse(value, source)
    shape = COMPARISON[key].shape
    if shape is Shape.CHOICE:
        return _choice(value, key, source)
    if shape is Shape.WORDS:
        return _patterns(value, key, source)
    assert shape is Shape.SWITCH, key  # a new shape needs its parser here
    return _bool(value, key, source)


def parse_layer(values: Mapping[str, Any] | None, source: str) -> dict[str, Any]:
    """Validate a set of options; ``None`` values mean "not set here"."""
    return {k: parse_one(k, v, source) for k, v in (values or {}).items() if v is not None}


def resolve(*layers: tuple[Mapping[str, Any] | None, str]) -> ComparisonOptions:
    """Combine ``(values, source)`` layers given weakest first (``option_tables.stack`` orders them)."""
    merged: dict[str, Any] = {}
    for values, source in layers:
        parsed = parse_layer(values, source)
        if "rules" in parsed:  # merged key by key: a stronger layer wins the keys it sets
            parsed["rules"] = rule_levels.merge(merged.get("rules", ()), parsed["rules"])
        merged.update(parsed)
    return ComparisonOptions(**merged)
