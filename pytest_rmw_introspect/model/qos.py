"""QoS vocabulary: spellings, the contract form, named profiles and compatibility rules.

Three shapes of a QoS appear in this project:

* the *raw capture* form written by the middleware: every field present, durations as integer
  nanoseconds with ``0`` = unspecified and ``-1`` = infinite;
* the *contract* form (``from_capture``): only the fields that differ from their default, or a
  profile name, or ``{profile: name, **overrides}``;
* the *explicit* form (``expand``): every field present, canonical, so that two QoS mean the same
  thing exactly when their explicit forms are equal.

Pure Python on purpose: nothing here imports rclpy.
"""

from __future__ import annotations

import enum
from collections.abc import Mapping
from typing import Any, Literal, cast, get_args

from . import middlewares
from .contract_shapes import QosFields


class History(enum.StrEnum):
    SYSTEM_DEFAULT = "SYSTEM_DEFAULT"
    KEEP_LAST = "KEEP_LAST"
    KEEP_ALL = "KEEP_ALL"
    UNKNOWN = "UNKNOWN"


class Reliability(enum.StrEnum):
    SYSTEM_DEFAULT = "SYSTEM_DEFAULT"
    RELIABLE = "RELIABLE"
    BEST_EFFORT = "BEST_EFFORT"
    UNKNOWN = "UNKNOWN"
    BEST_AVAILABLE = "BEST_AVAILABLE"


class Durability(enum.StrEnum):
    SYSTEM_DEFAULT = "SYSTEM_DEFAULT"
    TRANSIENT_LOCAL = "TRANSIENT_LOCAL"
    VOLATILE = "VOLATILE"
    UNKNOWN = "UNKNOWN"
    BEST_AVAILABLE = "BEST_AVAILABLE"


class Liveliness(enum.StrEnum):
    SYSTEM_DEFAULT = "SYSTEM_DEFAULT"
    AUTOMATIC = "AUTOMATIC"
    MANUAL_BY_TOPIC = "MANUAL_BY_TOPIC"
    UNKNOWN = "UNKNOWN"
    BEST_AVAILABLE = "BEST_AVAILABLE"


class Compatibility(enum.IntEnum):
    """Result of ``profile_compatibility``; same order as rmw's ``rmw_qos_compatibility_type_t``."""

    OK = 0
    WARNING = 1
    ERROR = 2


#: The name of a QoS field (a key of ``QosFields`` but ``profile``), in the order they are
#: written in contracts.
QosField = Literal["history", "depth", "reliability", "durability", "liveliness", "deadline_ns", "lifespan_ns",
                   "liveliness_lease_duration_ns", "avoid_ros_namespace_conventions"]
#: All QoS fields, in the order they are written in contracts.
FIELDS: tuple[QosField, ...] = get_args(QosField)
ENUM_FIELDS: dict[str, type[enum.StrEnum]] = {
    "history": History,
    "reliability": Reliability,
    "durability": Durability,
    "liveliness": Liveliness,
}
DurationField = Literal["deadline_ns", "lifespan_ns", "liveliness_lease_duration_ns"]
DURATION_FIELDS: tuple[DurationField, ...] = get_args(DurationField)

#: the fields that decide whether two endpoints match (a service's QoS is compared on these only)
MATCHING_FIELDS: tuple[QosField, ...] = ("reliability", "durability", "deadline_ns", "liveliness",
                                         "liveliness_lease_duration_ns")

DURATION_UNSPECIFIED = 0
DURATION_INFINITE = -1
#: RMW_QOS_DEADLINE_BEST_AVAILABLE / ..._LEASE_DURATION_BEST_AVAILABLE ({9223372036, 854775806})
#: in nanoseconds, and RMW_DURATION_INFINITE in case a writer did not map it to -1.
DURATION_BEST_AVAILABLE = 9_223_372_036_854_775_806
_DURATION_INFINITE_RAW = 9_223_372_036_854_775_807

_SECOND = 1_000_000_000


def _profile(history: str, depth: int, reliability: str, durability: str, lifespan_ns: int = 0) -> QosFields:
    return {
        "history": history,
        "depth": depth,
        "reliability": reliability,
        "durability": durability,
        "liveliness": "SYSTEM_DEFAULT",
        "deadline_ns": 0,
        "lifespan_ns": lifespan_ns,
        "liveliness_lease_duration_ns": 0,
        "avoid_ros_namespace_conventions": False,
    }


#: The named profiles a contract may use, in the order ``profile_name`` prefers them
#: (``default`` and ``services_default`` are identical, as are ``parameters`` and
#: ``parameter_events``: the first one wins).
PROFILES: dict[str, QosFields] = {
    "default": _profile("KEEP_LAST", 10, "RELIABLE", "VOLATILE"),
    "system_default": _profile("SYSTEM_DEFAULT", 0, "SYSTEM_DEFAULT", "SYSTEM_DEFAULT"),
    "sensor_data": _profile("KEEP_LAST", 5, "BEST_EFFORT", "VOLATILE"),
    "services_default": _profile("KEEP_LAST", 10, "RELIABLE", "VOLATILE"),
    "parameters": _profile("KEEP_LAST", 1000, "RELIABLE", "VOLATILE"),
    "parameter_events": _profile("KEEP_LAST", 1000, "RELIABLE", "VOLATILE"),
    # rcl_qos_profile_rosout_default
    "rosout": _profile("KEEP_LAST", 1000, "RELIABLE", "TRANSIENT_LOCAL", lifespan_ns=10 * _SECOND),
    # REP-2003: maps are latched and only the newest one matters
    "map": _profile("KEEP_LAST", 1, "RELIABLE", "TRANSIENT_LOCAL"),
}

#: Value of every field a contract leaves out (rmw_qos_profile_default).
DEFAULTS: QosFields = PROFILES["default"]


# --------------------------------------------------------------------------- validation


def _parse_enum(field: str, value: Any) -> str:
    allowed = ENUM_FIELDS[field]
    if isinstance(value, str):
        try:
            return allowed(value.strip().upper()).value
        except ValueError:
            pass
    names = ", ".join(member.value for member in allowed)
    raise ValueError(f"invalid QoS {field} {value!r}: expected one of {names}")


def _parse_int(field: str, value: Any) -> int:
    # bool is an int in Python; `depth: true` is a mistake, not 1
    if isinstance(value, bool) or not isinstance(value, int):
        raise ValueError(f"invalid QoS {field} {value!r}: expected an integer")
    return value


def _parse_depth(value: Any) -> int:
    depth = _parse_int("depth", value)
    if depth < 0:
        raise ValueError(f"invalid QoS depth {value!r}: must not be negative")
    return depth


def _parse_duration(field: str, value: Any) -> int:
    duration = _parse_int(field, value)
    if duration < DURATION_INFINITE:
        raise ValueError(
            f"invalid QoS {field} {value!r}: expected nanoseconds, 0 (unspecified) or -1 (infinite)"
        )
    if duration >= _DURATION_INFINITE_RAW:
        return DURATION_INFINITE
    return duration


def _parse_field(field: str, value: Any) -> Any:
    if field in ENUM_FIELDS:
        return _parse_enum(field, value)
    if field == "depth":
        return _parse_depth(value)
    if field in DURATION_FIELDS:
        return _parse_duration(field, value)
    if field == "avoid_ros_namespace_conventions":
        if not isinstance(value, bool):
            raise ValueError(f"invalid QoS {field} {value!r}: expected true or false")
        return value
    raise ValueError(f"unknown QoS key {field!r}: expected one of profile, {', '.join(FIELDS)}")


def _profile_by_name(name: Any) -> QosFields:
    if not isinstance(name, str) or name not in PROFILES:
        raise ValueError(f"unknown QoS profile {name!r}: expected one of {', '.join(PROFILES)}")
    return PROFILES[name].copy()


def _resolve(value: Any) -> QosFields:
    """Any accepted QoS shape → every field present and validated (durations kept as given)."""
    if isinstance(value, str):
        return _profile_by_name(value)
    if not isinstance(value, Mapping):
        raise ValueError(
            f"invalid QoS {value!r}: expected a profile name or a mapping of QoS fields"
        )
    overrides = dict(value)
    # the fields of a named profile or of DEFAULTS, then each override validated by _parse_field
    # (which refuses a key that is not a QoS field): every field, in FIELDS order
    resolved: dict[str, Any] = dict(_profile_by_name(overrides.pop("profile")) if "profile" in overrides else DEFAULTS)
    for field, field_value in overrides.items():
        resolved[field] = _parse_field(field, field_value)
    return cast(QosFields, {field: resolved[field] for field in FIELDS})


# --------------------------------------------------------------------------- public forms


def expand(value: Any) -> QosFields:
    """Contract QoS (profile name, ``{profile: ..., **overrides}`` or fields) → explicit form.

    The explicit form has every field of ``FIELDS``. It is canonical: ``depth`` is 0 unless
    history is KEEP_LAST (it means nothing otherwise) and an infinite duration is written as
    unspecified (0), because contracts do not distinguish the two ("no deadline").
    Raises ValueError naming the offending key or value.
    """
    resolved = _resolve(value)
    if resolved["history"] != History.KEEP_LAST:
        resolved["depth"] = 0
    for field in DURATION_FIELDS:
        if resolved[field] == DURATION_INFINITE:
            resolved[field] = DURATION_UNSPECIFIED
    return resolved


def from_capture(raw_qos: Mapping[str, Any]) -> QosFields:
    """Raw capture QoS (design.md section 1) → contract form (design.md section 2).

    Always written: history, depth (KEEP_LAST only), reliability, durability. The others only
    when they differ from their default; unspecified (0) and infinite (-1) durations are omitted.
    Missing raw fields are taken as their default.
    """
    explicit = expand(raw_qos)
    contract: QosFields = {"history": explicit["history"]}
    if explicit["history"] == History.KEEP_LAST:
        contract["depth"] = explicit["depth"]
    contract["reliability"] = explicit["reliability"]
    contract["durability"] = explicit["durability"]
    if explicit["liveliness"] != Liveliness.SYSTEM_DEFAULT:
        contract["liveliness"] = explicit["liveliness"]
    for field in DURATION_FIELDS:
        if explicit[field] != DURATION_UNSPECIFIED:
            contract[field] = explicit[field]
    if explicit["avoid_ros_namespace_conventions"]:
        contract["avoid_ros_namespace_conventions"] = True
    return contract


def service_from_capture(raw_qos: Mapping[str, Any]) -> QosFields | None:
    """A service server's or client's raw capture QoS → its contract form: the matching fields
    (:data:`MATCHING_FIELDS`) that differ from ``services_default``, None when none does (the
    QoS nearly every service has; history and depth never decide whether a client is served)."""
    explicit = expand(raw_qos)
    default = PROFILES["services_default"]
    differing = {f: explicit[f] for f in MATCHING_FIELDS if explicit[f] != default[f]}
    return cast(QosFields, differing) if differing else None


def profile_name(qos: Any) -> str | None:
    """The name of the standard profile ``qos`` equals (in any accepted shape), else None."""
    explicit = expand(qos)
    for name in PROFILES:
        if expand(name) == explicit:
            return name
    return None


def describe(qos: Any) -> str:
    """Short text for people: the profile name if there is one, else the contract form."""
    name = profile_name(qos)
    if name is not None:
        return name
    contract = from_capture(expand(qos))
    return "{" + ", ".join(f"{key}: {format_value(key, v)}" for key, v in contract.items()) + "}"


def format_duration(ns: int) -> str:
    """Nanoseconds → '250 ms', '10 s'; 0 → 'unset', -1 → 'infinite'."""
    if ns == DURATION_UNSPECIFIED:
        return "unset"
    if ns == DURATION_INFINITE:
        return "infinite"
    if ns == DURATION_BEST_AVAILABLE:
        return "best available"
    for unit, size in (("s", _SECOND), ("ms", 1_000_000), ("us", 1_000)):
        if ns % size == 0:
            return f"{ns // size} {unit}"
    return f"{ns} ns"  # exact rather than rounded: the contract compares exact values


def format_value(field: str, value: Any) -> str:
    """One QoS field value for people (durations in readable units)."""
    if value is None:
        return "none"
    if field in DURATION_FIELDS and isinstance(value, int) and not isinstance(value, bool):
        return format_duration(value)
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


# --------------------------------------------------------------------------- compatibility
#
# The rules of rmw_dds_common's qos_profile_check_compatible (what Fast DDS, Cyclone DDS and
# Connext enforce through rmw), restated: a publisher *offers*, a subscription *requests*.

_UNKNOWN = ("SYSTEM_DEFAULT", "UNKNOWN")


def _duration_set(ns: int) -> bool:
    return ns != DURATION_UNSPECIFIED


def _duration_exceeds(a: int, b: int) -> bool:
    """a > b for set durations, where infinite (-1) is longer than anything finite."""
    if a == DURATION_INFINITE:
        return b != DURATION_INFINITE
    if b == DURATION_INFINITE:
        return False
    return a > b


def _duration_errors(policy: str, offered: int, requested: int) -> list[str]:
    # BEST_AVAILABLE durations are chosen at creation to match the peers: never an error.
    if DURATION_BEST_AVAILABLE in (offered, requested):
        return []
    if not _duration_set(offered) and _duration_set(requested):
        return [f"subscription requests a {policy} but the publisher offers none"]
    if _duration_set(offered) and _duration_set(requested) and _duration_exceeds(offered, requested):
        return [
            f"subscription {policy} ({format_duration(requested)}) is shorter than the "
            f"publisher's ({format_duration(offered)})"
        ]
    return []


def _policy_warning(policy: str, offered: str, requested: str, weak: str, strong: str) -> list[str]:
    """The three "could go either way" cases for one policy (evaluated only without errors)."""
    offered_unknown = offered in _UNKNOWN
    requested_unknown = requested in _UNKNOWN
    if offered_unknown and requested_unknown:
        return [f"{policy} is {offered} on the publisher and {requested} on the subscription"]
    if offered_unknown and requested == strong:
        return [f"subscription requests {strong} {policy} but the publisher's is {offered}"]
    if offered == weak and requested_unknown:
        return [f"publisher offers {weak} {policy} but the subscription's is {requested}"]
    return []


def settle_system_defaults(qos: Any, rmw: str | None, *, offering: bool) -> QosFields:
    """``qos`` (any shape) with the policies left at SYSTEM_DEFAULT as the middleware ``rmw``
    creates them (``middlewares``: a publisher's as a DataWriter's, a subscription's as a
    DataReader's); unchanged for a middleware whose defaults are not known, or None."""
    resolved = _resolve(qos)
    middleware = middlewares.get(rmw)
    if middleware is None:
        return resolved
    defaults = middleware.writer_defaults if offering else middleware.reader_defaults
    settled: dict[str, Any] = dict(resolved)
    for policy, value in defaults.items():
        if settled[policy] == "SYSTEM_DEFAULT":
            settled[policy] = value
    return cast(QosFields, settled)


def profile_compatibility(offered: Any, requested: Any, rmw: str | None = None) -> tuple[Compatibility, str]:
    """Can a publisher with QoS ``offered`` reach a subscription with QoS ``requested``?

    Accepts any QoS shape (raw capture, contract or explicit). Returns the compatibility and a
    reason ("" when OK; errors first, then warnings, joined by "; "). History, depth and lifespan
    are never compared; BEST_AVAILABLE policies are resolved at creation and never conflict.

    ``rmw``: the middleware the two ends run on (``middlewares.KNOWN``; None: rmw_dds_common's
    rules as they are). A middleware that matches whatever the QoS (rmw_zenoh_cpp) answers OK;
    one whose SYSTEM_DEFAULT resolution is known (Fast DDS, Cyclone DDS) is judged on the
    policies it really creates (:func:`settle_system_defaults`). Raises ValueError for an
    unknown ``rmw``.
    """
    middleware = middlewares.get(rmw)
    if middleware is not None and not middleware.refuses:
        return Compatibility.OK, ""
    pub = settle_system_defaults(offered, rmw, offering=True)
    sub = settle_system_defaults(requested, rmw, offering=False)

    errors: list[str] = []
    if pub["reliability"] == "BEST_EFFORT" and sub["reliability"] == "RELIABLE":
        errors.append("BEST_EFFORT publisher and RELIABLE subscription")
    if pub["durability"] == "VOLATILE" and sub["durability"] == "TRANSIENT_LOCAL":
        errors.append("VOLATILE publisher and TRANSIENT_LOCAL subscription")
    errors += _duration_errors("deadline", pub["deadline_ns"], sub["deadline_ns"])
    if pub["liveliness"] == "AUTOMATIC" and sub["liveliness"] == "MANUAL_BY_TOPIC":
        errors.append("AUTOMATIC liveliness publisher and MANUAL_BY_TOPIC subscription")
    errors += _duration_errors(
        "liveliness lease duration",
        pub["liveliness_lease_duration_ns"],
        sub["liveliness_lease_duration_ns"],
    )
    settled = [f"{side} {policy} {value}" for side, given, now in (("publisher", _resolve(offered), pub),
                                                                   ("subscription", _resolve(requested), sub))
               for policy, value in now.items()
               if policy in ("reliability", "durability") and given[policy] == "SYSTEM_DEFAULT" != value]  # type: ignore[literal-required]
    because = f" ({rmw} creates SYSTEM_DEFAULT as {', '.join(settled)})" if settled else ""
    if errors:
        return Compatibility.ERROR, "; ".join(f"ERROR: {e}" for e in errors) + because

    warnings = (
        _policy_warning("reliability", pub["reliability"], sub["reliability"],
                        weak="BEST_EFFORT", strong="RELIABLE")
        + _policy_warning("durability", pub["durability"], sub["durability"],
                          weak="VOLATILE", strong="TRANSIENT_LOCAL")
        + _policy_warning("liveliness", pub["liveliness"], sub["liveliness"],
                          weak="AUTOMATIC", strong="MANUAL_BY_TOPIC")
    )
    if warnings:
        return Compatibility.WARNING, "; ".join(f"WARNING: {w}" for w in warnings)
    return Compatibility.OK, ""


def service_compatibility(server: Any, client: Any, rmw: str | None = None) -> tuple[Compatibility, str]:
    """Can a service client with QoS ``client`` reach a server with QoS ``server``?

    A DDS middleware carries a service on two topics, each end with its one QoS: requests (the
    client's writer, the server's reader) and responses (the server's writer, the client's
    reader); the client gets an answer only when both match (witnessed on Fast DDS: a
    BEST_EFFORT client of a RELIABLE server, and a RELIABLE client of a BEST_EFFORT server, are
    never served). So a pair is judged with :func:`profile_compatibility` both ways, the worse
    answer wins, and the reason names the direction."""
    worst, reasons = Compatibility.OK, list[str]()
    for direction, offered, requested, writer, reader in (("requests", client, server, "client", "server"),
                                                          ("responses", server, client, "server", "client")):
        compatibility, reason = profile_compatibility(offered, requested, rmw)
        if compatibility > worst:
            worst, reasons = compatibility, []
        if compatibility is worst and compatibility is not Compatibility.OK:
            for part in reason.split("; "):
                level, _, text = part.partition(": ")
                text = text.replace("publisher", writer).replace("subscription", reader)
                reasons.append(f"{level}: {text} ({direction})")
    return worst, "; ".join(reasons)
