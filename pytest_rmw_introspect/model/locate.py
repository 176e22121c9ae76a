"""Where things are written in a YAML file: the node and line at a path of keys and list indices
(for the errors of every loader), and the line of each node and interface entry of a contract, for
annotations that point at the contract (``--format github``)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import yaml

from .vocabulary import LISTS, PARAMETERS

#: (node, list name, "parameters" or "node", interface or parameter name) → 1-based line
LineIndex = dict[tuple[str, str, str], int]


def _scalar(node: yaml.Node) -> str | None:
    return node.value if isinstance(node, yaml.ScalarNode) else None


def _child(mapping: yaml.Node, key: str) -> yaml.Node | None:
    if not isinstance(mapping, yaml.MappingNode):
        return None
    for k, v in mapping.value:
        if _scalar(k) == key:
            child: yaml.Node = v
            return child
    return None


def node_at(root: yaml.Node | None, path: Sequence[Any]) -> yaml.Node | None:
    """The YAML node at ``path`` (mapping keys and list indices) under ``root``, or the deepest
    ancestor of it that exists."""
    node = root
    for part in path:
        if isinstance(node, yaml.MappingNode):
            found = _child(node, str(part))
            if found is None:
                return node
            node = found
        elif isinstance(node, yaml.SequenceNode) and isinstance(part, int) and 0 <= part < len(node.value):
            node = node.value[part]
        else:
            return node
    return node


def line_at(root: yaml.Node | None, path: Sequence[Any], first: int = 1) -> int | None:
    """The line of :func:`node_at` (``first``: the number of the text's first line)."""
    node = node_at(root, path)
    return node.start_mark.line + first if node is not None else None


def line_index(text: str) -> LineIndex:
    """The lines of every node, interface and parameter entry of a contract's text (empty when
    the text does not parse: annotations then point at the file)."""
    try:
        root = yaml.compose(text, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))
    except yaml.YAMLError:
        return {}
    index: LineIndex = {}
    nodes = _child(root, "nodes") if root is not None else None
    if not isinstance(nodes, yaml.MappingNode):
        return index
    for key, node in nodes.value:
        fqn = _scalar(key)
        if fqn is None:
            continue
        index[(fqn, "node", fqn)] = key.start_mark.line + 1
        for list_name in (*LISTS, PARAMETERS):
            entries = _child(node, list_name)
            if not isinstance(entries, yaml.SequenceNode):
                continue
            for entry in entries.value:
                name_node = _child(entry, "name")
                name = _scalar(name_node) if name_node is not None else None
                if name is not None:
                    index.setdefault((fqn, list_name, name), entry.start_mark.line + 1)
    return index


def line_of(index: LineIndex, node: str, kind: str, name: str) -> int | None:
    """The line of an interface entry, else of its node, else None."""
    return index.get((node, kind, name)) or index.get((node, "node", node))
