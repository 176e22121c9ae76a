"""Type tables (``model.types``) built from the real message packages of the venv: fields
through rosidl's generated Python classes (their SLOT_TYPES: element types, arrays, bounds),
constants from the installed ``.msg`` / ``.srv`` / ``.action`` files. The middleware records
the same from the C/C++ introspection type supports and the definition sources they carry;
the end-to-end test tests/middleware/test_type_descriptions.py checks that both agree (with
``python_class`` and ``field_of`` from here). Shared by tests/unit and tests/middleware."""

from __future__ import annotations

import importlib
import pkgutil
from pathlib import Path
from typing import Any

from rosidl_parser import definition

from pytest_rmw_introspect.model.types import Constant, Field, MessageType, ServiceType, TypeTable
from pytest_rmw_introspect.run import ros_env


def _share(pkg: str) -> Path:
    for prefix in ros_env.detect().ament_prefixes:
        if (Path(prefix) / "share" / pkg).is_dir():
            return Path(prefix) / "share" / pkg
    raise LookupError(f"package {pkg} is not installed")

_BASIC = {
    "boolean": "bool", "octet": "byte", "char": "char", "wchar": "wchar", "float": "float32",
    "double": "float64", "long double": "long_double",
}


def python_class(type_name: str) -> Any:
    """pkg/msg/X, pkg/srv/X, pkg/srv/X_Request, pkg/action/X_Goal ... -> the generated class."""
    pkg, kind, leaf = type_name.split("/")
    module = importlib.import_module(f"{pkg}.{kind}")
    if hasattr(module, leaf):
        return getattr(module, leaf)
    for info in pkgutil.iter_modules(module.__path__):
        sub = importlib.import_module(f"{pkg}.{kind}.{info.name}")
        if hasattr(sub, leaf):
            return getattr(sub, leaf)
    raise LookupError(type_name)


def field_of(name: str, slot: Any) -> Field:
    array = size = bound = None
    value = slot
    if isinstance(slot, definition.Array):
        array, size, value = "fixed", slot.size, slot.value_type
    elif isinstance(slot, definition.BoundedSequence):
        array, size, value = "bounded", slot.maximum_size, slot.value_type
    elif isinstance(slot, definition.UnboundedSequence):
        array, value = "unbounded", slot.value_type
    if isinstance(value, definition.NamespacedType):
        element = "/".join([*value.namespaces, value.name])
    elif isinstance(value, definition.AbstractGenericString):
        element = "wstring" if isinstance(value, definition.AbstractWString) else "string"
        bound = value.maximum_size if value.has_maximum_size() else None
    else:
        element = _BASIC.get(value.typename, value.typename)
    return Field(name=name, type=element, array=array, array_size=size, string_bound=bound)


_PARTS = {"srv": ("_Request", "_Response"), "action": ("_Goal", "_Result", "_Feedback")}


def definition_text(type_name: str) -> str:
    """The ``.msg`` text of a type, or its part of the ``.srv`` / ``.action`` file."""
    pkg, kind, leaf = type_name.split("/")
    share = _share(pkg) / kind
    if kind == "msg":
        return (share / f"{leaf}.msg").read_text()
    for index, suffix in enumerate(_PARTS[kind]):
        if leaf.endswith(suffix) and (share / f"{leaf[:-len(suffix)]}.{kind}").exists():
            text = (share / f"{leaf[:-len(suffix)]}.{kind}").read_text()
            parts = [[]]  # type: list[list[str]]
            for line in text.splitlines():
                if line.rstrip() == "---":
                    parts.append([])
                else:
                    parts[-1].append(line)
            return "\n".join(parts[index]) if index < len(parts) else ""
    return ""  # a type rosidl generates (SendGoal_Request, FeedbackMessage, ...): no constants


def constants_of(type_name: str) -> tuple[Constant, ...]:
    """``TYPE NAME=VALUE`` lines, comments cut at ``#``; a ``.msg`` char is a uint8."""
    constants = []
    for line in definition_text(type_name).replace("\t", " ").splitlines():
        line = line.split("#", 1)[0].strip()
        type_text, _, rest = line.partition(" ")
        name, equals, value = rest.partition("=")
        if equals and name.strip() and " " not in name.strip():
            constants.append(Constant(name.strip(), "uint8" if type_text == "char" else type_text, value.strip()))
    return tuple(constants)


def message_of(type_name: str) -> MessageType:
    cls = python_class(type_name)
    fields = tuple(field_of(n, s) for n, s in zip(cls.get_fields_and_field_types(), cls.SLOT_TYPES, strict=True))
    if not fields:  # rosidl's placeholder member of an empty message
        fields = (Field("structure_needs_at_least_one_member", "uint8"),)
    return MessageType(type_name, fields, constants_of(type_name))


def describe(*type_names: str) -> TypeTable:
    """The table of the given types (messages or services) and everything they nest."""
    table: TypeTable = {}

    def visit(name: str) -> None:
        if name in table:
            return
        cls = python_class(name)
        if hasattr(cls, "Request") and hasattr(cls, "Response"):
            table[name] = ServiceType(name, name + "_Request", name + "_Response")
        else:
            table[name] = message_of(name)
        for reference in table[name].references():
            visit(reference)

    for type_name in type_names:
        visit(type_name)
    return table
