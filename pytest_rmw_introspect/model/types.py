"""Type descriptions: what a message or service type is made of, in captures and contracts.

The middleware records every interface type a process uses, nested types included, in the
capture's ``types`` table (docs/design.md section 1): a message's fields in declaration
(= wire) order with their element type, array kind and bounds, and its constants; a service's
request and response message types. A contract may keep the same for its interfaces in a
generated ``types:`` section (section 2), so that a changed type hash can be explained field
by field (``compare.type_drift``).

In a contract a field is one line in ``.msg`` spelling, a constant too::

    types:
      test_msgs/msg/Bounded:
        fields:
          - string<=22[<=3] names          # bounded sequence of bounded strings
          - test_msgs/msg/BasicTypes[2] pair
          - int32[] values
        constants:
          - int32 LIMIT=3
      std_srvs/srv/SetBool:
        request: std_srvs/srv/SetBool_Request
        response: std_srvs/srv/SetBool_Response

Element types are the ``.msg`` ones (``bool``, ``byte``, ``char``, ``float32``, ``float64``,
``int8`` ... ``uint64``, ``string``, ``wstring``; ``wchar`` and ``long_double`` from ``.idl``),
nested types by full name. A ``.msg`` ``char`` is an IDL ``uint8`` and is written so, as the
type hash sees it. A message without ``constants`` has constants that are not known (a type
defined in ``.idl``); ``constants: []`` means it has none.

The section is generated: :func:`render_section` writes it deterministically (types sorted by
name) and :func:`replace_section` puts it into a contract's text, replacing the old one.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

from ..errors import SectionError
from . import yaml_blocks
from .vocabulary import ACTION_LISTS

#: ``kind`` values of the capture table
MESSAGE = "message"
SERVICE = "service"
#: array kinds: ``T[N]``, ``T[<=N]``, ``T[]``
FIXED, BOUNDED, UNBOUNDED = "fixed", "bounded", "unbounded"
ARRAY_KINDS = (FIXED, BOUNDED, UNBOUNDED)
#: the type-support types an action interface ``pkg/action/X`` is made of (its hashed parts)
ACTION_PART_SUFFIXES = ("_SendGoal", "_GetResult", "_FeedbackMessage")

SECTION_KEY = "types"
SECTION_COMMENT = (
    "# Generated with include_types: the definitions behind the type hashes above, so that a\n"
    "# changed hash is reported field by field. Rewritten by --update-golden.\n"
)

_TYPE_NAME = r"[A-Za-z][A-Za-z0-9_]*(?:/[A-Za-z0-9_]+)*"
_SPEC = re.compile(
    rf"^(?P<type>{_TYPE_NAME})(?:<=(?P<string_bound>[0-9]+))?"
    r"(?:\[(?P<bounded><=)?(?P<size>[0-9]*)\])?$"
)
_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
_FULL_TYPE_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*(/[A-Za-z0-9_]+)+$")


@dataclass(frozen=True)
class Field:
    """One field of a message type."""

    name: str
    type: str  # element type: a primitive or a nested type's full name
    array: str | None = None  # None (one value), "fixed", "bounded", "unbounded"
    array_size: int | None = None  # fixed: the size; bounded: the bound
    string_bound: int | None = None  # string / wstring elements: the bound

    @property
    def nested(self) -> bool:
        """The element type is a message type (``pkg/msg/X``)."""
        return "/" in self.type

    def spec(self) -> str:
        """The type in ``.msg`` spelling: ``string<=22[<=3]``."""
        text = self.type
        if self.string_bound:
            text += f"<={self.string_bound}"
        if self.array == FIXED:
            text += f"[{self.array_size}]"
        elif self.array == BOUNDED:
            text += f"[<={self.array_size}]"
        elif self.array == UNBOUNDED:
            text += "[]"
        return text

    def line(self) -> str:
        """``string<=22[<=3] names``: the field as a ``.msg`` line (and as a contract writes it)."""
        return f"{self.spec()} {self.name}"

    @classmethod
    def parse(cls, line: str) -> Field:
        """The inverse of :meth:`line` (ValueError for anything else)."""
        if not isinstance(line, str):
            raise ValueError(f"{line!r} is not a field line like `float64 x`")
        words = line.split()
        if len(words) != 2:
            raise ValueError(f"{line!r} is not a field line like `float64 x` or `string<=10[<=3] names`")
        spec, name = words
        if not _NAME.match(name):
            raise ValueError(f"{line!r}: {name!r} is not a field name")
        match = _SPEC.match(spec)
        if not match:
            raise ValueError(
                f"{line!r}: {spec!r} is not a field type like float64, string<=10, int32[3], "
                "pkg/msg/X[<=5] or uint8[]"
            )
        string_bound = int(match["string_bound"]) if match["string_bound"] else None
        if string_bound is not None and match["type"] not in ("string", "wstring"):
            raise ValueError(f"{line!r}: only string and wstring take a bound (<=N)")
        array: str | None = None
        size: int | None = None
        if match.group(0).endswith("]"):
            if match["bounded"]:
                if not match["size"]:
                    raise ValueError(f"{line!r}: a bounded sequence needs its bound, as in [<=5]")
                array, size = BOUNDED, int(match["size"])
            elif match["size"]:
                array, size = FIXED, int(match["size"])
            else:
                array = UNBOUNDED
        return cls(name=name, type=match["type"], array=array, array_size=size, string_bound=string_bound or None)


@dataclass(frozen=True)
class Constant:
    """One constant of a message type (``TYPE NAME=VALUE``, the value as written)."""

    name: str
    type: str
    value: str

    def line(self) -> str:
        return f"{self.type} {self.name}={self.value}"

    @classmethod
    def parse(cls, line: str) -> Constant:
        if not isinstance(line, str) or " " not in line.strip() or "=" not in line:
            raise ValueError(f"{line!r} is not a constant line like `int32 LIMIT=3`")
        type_name, rest = line.strip().split(None, 1)
        name, _, value = rest.partition("=")
        name = name.strip()
        if not _NAME.match(name):
            raise ValueError(f"{line!r}: {name!r} is not a constant name")
        if not _SPEC.match(type_name):
            raise ValueError(f"{line!r}: {type_name!r} is not a type")
        return cls(name=name, type=type_name, value=value.strip())


@dataclass(frozen=True)
class MessageType:
    """A message type: its fields in declaration order and its constants (None: not known)."""

    name: str
    fields: tuple[Field, ...] = ()
    constants: tuple[Constant, ...] | None = ()

    def references(self) -> list[str]:
        """Nested types, in order of first use."""
        return list(dict.fromkeys(f.type for f in self.fields if f.nested))


@dataclass(frozen=True)
class ServiceType:
    """A service type: its request and response message types."""

    name: str
    request: str
    response: str

    def references(self) -> list[str]:
        return [self.request, self.response]


TypeDescription = MessageType | ServiceType
TypeTable = dict[str, TypeDescription]


# ---------------------------------------------------------------------------- reading


def _int(value: Any, where: str) -> int | None:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise ValueError(f"{where}: {value!r} is not a non-negative integer")
    return value


#: the last entry read for each type name, and what it was read into: a session reads the same
#: descriptions (rcl_interfaces' for every node's parameter services) from every capture, and
#: comparing a JSON entry with the one read before is ~20x cheaper than reading it again
_READ: dict[str, tuple[Any, TypeDescription]] = {}
_READ_LIMIT = 4096


def from_capture(data: Any) -> TypeTable:
    """The capture's ``types`` table (ValueError naming the place of a malformed entry). An
    entry equal to one read before is replaced, in ``data`` too, by that one: the captures of a
    system share their type descriptions instead of holding a copy each (a talker's are ~60 KB
    decoded; 300 processes held 40 MB, issue 42)."""
    if data is None:
        return {}
    if not isinstance(data, Mapping):
        raise ValueError("`types` is not an object")
    table: TypeTable = {}
    for name, entry in data.items():
        known = _READ.get(name)
        if known is not None and known[0] == entry:
            table[name] = known[1]
            if isinstance(data, dict) and known[0] is not entry:
                data[name] = known[0]  # the same value: replacing a key's value keeps the iteration valid
            continue
        table[str(name)] = _entry_from_capture(name, entry)
        if len(_READ) >= _READ_LIMIT:
            _READ.clear()
        _READ[name] = (entry, table[str(name)])
    return table


def _entry_from_capture(name: Any, entry: Any) -> TypeDescription:
    where = f"types[{name!r}]"
    if not isinstance(entry, Mapping):
        raise ValueError(f"{where} is not an object")
    kind = entry.get("kind")
    if kind == SERVICE:
        request, response = entry.get("request"), entry.get("response")
        if not isinstance(request, str) or not isinstance(response, str):
            raise ValueError(f"{where}: a service needs `request` and `response` type names")
        return ServiceType(str(name), request, response)
    if kind != MESSAGE:
        raise ValueError(f"{where}: unknown kind {kind!r}")
    fields_data = entry.get("fields")
    if not isinstance(fields_data, list):
        raise ValueError(f"{where}: `fields` is not a list")
    fields = []
    for i, f in enumerate(fields_data):
        at = f"{where}.fields[{i}]"
        if not isinstance(f, Mapping) or not isinstance(f.get("name"), str) or not isinstance(f.get("type"), str):
            raise ValueError(f"{at}: needs a `name` and a `type`")
        array = f.get("array")
        if array is not None and array not in ARRAY_KINDS:
            raise ValueError(f"{at}: unknown array kind {array!r}")
        fields.append(Field(name=f["name"], type=f["type"], array=array,
                            array_size=_int(f.get("array_size"), at) if array in (FIXED, BOUNDED) else None,
                            string_bound=_int(f.get("string_bound"), at) or None))
    constants: tuple[Constant, ...] | None = None
    if entry.get("constants") is not None:
        if not isinstance(entry["constants"], list):
            raise ValueError(f"{where}: `constants` is not a list")
        items = []
        for i, c in enumerate(entry["constants"]):
            if not isinstance(c, Mapping) or not all(isinstance(c.get(k), str) for k in ("name", "type", "value")):
                raise ValueError(f"{where}.constants[{i}]: needs `name`, `type` and `value` strings")
            items.append(Constant(c["name"], c["type"], c["value"]))
        constants = tuple(items)
    return MessageType(str(name), tuple(fields), constants)


def from_contract(data: Any) -> TypeTable:
    """A contract's ``types:`` section (raises :class:`SectionError`)."""
    if data is None:
        return {}
    if not isinstance(data, Mapping):
        raise SectionError([SECTION_KEY], "`types` must be a mapping of type names to descriptions")
    table: TypeTable = {}
    for name, entry in data.items():
        where: list[Any] = [SECTION_KEY, name]
        if not isinstance(name, str) or not _FULL_TYPE_NAME.match(name):
            raise SectionError(where, f"{name!r} is not an interface type like std_msgs/msg/String")
        if not isinstance(entry, Mapping):
            raise SectionError(where, "a type needs `fields` (a message) or `request` and `response` (a service)")
        if "request" in entry or "response" in entry:
            if "fields" in entry or "constants" in entry:
                raise SectionError(where, "a type is a message (fields, constants) or a service "
                                          "(request, response), not both")
            for key in ("request", "response"):
                value = entry.get(key)
                if not isinstance(value, str) or not _FULL_TYPE_NAME.match(value):
                    raise SectionError(where + [key], f"a service needs its {key} message type, got {value!r}")
            table[name] = ServiceType(name, entry["request"], entry["response"])
            continue
        if not isinstance(entry.get("fields"), list):
            raise SectionError(where + ["fields"], "a message needs its `fields`, a list of lines like `float64 x`")
        fields = []
        for i, line in enumerate(entry["fields"]):
            try:
                fields.append(Field.parse(line))
            except ValueError as exc:
                raise SectionError(where + ["fields", i], str(exc)) from None
        names = [f.name for f in fields]
        duplicates = sorted({n for n in names if names.count(n) > 1})
        if duplicates:
            raise SectionError(where + ["fields"], f"field {duplicates[0]!r} appears twice")
        constants: tuple[Constant, ...] | None = None
        if "constants" in entry:
            if not isinstance(entry["constants"], list):
                raise SectionError(where + ["constants"], "`constants` is a list of lines like `int32 LIMIT=3`")
            items = []
            for i, line in enumerate(entry["constants"]):
                try:
                    items.append(Constant.parse(line))
                except ValueError as exc:
                    raise SectionError(where + ["constants", i], str(exc)) from None
            constants = tuple(items)
        table[name] = MessageType(name, tuple(fields), constants)
    return table


# ---------------------------------------------------------------------------- which types


def interface_roots(list_name: str, type_name: str) -> list[str]:
    """The described types an interface of ``list_name`` and ``type_name`` stands for: the
    type itself, or for an action its three definition-dependent parts."""
    if list_name in ACTION_LISTS:
        return [type_name + suffix for suffix in ACTION_PART_SUFFIXES]
    return [type_name]


def closure(table: Mapping[str, TypeDescription], roots: Iterable[str]) -> list[str]:
    """The names of ``roots`` and every type they refer to that ``table`` describes, in
    order of first reference (roots first, then depth first)."""
    seen: dict[str, None] = {}

    def visit(name: str) -> None:
        if name in seen or name not in table:
            return
        seen[name] = None
        for reference in table[name].references():
            visit(reference)

    for root in roots:
        visit(root)
    return list(seen)


def for_interfaces(table: Mapping[str, TypeDescription], interfaces: Iterable[tuple[str, str]]) -> TypeTable:
    """The part of ``table`` that ``(list_name, type_name)`` interfaces need, sorted by name."""
    roots = [root for list_name, type_name in interfaces for root in interface_roots(list_name, type_name)]
    return {name: table[name] for name in sorted(closure(table, roots))}


# ---------------------------------------------------------------------------- writing


def _scalar(text: str) -> str:
    """A YAML plain scalar when that reads back as the same string, else quoted."""
    import yaml  # ~20 ms: only writing a `types:` section needs it

    dumped = yaml.safe_dump(text, default_flow_style=True, width=math.inf, allow_unicode=True)
    dumped = dumped.rstrip("\n").removesuffix("\n...")
    if any(c in dumped for c in ",[]{}") and not dumped.startswith(("'", '"')):
        dumped = "'" + text.replace("'", "''") + "'"
    return dumped


def to_contract(table: Mapping[str, TypeDescription]) -> dict[str, Any]:
    """The section as plain data (what :func:`from_contract` reads)."""
    out: dict[str, Any] = {}
    for name in sorted(table):
        entry = table[name]
        if isinstance(entry, ServiceType):
            out[name] = {"request": entry.request, "response": entry.response}
        else:
            data: dict[str, Any] = {"fields": [f.line() for f in entry.fields]}
            if entry.constants is not None:
                data["constants"] = [c.line() for c in entry.constants]
            out[name] = data
    return out


def render_section(table: Mapping[str, TypeDescription]) -> str:
    """The ``types:`` block, deterministic: types by name, fields and constants in order."""
    lines = [SECTION_COMMENT.rstrip("\n"), f"{SECTION_KEY}:" if table else f"{SECTION_KEY}: {{}}"]
    for name, data in to_contract(table).items():
        lines.append(f"  {_scalar(name)}:")
        for key, value in data.items():
            if isinstance(value, list):
                if not value:
                    lines.append(f"    {key}: []")
                    continue
                lines.append(f"    {key}:")
                lines += [f"      - {_scalar(item)}" for item in value]
            else:
                lines.append(f"    {key}: {_scalar(value)}")
    return "\n".join(lines) + "\n"


def _section_span(text: str) -> tuple[int, int] | None:
    """Line numbers ``[start, end)`` of the top-level ``types`` block of ``text`` (with the
    comment lines directly above its key), or None when there is none."""
    block = yaml_blocks.top_level_block(text, SECTION_KEY)
    if block is None:
        return None
    lines, start, end = block
    while start > 0 and lines[start - 1].startswith("#"):
        start -= 1
    return start, end


def replace_section(text: str, table: Mapping[str, TypeDescription]) -> str:
    """``text`` (a contract) with its ``types:`` block replaced by :func:`render_section`, or
    the block appended at the end (after a blank line) when it has none. Everything else is
    kept byte for byte; comments inside the block are not."""
    block = render_section(table)
    span = _section_span(text)
    if span is None:
        if text and not text.endswith("\n"):
            text += "\n"
        return text + ("\n" if text.strip() else "") + block
    lines = text.splitlines(keepends=True)
    start, end = span
    return "".join(lines[:start]) + block + "".join(lines[end:])
