"""Launch files (XML and YAML) as one tree of :class:`Entity` objects with file and line.

Both front ends of ROS 2 launch describe the same entities: a tag (``node``, ``group``,
``include``, ...), attributes, and children. Tag and attribute names are normalised to
underscores (``push-ros-namespace`` and ``push_ros_namespace`` are the same tag), as the
launch front ends accept both spellings.

XML: ``<launch>`` root; attributes are strings; child elements are children.

YAML: ``launch:`` holds a list of one-key mappings (``- node: {...}``). In an entity's mapping,
a key whose value is a list of mappings (``param:``, ``remap:``, ``env:``, ``arg:``) gives one
child per item with that key as tag; ``children:`` (of a ``group``) holds one-key mappings
like the root; other values are attributes, typed as YAML reads them.

Launch files may come from anywhere, so they are read like contracts (``model.untrusted``): a
regular UTF-8 file of at most :data:`MAX_FILE_BYTES`, YAML through the same bounded reader
(control characters, nesting, alias bombs, non-string keys refused with a reason and a line),
and XML elements nested at most :data:`MAX_DEPTH` deep.
"""

from __future__ import annotations

import xml.parsers.expat
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from ..errors import EntityFormatError, InputError
from ..model import untrusted

#: the largest launch file read (real ones are a few kB)
MAX_FILE_BYTES = 8 * 1024 * 1024
#: the deepest nesting of XML elements and of YAML mappings and lists (the contract loader's)
MAX_DEPTH = untrusted.MAX_DEPTH
#: the most values a YAML launch file may expand to through aliases
MAX_VALUES = 100_000


@dataclass
class Entity:
    tag: str
    attributes: dict[str, Any]
    children: list[Entity] = field(default_factory=list)
    line: int | None = None

    def attribute_names(self) -> set[str]:
        return set(self.attributes)


def normalize(name: str) -> str:
    return name.replace("-", "_")


# ---------------------------------------------------------------------------- XML


def parse_xml(text: str) -> Entity:
    """The root entity of an XML launch file (raises EntityFormatError)."""
    parser = xml.parsers.expat.ParserCreate()
    stack: list[Entity] = []
    root: list[Entity] = []

    def start(name: str, attrs: dict[str, str]) -> None:
        if len(stack) >= MAX_DEPTH:
            raise EntityFormatError(f"elements nested more than {MAX_DEPTH} levels deep", parser.CurrentLineNumber)
        entity = Entity(normalize(name), {normalize(k): v for k, v in attrs.items()},
                        line=parser.CurrentLineNumber)
        if stack:
            stack[-1].children.append(entity)
        else:
            root.append(entity)
        stack.append(entity)

    def end(name: str) -> None:
        stack.pop()

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    try:
        parser.Parse(text, True)
    except xml.parsers.expat.ExpatError as exc:
        raise EntityFormatError(f"not well-formed XML: {xml.parsers.expat.ErrorString(exc.code)}",
                                exc.lineno) from None
    if not root:
        raise EntityFormatError("the file has no root element")
    return root[0]


# ---------------------------------------------------------------------------- YAML


def parse_yaml(text: str) -> Entity:
    """The root entity of a YAML launch file (raises EntityFormatError)."""
    try:
        node = untrusted.compose_yaml(text)
        if node is None:
            raise EntityFormatError("the file is empty")
        untrusted.check_tree(node, max_values=MAX_VALUES)  # keys are strings from here on
        if not isinstance(node, yaml.MappingNode) or len(node.value) != 1:
            raise EntityFormatError("a YAML launch file is a mapping with the one key `launch`", _line(node))
        key, value = node.value[0]
        tag = normalize(key.value)
        if tag != "launch":
            raise EntityFormatError(f"a YAML launch file starts with `launch:`, not `{untrusted.shorten(tag)}:`",
                                    _line(key))
        return Entity("launch", {}, _entity_list(value), line=_line(key))
    except InputError as exc:
        raise EntityFormatError(exc.reason, exc.line) from None


def _line(node: yaml.Node) -> int:
    return int(node.start_mark.line) + 1


def _is_null(node: yaml.Node) -> bool:
    return isinstance(node, yaml.ScalarNode) and node.value in ("", "null", "~")


def _entity_list(node: yaml.Node) -> list[Entity]:
    """A list of one-key mappings (``- node: {...}``) → entities."""
    if _is_null(node):
        return []
    if not isinstance(node, yaml.SequenceNode):
        raise EntityFormatError("expected a list of entities (`- node: ...`)", _line(node))
    out = []
    for item in node.value:
        if not isinstance(item, yaml.MappingNode) or len(item.value) != 1:
            raise EntityFormatError("each entity is a mapping with one key, its tag (`- node: {...}`)", _line(item))
        key, value = item.value[0]
        out.append(_entity(normalize(key.value), value, _line(key)))
    return out


def _entity(tag: str, node: yaml.Node, line: int) -> Entity:
    entity = Entity(tag, {}, line=line)
    if _is_null(node):
        return entity
    if not isinstance(node, yaml.MappingNode):
        raise EntityFormatError(f"`{untrusted.shorten(tag)}` takes a mapping of attributes", _line(node))
    for key_node, value in node.value:
        key = normalize(key_node.value)
        if key == "children":
            entity.children += _entity_list(value)
        elif isinstance(value, yaml.SequenceNode) and value.value and all(isinstance(v, yaml.MappingNode) for v in value.value):
            entity.children += [_entity(key, v, _line(v)) for v in value.value]
        else:
            entity.attributes[key] = untrusted.construct(value)
    return entity


def yaml_value(text: str) -> Any:
    """A parameter value written as YAML (``[1, 2]``, ``true``, ``3.5``) as launch_ros types it:
    a scalar or a list, else the text itself. Read like a launch file (raises ValueError for
    an alias bomb or a list nested too deep)."""
    try:
        root = untrusted.compose_yaml(text)
    except InputError:
        return text
    if root is None:
        return text
    try:
        untrusted.check_tree(root, max_values=MAX_VALUES)
    except InputError as exc:
        if isinstance(root, yaml.MappingNode):  # a mapping is no parameter value anyway
            return text
        raise ValueError(f"the value {untrusted.shorten(text)} cannot be read: {exc.reason}") from None
    try:
        loaded = untrusted.construct(root)
    except InputError:
        return text
    return loaded if isinstance(loaded, (str, int, float, bool, list)) else text


def parse_file(path: Path) -> Entity:
    """The root entity of ``path`` by its suffix: ``.xml`` or ``.yaml``/``.yml``
    (raises EntityFormatError, FileNotFoundError)."""
    name = path.name
    if not name.endswith((".xml", ".yaml", ".yml")):
        raise EntityFormatError(f"unknown launch file type {path.suffix!r} (expected .xml, .yaml, .yml or .py)")
    try:
        text = untrusted.read_text(path, max_bytes=MAX_FILE_BYTES)
    except InputError as exc:
        raise EntityFormatError(exc.reason) from None
    return parse_xml(text) if name.endswith(".xml") else parse_yaml(text)
