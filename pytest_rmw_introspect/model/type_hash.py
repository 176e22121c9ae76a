"""RIHS01 type hashes (REP-2011) of message types, computed from their descriptions.

A type hash is SHA-256 over a canonical JSON text of the type's description and the
descriptions of every type it nests (``type_description_interfaces/TypeDescription``, field
default values left out), so it changes exactly when the type or one of its nested types
changes on the wire. The middleware records the hash of each interface's own type; the hashes of
the nested types (``std_msgs/msg/Header`` inside ``sensor_msgs/msg/Image``) are computed here
from a ``types:`` table, which is what ``rmw-introspect lock`` pins and ``check`` compares.
``tests/unit/test_type_lock.py`` checks the result against the hashes rosidl generated for
every message type of the installed ROS 2 packages.

Only message types are hashed here: a service's hash also covers its event message, which a
``types:`` table does not describe (the middleware records the service's own hash).
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping
from typing import Any

from ..errors import UnhashableType
from .types import BOUNDED, FIXED, UNBOUNDED, Field, MessageType, TypeDescription, closure

PREFIX = "RIHS01_"

#: ``type_description_interfaces/msg/FieldType`` ids of the element types (a ``.msg`` char is uint8)
_TYPE_IDS = {
    "int8": 2, "uint8": 3, "char": 3, "int16": 4, "uint16": 5, "int32": 6, "uint32": 7, "int64": 8, "uint64": 9,
    "float32": 10, "float64": 11, "long_double": 12, "wchar": 14, "bool": 15, "byte": 16,
    "string": 17, "wstring": 18,
}
_NESTED = 1
_BOUNDED_STRING = {"string": 21, "wstring": 22}
#: what an array layout adds to the element's id
_ARRAY_OFFSET = {None: 0, FIXED: 48, BOUNDED: 96, UNBOUNDED: 144}


def _field_type(field: Field) -> dict[str, Any]:
    if field.nested:
        element = _NESTED
    elif field.string_bound and field.type in _BOUNDED_STRING:
        element = _BOUNDED_STRING[field.type]
    elif field.type in _TYPE_IDS:
        element = _TYPE_IDS[field.type]
    else:
        raise UnhashableType(f"field {field.name}: unknown element type {field.type!r}")
    return {
        "type_id": element + _ARRAY_OFFSET[field.array],
        "capacity": field.array_size if field.array in (FIXED, BOUNDED) and field.array_size else 0,
        "string_capacity": field.string_bound or 0,
        "nested_type_name": field.type if field.nested else "",
    }


def _description(message: MessageType) -> dict[str, Any]:
    return {"type_name": message.name,
            "fields": [{"name": f.name, "type": _field_type(f)} for f in message.fields]}


def message_hash(table: Mapping[str, TypeDescription], name: str) -> str:
    """The RIHS01 hash of the message type ``name`` as ``table`` describes it (raises
    UnhashableType when it, or a type it nests, is not a message type the table describes)."""
    names = closure(table, [name])
    if name not in names:
        raise UnhashableType(f"{name} is not described")
    described = []
    for each in names:
        entry = table[each]
        if not isinstance(entry, MessageType):
            raise UnhashableType(f"{each} is not a message type")
        missing = [r for r in entry.references() if r not in table]
        if missing:
            raise UnhashableType(f"{each} nests {missing[0]}, which is not described")
        described.append(entry)
    referenced = sorted((m for m in described if m.name != name), key=lambda m: m.name)
    document = {"type_description": _description(table[name]),  # type: ignore[arg-type]
                "referenced_type_descriptions": [_description(m) for m in referenced]}
    text = json.dumps(document, ensure_ascii=True, allow_nan=False, separators=(", ", ": "))
    return PREFIX + hashlib.sha256(text.encode("utf-8")).hexdigest()


def message_hashes(table: Mapping[str, TypeDescription]) -> dict[str, str]:
    """The hash of every message type of ``table`` that can be hashed, by name."""
    out: dict[str, str] = {}
    for name, entry in table.items():
        if isinstance(entry, MessageType):
            try:
                out[name] = message_hash(table, name)
            except UnhashableType:
                continue
    return out
