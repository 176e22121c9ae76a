"""Components of XML and YAML launch files as the LoadNode requests launch_ros makes of them.

``<node_container>`` and ``<load_composable_node>`` hold ``<composable_node>`` entries; launch_ros
turns each into a composition_interfaces/srv/LoadNode request (``get_composable_node_load_request``):
the namespace below the scope's, the scope's ``<set_remap>`` rules before the component's own
``<remap>``, and the scope's ``<set_parameter>``/``<set_parameters_from_file>`` parameters before
its own ``<param>`` entries, every parameter typed (rcl_interfaces/msg/ParameterType). A
parameters file gives a component only two of its sections, ``/**`` and the one keyed by the
component's exact full name (launch_ros's ``to_parameters_list``; rclcpp's wildcards such as
``/**/talker`` reach a process, never a component).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ..errors import ComponentParameterError
from ..model import untrusted
from ..model.parameters import flatten
from .result import ComponentParameter, LaunchParameter


def typed(name: str, value: Any) -> ComponentParameter:
    """``value`` with its rcl_interfaces/msg/ParameterType number, as rclpy types it."""
    if isinstance(value, bool):
        return (name, 1, value)
    if isinstance(value, int):
        return (name, 2, value)
    if isinstance(value, float):
        return (name, 3, value)
    if isinstance(value, str):
        return (name, 4, value)
    if isinstance(value, (list, tuple)):
        items = list(value)
        for kind, types in ((6, (bool,)), (7, (int,)), (8, (float, int)), (9, (str,))):
            if all(isinstance(i, types) and (kind == 6 or not isinstance(i, bool)) for i in items):
                return (name, kind, tuple(float(i) if kind == 8 else i for i in items))
    raise ComponentParameterError(f"parameter `{name}`: {value!r} is no parameter value (a bool, integer, float, "
                                  "string, or a list of one of those)")


def file_sections(path: Path) -> dict[str, dict[str, Any]]:
    """A parameters file's node sections, keyed as launch_ros keys them (namespaces and node
    name joined with ``/``, without a leading one), each with its flattened parameters."""
    root = untrusted.compose_yaml(untrusted.read_text(path))
    if root is None:
        return {}
    untrusted.check_tree(root)
    data = untrusted.construct(root)
    found: dict[str, dict[str, Any]] = {}

    def walk(mapping: Mapping[str, Any], keys: list[str]) -> None:
        for key, value in mapping.items():
            if key == "ros__parameters" and isinstance(value, Mapping):
                found["/".join(keys)] = flatten(value)
                return
            if isinstance(value, Mapping):
                walk(value, [*keys, str(key).lstrip("/")])

    if isinstance(data, Mapping):
        walk(data, [])
    return found


def parameters(given: Sequence[LaunchParameter], name: str, namespace: str | None) -> tuple[ComponentParameter, ...]:
    """The LoadNode parameters of the component ``namespace``/``name`` from ``given`` (values and
    parameters files, in order; raises ComponentParameterError, OSError, InputError)."""
    full = f"{namespace.strip('/')}/{name}" if namespace and namespace != "/" else name
    merged: dict[str, Any] = {}
    for parameter in given:
        if parameter.name is not None:
            merged[parameter.name] = parameter.value
        elif parameter.file is not None:
            sections = file_sections(parameter.file)
            merged.update(sections.get("**", {}))
            merged.update(sections.get(full, {}))
    return tuple(typed(key, value) for key, value in merged.items())
