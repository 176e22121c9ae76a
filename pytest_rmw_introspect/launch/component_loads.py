"""The components a launch file loads into a container, handed to the container's middleware.

A launch file loads components by calling the container's ``~/_container/load_node`` service
(composition_interfaces/srv/LoadNode) from the ``ros2 launch`` process, over DDS. A capture has
no DDS between processes, so the recording middleware in the container process sends the same
requests to the container's own service itself, as it asks nodes' own parameter services
(``rmw_introspect_cpp``: ComponentLoadPlan through the Injector), before it reads parameters:
the component nodes are then nodes of the container process, probed like any other.

:func:`requests_text` writes the requests in the middleware's format (``RMW_INTROSPECT_LOAD_NODES``
names the file; rmw_introspect_cpp/src/detail/component_loads.hpp describes it);
:func:`problems` says which loads created no node, from what a capture's records say they came to
(``Capture.component_loads``, read by ``model.capture_file``).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from .result import ComponentLoad, ComponentParameter

if TYPE_CHECKING:
    from ..model.capture_file import ComponentLoadRecord

#: the variable that names the requests file
VARIABLE = "RMW_INTROSPECT_LOAD_NODES"


def service_of(container_fqn: str) -> str:
    """The load service of the container node ``container_fqn``."""
    return container_fqn.rstrip("/") + "/_container/load_node"


def _field(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    text = repr(value) if isinstance(value, float) else str(value)
    return text.replace("\\", "\\\\").replace("\t", "\\t").replace("\n", "\\n")


def _line(*fields: Any) -> str:
    return "\t".join(_field(f) for f in fields) + "\n"


def _parameter(key: str, parameter: ComponentParameter) -> str:
    name, kind, value = parameter
    values = list(value) if kind >= 6 else [value]
    return _line(key, name, kind, *values)


def requests_text(container_fqn: str, loads: Sequence[ComponentLoad]) -> str:
    """The LoadNode requests of ``loads`` for the container ``container_fqn``."""
    out = ["# LoadNode requests for the component container " + container_fqn.replace("\n", " ") + "\n"]
    for load in loads:
        out.append(_line("load", service_of(container_fqn)))
        out.append(_line("package_name", load.package))
        out.append(_line("plugin_name", load.plugin))
        if load.name is not None:
            out.append(_line("node_name", load.name))
        if load.namespace is not None:
            out.append(_line("node_namespace", load.namespace))
        out.append(_line("log_level", load.log_level))
        out += [_line("remap_rule", rule) for rule in load.remap_rules]
        out += [_parameter("parameter", p) for p in load.parameters]
        out += [_parameter("extra_argument", p) for p in load.extra_arguments]
        out.append("end\n")
    return "".join(out)


def problems(records: Sequence[ComponentLoadRecord],
             loads: Sequence[ComponentLoad]) -> list[tuple[ComponentLoad, str]]:
    """Each load of ``loads`` that did not create its node, with why, from the container's
    capture ``records`` (``Capture.component_loads``, in the same order)."""
    out: list[tuple[ComponentLoad, str]] = []
    for index, load in enumerate(loads):
        record = records[index] if index < len(records) else None
        if record is None:
            out.append((load, "the container's middleware never sent the request (it ended first, or read no "
                              f"request: is {VARIABLE} set?)"))
            continue
        result = record.result
        if result == "loaded":
            continue
        why = {
            "refused": "the container refused it: {error}",
            "no_answer": "the container did not answer the load request: {error}",
            "no_service": "{error}",
            "failed": "the load request could not be sent: {error}",
            "pending": "the process ended before the load request was sent",
        }.get(str(result), "unknown result {result!r}: {error}")
        out.append((load, why.format(error=record.error or "no reason given", result=result)))
    return out
