"""The middleware's capture file: its format, the records it holds and reading them.

The raw file (docs/design.md section 1) lists nodes and endpoints as the middleware saw them:
:class:`RawNode` and :class:`Endpoint` are those records, :class:`VirtualTime` its ``time``
object, :class:`Quiescence` its ``quiescence`` object, :class:`Stimulus` (with its
:class:`StimulusTarget` deliveries) an entry of its ``stimuli`` and :class:`ComponentLoadRecord`
one of its ``component_loads``. :func:`read` reads a file (JSON, or YAML with
``RMW_INTROSPECT_FORMAT=yaml``) and :func:`parse` checks a document (``format``/``format_version``
and every field's type) and returns what it says as :class:`CaptureFields`, the fields of a
:class:`~pytest_rmw_introspect.model.capture.Capture` (which builds its contract view,
``model.capture_view``, on top). Every malformed input is a
:class:`~pytest_rmw_introspect.errors.CaptureFormatError` naming the file.

This is the only module that reads the document's mappings: every other module reads these
records (``tests/unit/test_capture_file_readers.py`` fails when another reads a key of the file).
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypedDict

from ..errors import CaptureFormatError, InputError
from . import parameters as parameter_model
from . import qos as qos_module
from . import types as type_model
from . import untrusted
from .parameters import Lifecycle, Parameter, Probe
from .vocabulary import KIND_TO_LIST, TOPIC_KINDS

FORMAT = "rmw_introspect_capture"
FORMAT_VERSIONS = (1,)

# ---------------------------------------------------------------------- raw records


@dataclass(frozen=True, kw_only=True)
class _Lifetime:
    """How long a recorded node or endpoint lived (shared by :class:`RawNode` and :class:`Endpoint`;
    keyword-only, so the records' own fields stay positional)."""

    destroyed: bool = False
    #: destroyed in the run of destructions that ended the process (alive before its teardown)
    in_teardown: bool = False
    #: its virtual and real age (ms since the first rmw_init) when it was created
    created_virtual_ms: float | None = None
    created_real_ms: float | None = None
    #: its virtual and real age when the program destroyed it (None: not destroyed by the
    #: program while it ran, or a capture older than format_minor 4)
    destroyed_virtual_ms: float | None = None
    destroyed_real_ms: float | None = None

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
    #: the warp ended before its horizon because the process was proven idle while a thread of
    #: the program, in its loop, waited on the real clock with a deadline before the horizon (a
    #: Rate or WallRate sleep, a timed condition wait), which virtual time does not step
    warp_real_waits: bool = False

    @property
    def enabled(self) -> bool:
        return self.horizon_ms > 0


@dataclass(frozen=True)
class Quiescence:
    """How the settles ended (``quiescence`` in the capture file; docs/design.md, "Detected
    quiescence"). A capture that does not say reads as zeros and None."""

    #: whether detection of idle threads was on (``RMW_INTROSPECT_IDLE``)
    detect: bool | None = None
    #: settles ended by detection, and by the quiet window
    detected: int = 0
    window: int = 0
    #: returns from ``rmw_wait`` without waiting (timeout 0: ``spin_some``, ``spin_once(timeout_sec=0)``)
    polls: int = 0
    #: why the middleware last found the process not provably idle (a thread not blocked, and in
    #: which system call); None: it did not
    not_idle: str | None = None


@dataclass(frozen=True)
class StimulusTarget:
    """One delivery of a stimulus: to a subscription (a default message) or a service (a default
    request) of a node. ``result``: ``pending``, ``taken``, ``answered``, ``not_taken``,
    ``no_answer`` or ``failed``."""

    kind: str | None
    node: str | None
    type: str | None
    result: str | None
    error: str | None = None


@dataclass(frozen=True)
class Stimulus:
    """One name of ``RMW_INTROSPECT_STIMULI`` and what it came to (an entry of ``stimuli``).
    ``state``: ``pending``, ``done``, ``no_match`` or ``skipped``."""

    name: str | None
    state: str | None
    targets: tuple[StimulusTarget, ...] = ()
    error: str | None = None


@dataclass(frozen=True)
class ComponentLoadRecord:
    """What one LoadNode request of ``RMW_INTROSPECT_LOAD_NODES`` came to (an entry of
    ``component_loads``, in the order of the requests). ``result``: ``pending``, ``loaded``,
    ``refused``, ``no_answer``, ``no_service`` or ``failed``; ``full_node_name``: the node the
    container says it created."""

    service: str | None
    plugin: str | None
    node: str | None
    result: str | None
    full_node_name: str | None = None
    error: str | None = None


class CaptureFields(TypedDict):
    """What a capture document says, checked: the fields of a ``Capture`` but its contract view
    (``nodes``), its infrastructure filter and its path."""

    raw_nodes: list[RawNode]
    raw_endpoints: list[Endpoint]
    state: str
    format_version: int
    rmw_implementation: str | None
    pid: int | None
    argv: list[str]
    settle_ms: float | None
    time_to_settle_ms: float | None
    elapsed_ms: float | None
    settled_by: str | None
    ever_waited: bool | None
    activity_calls: int | None
    virtual_time: VirtualTime | None
    ended_before_settle: bool | None
    raw: Mapping[str, Any]
    types: dict[str, type_model.TypeDescription]
    has_types: bool
    format_minor: int
    probe: Probe | None
    quiescence: Quiescence | None
    stimuli: tuple[Stimulus, ...]
    component_loads: tuple[ComponentLoadRecord, ...]


# ---------------------------------------------------------------------- reading


def read(path: Path) -> Any:
    """The document of the capture file ``path`` (JSON, or YAML: ``RMW_INTROSPECT_FORMAT=yaml``)."""
    try:
        text = untrusted.read_text(path)
    except FileNotFoundError:
        raise CaptureFormatError(path, "the file does not exist") from None
    except InputError as exc:
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
        except InputError as yaml_exc:
            raise CaptureFormatError(path, f"not valid JSON ({exc}) or YAML ({yaml_exc})") from None
    except RecursionError:
        raise CaptureFormatError(path, "nested too deeply") from None
    return data


# ---------------------------------------------------------------------- parsing


def _require(cond: bool, path: Path | None, reason: str) -> None:
    if not cond:
        raise CaptureFormatError(path, reason)


def parse(data: Any, *, path: Path | None) -> CaptureFields:
    """The fields of the capture document ``data`` (read from ``path``, None: not from a file)."""
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
                    **_lifetime(n),
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
            if kind in TOPIC_KINDS:
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
                    **_lifetime(e),
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

    return CaptureFields(
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
        raw=data,
        types=types,
        has_types=data.get("types") is not None,
        format_minor=minor,
        probe=probe,
        quiescence=_quiescence(data.get("quiescence")),
        stimuli=_stimuli(data.get("stimuli")),
        component_loads=_component_loads(data.get("component_loads"), path),
    )


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


def _lifetime(record: Mapping[str, Any]) -> dict[str, Any]:
    """The :class:`_Lifetime` fields of a node or endpoint record."""
    return {
        "destroyed": bool(record.get("destroyed", False)),
        "in_teardown": bool(record.get("in_teardown", False)),
        "created_virtual_ms": _optional_float(record.get("created_virtual_ms")),
        "created_real_ms": _optional_float(record.get("created_real_ms")),
        "destroyed_virtual_ms": _optional_float(record.get("destroyed_virtual_ms")),
        "destroyed_real_ms": _optional_float(record.get("destroyed_real_ms")),
    }


def _optional_float(value: Any) -> float | None:
    return None if value is None else float(value)


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
            warp_real_waits=bool(data.get("warp_real_waits", False)),
        )
    except (TypeError, ValueError, OverflowError) as exc:
        raise CaptureFormatError(path, f"`time`: malformed field ({exc})") from None


# The three records below are read as leniently as their readers always read them (they are
# optional for readers, docs/design.md section 1): what is not the shape the middleware writes
# reads as "not said", not as a malformed capture.


def _quiescence(data: Any) -> Quiescence | None:
    if not isinstance(data, Mapping):
        return None
    polls = data.get("polls", 0)
    not_idle = data.get("not_idle")
    return Quiescence(
        detect=data["detect"] if isinstance(data.get("detect"), bool) else None,
        detected=_count(data.get("detected")),
        window=_count(data.get("window")),
        polls=_count(polls),
        not_idle=not_idle if isinstance(not_idle, str) and not_idle else None,
    )


def _count(value: Any) -> int:
    return value if isinstance(value, int) and not isinstance(value, bool) else 0


def _stimuli(data: Any) -> tuple[Stimulus, ...]:
    if not isinstance(data, list):
        return ()
    return tuple(
        Stimulus(
            name=_text(record.get("name")),
            state=_text(record.get("state")),
            targets=tuple(
                StimulusTarget(kind=_text(t.get("kind")), node=_text(t.get("node")), type=_text(t.get("type")),
                               result=_text(t.get("result")), error=_text(t.get("error")))
                for t in (record.get("targets") or ()) if isinstance(t, Mapping)
            ),
            error=_text(record.get("error")),
        )
        for record in data if isinstance(record, Mapping)
    )


def _component_loads(data: Any, path: Path | None) -> tuple[ComponentLoadRecord, ...]:
    if not data:
        return ()
    # each entry answers the request at its place: one that is not an object cannot be skipped
    _require(isinstance(data, list) and all(isinstance(r, Mapping) for r in data), path,
             "`component_loads` is not a list of objects")
    return tuple(
        ComponentLoadRecord(service=_text(r.get("service")), plugin=_text(r.get("plugin")), node=_text(r.get("node")),
                            result=_text(r.get("result")), full_node_name=_text(r.get("full_node_name")),
                            error=_text(r.get("error")))
        for r in data
    )


def _text(value: Any) -> str | None:
    """A string field of a record as it reads in messages (None: absent or null)."""
    return None if value is None else str(value)


def _fqn(namespace: str, name: str) -> str:
    return ("/" if namespace in ("", "/") else namespace.rstrip("/") + "/") + name
