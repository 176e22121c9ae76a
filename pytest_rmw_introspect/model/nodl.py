"""NoDL v2 node documents (ros-tooling/nodl) as contracts, and contracts written as NoDL.

A NoDL document describes one node's public interface: ``parameters`` (keyed by name, in
generate_parameter_library's shape), ``publishers``, ``subscriptions`` (name, type, qos),
``service_servers``, ``service_clients`` (name, type, optional qos) and ``action_servers``,
``action_clients`` (name, type). It does not name its node: NoDL takes the node's identity from
the package and the file. So a document is bound to a node by a ``# node: /fqn`` comment above
it (``rmw-introspect capture --format nodl`` writes one per document, so a YAML stream of
several documents describes several nodes), else by the checked target when it creates exactly
one node; without a capture (``diff``, ``compat``) it is the node ``/<file stem>``
(``camera.nodl.yaml`` → ``/camera``). Relative names (``chatter``, ``~/status``) are resolved
against that node.

Reading checks what this module needs (the keys, the names and types, the QoS values), then
NoDL's own JSON Schema when it is found (:func:`schema_directory`): never a copy of it, but the
one of the user's NoDL install (the ``nodl_schema`` Python package) or a directory named by
``RMW_INTROSPECT_NODL_SCHEMA``. A document is compared with the same rules as a contract;
what NoDL cannot express is not compared and said so (:data:`NOT_EXPRESSIBLE`, ``notes``):
type hashes, the lifecycle state, parameter ranges and dynamic typing, service QoS. Keys a
document leaves out (a QoS policy, a parameter's default value, description or read-only flag)
are not compared either: :func:`project` cuts the capture down to what the document states.
"""

from __future__ import annotations

import functools
import importlib.util
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import ContractError
from . import parameters as parameter_model
from . import qos as qos_module
from . import untrusted
from .vocabulary import ACTION_LISTS, LIFECYCLE, LISTS, PARAMETER_TYPES, PARAMETERS, TOPIC_LISTS

VERSION = 2
#: ``RMW_INTROSPECT_NODL_SCHEMA``: a directory with ``nodl.schema.yaml``, or a NoDL source checkout
SCHEMA_ENV = "RMW_INTROSPECT_NODL_SCHEMA"
SCHEMA_FILES = ("nodl.schema.yaml", "parameter.schema.yaml")
#: the top-level keys of a NoDL v2 document
TOP_KEYS = ("nodl_version", "description", "codegen", "include", PARAMETERS, *LISTS)
#: the keys of a parameter, an endpoint, a QoS profile in NoDL v2
PARAMETER_KEYS = ("type", "default_value", "description", "read_only", "additional_constraints", "validation")
ENDPOINT_KEYS = ("name", "type", "qos", "description")
QOS_KEYS = ("history", "depth", "reliability", "durability", "deadline_ns", "lifespan_ns", "liveliness",
            "liveliness_lease_duration_ns")
NOT_EXPRESSIBLE = ("type hashes", "lifecycle states", "parameter ranges and dynamic typing",
                   "service QoS", "avoid_ros_namespace_conventions")
#: what a contract's parameter entry states that NoDL has no field for
_PARAMETER_ONLY_HERE = ("dynamic_typing", "integer_range", "floating_point_range", "declared_in")
#: parameter types, this tool's spelling → NoDL's (generate_parameter_library's); the others are the same
_TO_NODL_TYPE = {"integer": "int", "integer_array": "int_array"}
_FROM_NODL_TYPE = {v: k for k, v in _TO_NODL_TYPE.items()}
_FIXED_TYPE = re.compile(r"^(string|int_array|double_array|string_array)_fixed_[1-9][0-9]*$")
_NODE_COMMENT = re.compile(r"^#\s*node:\s*(\S+)\s*$")
_NODE_NAME = re.compile(r"^(/[A-Za-z_][A-Za-z0-9_]*)+$")
_ROS_NAME = re.compile(r"^[A-Za-z]$|^[/~A-Za-z][A-Za-z0-9_/]*[A-Za-z0-9_]$")
_ROS_TYPE = re.compile(r"^([a-zA-Z][a-zA-Z0-9_]*)(?:/(msg|srv|action))?/([A-Z][a-zA-Z0-9]*)$")
_INTERFACE_KIND = {**dict.fromkeys(TOPIC_LISTS, "msg"), "service_servers": "srv", "service_clients": "srv",
                   **dict.fromkeys(ACTION_LISTS, "action")}


def is_nodl(text: str, path: Path | None = None) -> bool:
    """A NoDL document: a ``*.nodl.yaml`` / ``.yml`` / ``.json`` file, or a text with a top-level
    ``nodl_version`` key (NoDL asks tools not to rely on the file name)."""
    if path is not None and re.search(r"\.nodl\.(ya?ml|json)$", path.name):
        return True
    return re.search(r'^(\{\s*)?"?nodl_version"?\s*:', text, re.MULTILINE) is not None


# ---------------------------------------------------------------------------- the schema


def schema_directory() -> tuple[Path | None, str]:
    """Where NoDL's schema files are, and how that was decided (for notes): ``RMW_INTROSPECT_
    NODL_SCHEMA`` (the schemas directory or a NoDL source checkout), else the installed
    ``nodl_schema`` package (found without importing it)."""
    given = os.environ.get(SCHEMA_ENV)
    if given:
        for candidate in (Path(given), Path(given) / "nodl_schema" / "nodl_schema" / "schemas"):
            if (candidate / SCHEMA_FILES[0]).is_file():
                return candidate, f"{SCHEMA_ENV}={given}"
        return None, f"{SCHEMA_ENV}={given} holds no {SCHEMA_FILES[0]}"
    try:
        spec = importlib.util.find_spec("nodl_schema")
    except (ImportError, ValueError):
        spec = None
    for location in (spec.submodule_search_locations or []) if spec is not None else []:
        if (Path(location) / "schemas" / SCHEMA_FILES[0]).is_file():
            return Path(location) / "schemas", "the installed nodl_schema package"
    return None, "no nodl_schema package is installed and RMW_INTROSPECT_NODL_SCHEMA is not set"


@functools.lru_cache(maxsize=4)
def _validator(directory: Path) -> Any:
    # jsonschema (~80 ms) and referencing only when a NoDL document is validated
    import jsonschema
    import referencing
    import referencing.jsonschema
    import yaml

    documents = {name: yaml.safe_load((directory / name).read_text(encoding="utf-8")) for name in SCHEMA_FILES}
    draft7 = referencing.jsonschema.DRAFT7
    registry: Any = referencing.Registry().with_resources(
        (name, referencing.Resource.from_contents(document, default_specification=draft7))
        for name, document in documents.items())
    return jsonschema.Draft7Validator(documents[SCHEMA_FILES[0]], registry=registry)


def schema_problem(document: Any, directory: Path) -> tuple[list[Any], str] | None:
    """The first violation of NoDL's schema in ``document``: (place, message), or None."""
    import jsonschema

    errors = list(_validator(directory).iter_errors(document))
    if not errors:
        return None
    best = jsonschema.exceptions.best_match(errors)
    return list(best.absolute_path), f"{best.message} (NoDL's schema, {directory})"


# ---------------------------------------------------------------------------- reading


@dataclass
class Document:
    """One NoDL document of a file, as written."""

    data: dict[str, Any]
    node: str | None  # the ``# node:`` comment's node, or None
    first_line: int  # of the document in the file (1-based)
    root: Any = None  # the YAML node tree, for line numbers


@dataclass
class NodlSource:
    """What a NoDL file adds to the contract read from it."""

    documents: list[Document]
    default_node: str  # the node of a document that names none, until a capture binds it
    notes: list[str] = field(default_factory=list)

    @property
    def unnamed(self) -> bool:
        """One document that names no node: it describes the target's one node."""
        return len(self.documents) == 1 and self.documents[0].node is None

    def nodes(self, bound: str | None = None) -> dict[str, dict[str, Any]]:
        """The documents as contract ``nodes`` (the unnamed one as ``bound``, when given)."""
        out: dict[str, dict[str, Any]] = {}
        for doc in self.documents:
            fqn = doc.node or bound or self.default_node
            out[fqn] = to_contract_node(doc.data, fqn)
        return out


    def lines(self, bound: str | None = None) -> dict[tuple[str, str, str], int]:
        """Where each node, endpoint and parameter is written (``model.locate.LineIndex``), for
        annotations on the document's lines."""
        index: dict[tuple[str, str, str], int] = {}
        for doc in self.documents:
            fqn = doc.node or bound or self.default_node
            index[(fqn, "node", fqn)] = doc.first_line
            for list_name in LISTS:
                for i, entry in enumerate(doc.data.get(list_name) or ()):
                    line = _line(doc.root, [list_name, i], doc.first_line)
                    if line is not None:
                        index.setdefault((fqn, list_name, resolve_name(entry["name"], fqn)), line)
            for name, line in _key_lines(doc.root, PARAMETERS, doc.first_line).items():
                index.setdefault((fqn, PARAMETERS, name), line)
        return index


def _split(text: str) -> list[tuple[int, str, str | None]]:
    """The documents of a YAML stream: (first line, text, the ``# node:`` comment's node)."""
    parts: list[tuple[int, list[str]]] = [(1, [])]
    for number, line in enumerate(text.splitlines(keepends=True), start=1):
        if re.match(r"^---(\s|$)", line):
            parts.append((number + 1, []))
        elif re.match(r"^\.\.\.(\s|$)", line):
            continue
        else:
            parts[-1][1].append(line)
    out = []
    pending: str | None = None  # a `# node:` comment before the `---` of its document
    for first, lines in parts:
        body = "".join(lines)
        named = [m.group(1) for m in (_NODE_COMMENT.match(line.strip()) for line in lines) if m]
        if any(line.strip() and not line.lstrip().startswith("#") for line in lines):
            out.append((first, body, named[0] if named else pending))
            pending = None
        elif named:
            pending = named[0]
    return out


def _line(root: Any, path: Sequence[Any], first: int) -> int | None:
    import yaml

    node = root
    for part in path:
        if isinstance(node, yaml.MappingNode):
            found = next((v for k, v in node.value if isinstance(k, yaml.ScalarNode) and k.value == str(part)), None)
            if found is None:
                break
            node = found
        elif isinstance(node, yaml.SequenceNode) and isinstance(part, int) and 0 <= part < len(node.value):
            node = node.value[part]
        else:
            break
    return node.start_mark.line + first if node is not None else None


def _key_lines(root: Any, key: str, first: int) -> dict[str, int]:
    """The line of each key of the mapping under the top-level ``key`` (a parameter's name)."""
    import yaml

    if not isinstance(root, yaml.MappingNode):
        return {}
    mapping = next((v for k, v in root.value if isinstance(k, yaml.ScalarNode) and k.value == key), None)
    if not isinstance(mapping, yaml.MappingNode):
        return {}
    return {str(k.value): k.start_mark.line + first for k, _v in mapping.value if isinstance(k, yaml.ScalarNode)}


def _where(path: Sequence[Any]) -> str | None:
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else ("." if out else "") + str(part)
    return out or None


def load_text(text: str, path: Path | None) -> NodlSource:
    """Read and validate a NoDL file (one document or a stream); raises ContractError."""
    stem = re.sub(r"\.nodl$", "", Path(path.name).stem) if path is not None else "node"
    default = "/" + (re.sub(r"[^A-Za-z0-9_]", "_", stem) or "node")
    if not re.match(r"^/[A-Za-z_]", default):
        default = "/node_" + default[1:]
    directory, found_how = schema_directory()
    source = NodlSource(documents=[], default_node=default)
    parts = _split(text)
    if not parts:
        raise ContractError(path, None, "the file holds no NoDL document (it needs at least `nodl_version: 2`)")
    for first, body, node in parts:
        try:
            root = untrusted.compose_yaml(body)
            if root is None:
                continue
            untrusted.check_tree(root)
            data = untrusted.construct(root)
        except untrusted.InputError as exc:
            line = exc.line + first - 1 if exc.line is not None else first
            raise ContractError(path, _where(list(exc.location)), exc.reason, line=line) from None
        doc = Document(data=data, node=node, first_line=first, root=root)
        _check(doc, path)
        if directory is not None:
            problem = schema_problem(data, directory)
            if problem is not None:
                where, reason = problem
                raise ContractError(path, _where(where), reason, line=_line(root, where, first))
        source.documents.append(doc)
    names = [d.node for d in source.documents]
    if len(source.documents) > 1 and None in names:
        i = names.index(None)
        raise ContractError(path, None, f"document {i + 1} of {len(names)} does not name its node: with several "
                            "documents in one file, put a `# node: /fqn` line above each",
                            line=source.documents[i].first_line)
    duplicate = next((n for n in names if n is not None and names.count(n) > 1), None)
    if duplicate:
        raise ContractError(path, None, f"two documents describe the node {duplicate}")
    source.notes.append(f"NoDL cannot express {', '.join(NOT_EXPRESSIBLE)}: they are not compared")
    if directory is None:
        source.notes.append(f"not validated against NoDL's own schema ({found_how}): set {SCHEMA_ENV} to NoDL's "
                            "schemas directory or install NoDL (nodl_schema)")
    if any(d.data.get("include") for d in source.documents):
        raise ContractError(path, "include", "`include:` references are not read by this tool yet: merge the "
                            "included documents into this one (`ros2 nodl` can resolve them), or check them one by one")
    return source


def _check(doc: Document, path: Path | None) -> None:
    """What this module needs of a document (NoDL's schema says more where it is found)."""
    data, first = doc.data, doc.first_line

    def fail(where: list[Any], reason: str) -> ContractError:
        return ContractError(path, _where(where), reason, line=_line(doc.root, where, first))

    if not isinstance(data, Mapping):
        raise fail([], f"a NoDL document is a mapping, not a {type(data).__name__}")
    if data.get("nodl_version") != VERSION:
        raise fail(["nodl_version"], f"nodl_version {data.get('nodl_version')!r} is not supported: this tool reads "
                   f"NoDL v{VERSION} documents (`nodl_version: {VERSION}`)")
    unknown = [k for k in data if k not in TOP_KEYS]
    if unknown:
        raise fail([unknown[0]], f"unknown key {unknown[0]!r} in a NoDL v2 document; allowed: {', '.join(TOP_KEYS)}")
    if doc.node is not None and not _NODE_NAME.match(doc.node):
        raise fail([], f"`# node: {doc.node}` does not name a node: give its fully qualified name (/ns/name)")
    params = data.get(PARAMETERS)
    if params is not None and not isinstance(params, Mapping):
        raise fail([PARAMETERS], "`parameters` is a mapping of parameter names to definitions")
    for name, definition in (params or {}).items():
        if not isinstance(definition, Mapping) or not isinstance(definition.get("type"), str):
            raise fail([PARAMETERS, name], f"parameter {name} needs a mapping with its `type`")
        if _parameter_type(definition["type"]) is None and definition["type"] != "none":
            raise fail([PARAMETERS, name, "type"], f"{definition['type']!r} is not a NoDL parameter type")
        extra = [k for k in definition if k not in PARAMETER_KEYS]
        if extra:
            raise fail([PARAMETERS, name, extra[0]], f"unknown key {extra[0]!r}; allowed: {', '.join(PARAMETER_KEYS)}")
        entry = _parameter_entry(name, definition)
        if entry is not None:
            try:
                parameter_model.check_contract_parameters([entry])
            except parameter_model.EntryProblem as problem:
                raise fail([PARAMETERS, name], problem.reason) from None
    for list_name in LISTS:
        entries = data.get(list_name)
        if entries is None:
            continue
        if not isinstance(entries, list):
            raise fail([list_name], f"`{list_name}` is a list of endpoints")
        seen: set[str] = set()
        for i, entry in enumerate(entries):
            if not isinstance(entry, Mapping) or not isinstance(entry.get("name"), str) \
                    or not isinstance(entry.get("type"), str):
                raise fail([list_name, i], "an endpoint needs a `name` and a `type`")
            if not _ROS_NAME.match(entry["name"]):
                raise fail([list_name, i, "name"], f"{entry['name']!r} is not a ROS name")
            if not _ROS_TYPE.match(entry["type"]):
                raise fail([list_name, i, "type"], f"{entry['type']!r} is not an interface type like std_msgs/msg/String")
            if entry["name"] in seen:
                raise fail([list_name, i, "name"], f"{entry['name']} is listed twice in {list_name}")
            seen.add(entry["name"])
            extra = [k for k in entry if k not in ENDPOINT_KEYS or (k == "qos" and list_name in ACTION_LISTS)]
            if extra:
                raise fail([list_name, i, extra[0]], f"unknown key {extra[0]!r} of an endpoint in {list_name}")
            if "qos" in entry:
                qos = entry["qos"]
                bad = [k for k in qos] if not isinstance(qos, Mapping) else [k for k in qos if k not in QOS_KEYS]
                if not isinstance(qos, Mapping) or bad:
                    raise fail([list_name, i, "qos"], f"a NoDL QoS is a mapping of {', '.join(QOS_KEYS)}")
                try:
                    qos_module.expand(dict(qos))
                except ValueError as exc:
                    raise fail([list_name, i, "qos"], str(exc)) from None


def _parameter_type(nodl_type: str) -> str | None:
    fixed = _FIXED_TYPE.match(nodl_type)
    base = fixed.group(1) if fixed else nodl_type
    ours = _FROM_NODL_TYPE.get(base, base)
    return ours if ours in PARAMETER_TYPES else None


def _parameter_entry(name: str, definition: Mapping[str, Any]) -> dict[str, Any] | None:
    """A contract parameter entry of a NoDL parameter (None for type ``none``: not compared)."""
    ours = _parameter_type(definition["type"])
    if ours is None:
        return None
    entry: dict[str, Any] = {"name": name, "type": ours}
    for key in ("default_value", "read_only", "description", "additional_constraints"):
        if key in definition:
            entry[key] = definition[key]
    return entry


def resolve_name(name: str, node: str) -> str:
    """A NoDL name as the node resolves it: absolute stays, ``~/x`` is under the node, ``x`` in its namespace."""
    if name.startswith("/"):
        return name
    if name.startswith("~"):
        return node + "/" + name[1:].lstrip("/") if name != "~" else node
    namespace = node.rsplit("/", 1)[0]
    return f"{namespace}/{name}"


def _full_type(type_name: str, list_name: str) -> str:
    match = _ROS_TYPE.match(type_name)
    if match is None or match.group(2):
        return type_name
    return f"{match.group(1)}/{_INTERFACE_KIND[list_name]}/{match.group(3)}"


def to_contract_node(data: Mapping[str, Any], fqn: str) -> dict[str, Any]:
    """One NoDL document as a contract node (six lists and its parameters)."""
    node: dict[str, Any] = {}
    for list_name in LISTS:
        entries = []
        for entry in data.get(list_name) or ():
            out: dict[str, Any] = {"name": resolve_name(entry["name"], fqn), "type": _full_type(entry["type"], list_name)}
            if list_name in TOPIC_LISTS and "qos" in entry:
                out["qos"] = dict(entry["qos"])
            entries.append(out)
        node[list_name] = entries
    parameters = [_parameter_entry(name, d) for name, d in (data.get(PARAMETERS) or {}).items()]
    node[PARAMETERS] = [p for p in parameters if p is not None]
    return node


# ---------------------------------------------------------------------------- comparing


def project(actual: Mapping[str, Any], expected: Mapping[str, Any]) -> dict[str, Any]:
    """``actual`` (a capture's nodes in contract form) cut down to what NoDL can state and the
    document (``expected``, its contract nodes) does state, so that nothing else is compared."""
    out: dict[str, Any] = {}
    for fqn, node in actual.items():
        wanted = expected.get(fqn) or {}
        projected: dict[str, Any] = {}
        for list_name in LISTS:
            stated = {e["name"]: e for e in wanted.get(list_name) or ()}
            entries = []
            for entry in node.get(list_name) or ():
                kept = {"name": entry["name"], "type": entry["type"]}
                if list_name in TOPIC_LISTS and "qos" in entry:
                    fields = qos_module.expand(entry["qos"])
                    if entry["name"] in stated:
                        keys = set(stated[entry["name"]].get("qos") or ())
                    else:
                        keys = set(nodl_qos(entry["qos"]))
                    if keys:
                        kept["qos"] = {k: fields[k] for k in QOS_KEYS if k in keys}
                entries.append(kept)
            projected[list_name] = entries
        if PARAMETERS in node:
            stated_params = {e["name"]: e for e in wanted.get(PARAMETERS) or ()}
            params = []
            for entry in node[PARAMETERS]:
                if entry.get("type") is None:
                    continue
                keys = set(stated_params[entry["name"]]) if entry["name"] in stated_params else set(entry)
                params.append({k: v for k, v in entry.items()
                               if k in ("name", "type") or (k in keys and k not in _PARAMETER_ONLY_HERE)})
            projected[PARAMETERS] = params
        out[fqn] = projected
    return out


# ---------------------------------------------------------------------------- writing


def nodl_qos(qos: Any) -> dict[str, Any]:
    """A contract QoS (any spelling) as NoDL writes it: history, depth (KEEP_LAST), reliability,
    durability, and the other policies that differ from their default."""
    contract_form = qos_module.from_capture(qos_module.expand(qos))
    return {k: contract_form[k] for k in QOS_KEYS if k in contract_form}


def nodl_parameters(entries: Sequence[Mapping[str, Any]]) -> tuple[dict[str, Any], list[str]]:
    """NoDL ``parameters`` of contract parameter entries, and a comment line for each one NoDL
    cannot describe (no type)."""
    out: dict[str, Any] = {}
    left_out: list[str] = []
    for p in sorted(entries, key=lambda p: str(p["name"])):
        if p.get("type") is None:
            left_out.append(f"# parameter {p['name']} (no type) left out: NoDL v2 has no such type")
            continue
        definition: dict[str, Any] = {"type": _TO_NODL_TYPE.get(p["type"], p["type"])}
        if p.get("default_value") is not None:
            definition["default_value"] = p["default_value"]
        for key in ("description", "additional_constraints"):
            if p.get(key):
                definition[key] = p[key]
        if p.get("read_only"):
            definition["read_only"] = True
        out[str(p["name"])] = definition
    return out, left_out


def _document(fqn: str, node: Mapping[str, Any], previous: Mapping[str, Any] | None) -> str:
    import yaml  # ~20 ms: only writing NoDL needs it

    doc: dict[str, Any] = {"nodl_version": VERSION}
    for key in ("description", "codegen"):  # what a person wrote, kept
        if previous and key in previous:
            doc[key] = previous[key]
    comments = [f"# node: {fqn}"]
    if node.get(LIFECYCLE) is not None:
        comments.append(f"# lifecycle: {node[LIFECYCLE]} (a lifecycle node: NoDL v2 cannot say so, not compared)")
    params, left_out = nodl_parameters(node.get(PARAMETERS) or ())
    comments += left_out
    if params:
        doc[PARAMETERS] = params
    for list_name in LISTS:
        entries = []
        for entry in sorted(node.get(list_name) or (), key=lambda e: str(e["name"])):
            written: dict[str, Any] = {"name": entry["name"], "type": entry["type"]}
            if list_name in TOPIC_LISTS and entry.get("qos") is not None:
                written["qos"] = nodl_qos(entry["qos"])
            entries.append(written)
        if entries:
            doc[list_name] = entries
    return "\n".join(comments) + "\n" + yaml.safe_dump(doc, sort_keys=False, default_flow_style=False,
                                                       allow_unicode=True)


def bind(source: NodlSource, nodes: Mapping[str, Any], node_names: Sequence[str], shown: str) -> dict[str, Any]:
    """The contract ``nodes`` of ``source`` for a capture of ``node_names``: a document that names
    no node describes the target's one node (raises ContractError when it created several)."""
    if not source.unnamed or source.default_node in node_names:
        return dict(nodes)
    if len(node_names) == 1:
        return source.nodes(bound=node_names[0])
    created = ", ".join(node_names) or "none"
    raise ContractError(Path(shown), None, f"the NoDL document does not name its node, and the target created "
                        f"{len(node_names)} nodes ({created}): put a `# node: /fqn` line above it naming the one it "
                        "describes")


def render(nodes: Mapping[str, Mapping[str, Any]], previous: NodlSource | None = None) -> str:
    """The NoDL file of contract ``nodes``: a document per node, each under its ``# node:``
    line (a YAML stream), with the description and codegen blocks of ``previous`` kept."""
    before: dict[str, Mapping[str, Any]] = {}
    if previous is not None:
        for doc in previous.documents:
            before[doc.node or previous.default_node] = doc.data
        if previous.unnamed and len(nodes) == 1:
            before[next(iter(nodes))] = previous.documents[0].data
    return "---\n" + "---\n".join(_document(fqn, nodes[fqn], before.get(fqn)) for fqn in sorted(nodes))
