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
"""

from __future__ import annotations

import xml.parsers.expat
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml


class EntityFormatError(Exception):
    """A launch file that is not well-formed; ``line`` when known."""

    def __init__(self, reason: str, line: int | None = None) -> None:
        self.reason = reason
        self.line = line
        super().__init__(reason)


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
    loader = yaml.SafeLoader(text)
    try:
        node = loader.get_single_node()
        if node is None:
            raise EntityFormatError("the file is empty")
        if not isinstance(node, yaml.MappingNode) or len(node.value) != 1:
            raise EntityFormatError("a YAML launch file is a mapping with the one key `launch`", _line(node))
        key, value = node.value[0]
        tag = normalize(str(loader.construct_object(key, deep=True)))
        if tag != "launch":
            raise EntityFormatError(f"a YAML launch file starts with `launch:`, not `{tag}:`", _line(key))
        return Entity("launch", {}, _entity_list(loader, value), line=_line(key))
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        reason = " ".join(p for p in (exc.context, exc.problem) if p)
        raise EntityFormatError(f"YAML syntax error: {reason}", mark.line + 1 if mark else None) from None
    except yaml.YAMLError as exc:
        raise EntityFormatError(f"YAML error: {exc}") from None
    finally:
        loader.dispose()


def _line(node: yaml.Node) -> int:
    return node.start_mark.line + 1


def _entity_list(loader: yaml.SafeLoader, node: yaml.Node) -> list[Entity]:
    """A list of one-key mappings (``- node: {...}``) → entities."""
    if isinstance(node, yaml.ScalarNode) and node.value in ("", "null", "~"):
        return []
    if not isinstance(node, yaml.SequenceNode):
        raise EntityFormatError("expected a list of entities (`- node: ...`)", _line(node))
    out = []
    for item in node.value:
        if not isinstance(item, yaml.MappingNode) or len(item.value) != 1:
            raise EntityFormatError("each entity is a mapping with one key, its tag (`- node: {...}`)", _line(item))
        key, value = item.value[0]
        out.append(_entity(loader, normalize(str(loader.construct_object(key, deep=True))), value, _line(key)))
    return out


def _entity(loader: yaml.SafeLoader, tag: str, node: yaml.Node, line: int) -> Entity:
    entity = Entity(tag, {}, line=line)
    if isinstance(node, yaml.ScalarNode) and node.value in ("", "null", "~"):
        return entity
    if not isinstance(node, yaml.MappingNode):
        raise EntityFormatError(f"`{tag}` takes a mapping of attributes", _line(node))
    for key_node, value in node.value:
        key = normalize(str(loader.construct_object(key_node, deep=True)))
        if key == "children":
            entity.children += _entity_list(loader, value)
        elif isinstance(value, yaml.SequenceNode) and value.value and all(
                isinstance(v, yaml.MappingNode) for v in value.value):
            entity.children += [_entity(loader, key, v, _line(v)) for v in value.value]
        else:
            entity.attributes[key] = loader.construct_object(value, deep=True)
    return entity


def parse_file(path: Path) -> Entity:
    """The root entity of ``path`` by its suffix: ``.xml`` or ``.yaml``/``.yml``
    (raises EntityFormatError, OSError)."""
    text = path.read_text(encoding="utf-8")
    name = path.name
    if name.endswith(".xml"):
        return parse_xml(text)
    if name.endswith((".yaml", ".yml")):
        return parse_yaml(text)
    raise EntityFormatError(f"unknown launch file type {path.suffix!r} (expected .xml, .yaml, .yml or .py)")
