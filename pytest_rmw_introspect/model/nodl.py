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
from typing import Any, cast

from ..errors import ContractError, EntryProblem, InputError
from . import ament_index, untrusted
from . import parameters as parameter_model
from . import qos as qos_module
from .contract_shapes import ContractNode, ContractNodes, InterfaceEntry, ParameterEntry, QosFields
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
QOS_KEYS: tuple[qos_module.QosField, ...] = ("history", "depth", "reliability", "durability", "deadline_ns", "lifespan_ns", "liveliness",
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
_INTERFACE_KIND: dict[str, str] = {**dict.fromkeys(TOPIC_LISTS, "msg"), "service_servers": "srv", "service_clients": "srv",
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
    #: what its ``include:`` references add (their entities and parameters, resolved recursively),
    #: kept apart from ``data`` so that writing the document back keeps the references
    included: dict[str, Any] = field(default_factory=dict)

    @property
    def merged(self) -> dict[str, Any]:
        """The document with what it includes: the interface it describes."""
        if not self.included:
            return self.data
        out = dict(self.data)
        for list_name in LISTS:
            if self.included.get(list_name):
                out[list_name] = [*(self.data.get(list_name) or ()), *self.included[list_name]]
        if self.included.get(PARAMETERS):
            out[PARAMETERS] = {**(self.data.get(PARAMETERS) or {}), **self.included[PARAMETERS]}
        return out


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

    def nodes(self, bound: str | None = None) -> ContractNodes:
        """The documents as contract ``nodes`` (the unnamed one as ``bound``, when given)."""
        out: ContractNodes = {}
        for doc in self.documents:
            fqn = doc.node or bound or self.default_node
            out[fqn] = to_contract_node(doc.merged, fqn)
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
    from .locate import line_at  # with PyYAML: only a document with a problem is located

    return line_at(root, path, first)


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


def load_text(text: str, path: Path | None, _chain: tuple[Path, ...] = ()) -> NodlSource:
    """Read and validate a NoDL file (one document or a stream), with the documents its
    ``include:`` references name; raises ContractError."""
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
        except InputError as exc:
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
    for doc in source.documents:
        if doc.data.get("include"):
            chain = _chain or ((path.resolve(),) if path is not None else ())
            doc.included = _resolve_includes(doc, path, chain)
    return source


# ---------------------------------------------------------------------------- include:

#: the resource type ament_nodl_register installs documents under (key ``<package>__<name>``)
_AMENT_RESOURCE_TYPE = "nodl"
_REF = re.compile(r"^([a-z][a-z0-9+.-]*)://(\S+)$")


def _reference_path(ref: str, including: Path | None) -> Path:
    """The file a NoDL reference names: ``local://<path relative to the including file>`` or
    ``nodl://<package>/<name>`` (the ament index of AMENT_PREFIX_PATH, as ament_nodl_register
    installs it). Raises ValueError with what to do."""
    match = _REF.match(ref)
    if match is None:
        raise ValueError(f"{ref!r} is not a NoDL reference (`local://<relative path>` or `nodl://<package>/<name>`)")
    scheme, body = match.groups()
    if scheme == "local":
        if including is None:
            raise ValueError(f"{ref}: a local:// reference needs the including document's file")
        return including.parent / body
    if scheme == "nodl":
        package, _, name = body.partition("/")
        if not package or not name or "/" in name:
            raise ValueError(f"{ref}: a nodl:// reference is nodl://<package>/<name>")
        prefixes = ament_index.env_prefixes()
        for prefix in prefixes:
            candidate = ament_index.resource(prefix, f"{package}__{name}", _AMENT_RESOURCE_TYPE)
            if candidate.is_file():
                return candidate
        where = ", ".join(map(str, prefixes)) or "no prefix: AMENT_PREFIX_PATH is not set"
        raise ValueError(f"{ref}: no NoDL document {package}__{name} registered in the ament index ({where}); "
                         "build and source the package that registers it (ament_nodl_register)")
    raise ValueError(f"{ref}: this tool resolves local:// and nodl:// references, not {scheme}://")


def _include_error(doc: Document, path: Path | None, index: int, reason: str) -> ContractError:
    where = ["include", index]
    return ContractError(path, _where(where), reason, line=_line(doc.root, where, doc.first_line))


def _resolve_includes(doc: Document, path: Path | None, chain: tuple[Path, ...]) -> dict[str, Any]:
    """The entities and parameters ``doc``'s ``include:`` references add, recursively (what
    NoDL's resolver does): an entity or parameter defined twice, or a circular inclusion, is an
    error naming both places."""
    added: dict[str, Any] = {}
    own = {(list_name, e["name"]) for list_name in LISTS for e in doc.data.get(list_name) or ()}
    own_parameters = set(doc.data.get(PARAMETERS) or {})
    for i, reference in enumerate(doc.data.get("include") or ()):
        ref = reference.get("ref") if isinstance(reference, Mapping) else None
        fail = functools.partial(_include_error, doc, path, i)
        if not isinstance(ref, str):
            raise fail("an include entry is `{ref: <scheme>://<body>}`")
        try:
            target = _reference_path(ref, path).resolve()
        except ValueError as exc:
            raise fail(str(exc)) from None
        if target in chain:
            cycle = " -> ".join(str(p) for p in (*chain, target))
            raise fail(f"{ref} includes itself in a circle ({cycle})")
        try:
            text = untrusted.read_text(target)
        except FileNotFoundError:
            raise fail(f"{ref}: the included document {target} does not exist") from None
        except InputError as exc:
            raise fail(f"{ref}: {target}: {exc.reason}") from None
        included = load_text(text, target, _chain=(*chain, target))
        if len(included.documents) != 1:
            raise fail(f"{ref}: {target} holds {len(included.documents)} documents; an included file holds one")
        content = included.documents[0].merged
        for list_name in LISTS:
            for entry in content.get(list_name) or ():
                key = (list_name, entry["name"])
                if key in own or any(e["name"] == entry["name"] for e in added.get(list_name, ())):
                    raise fail(f"{list_name} {entry['name']} is defined twice: here and in {ref} ({target})")
                added.setdefault(list_name, []).append(entry)
        for name, definition in (content.get(PARAMETERS) or {}).items():
            if name in own_parameters or name in added.get(PARAMETERS, {}):
                raise fail(f"parameter {name} is defined twice: here and in {ref} ({target})")
            added.setdefault(PARAMETERS, {})[name] = definition
    return added


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
        parameter_entry = _parameter_entry(name, definition)
        if parameter_entry is not None:
            try:
                parameter_model.check_contract_parameters([parameter_entry])
            except EntryProblem as problem:
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


def _parameter_entry(name: str, definition: Mapping[str, Any]) -> ParameterEntry | None:
    """A contract parameter entry of a NoDL parameter (None for type ``none``: not compared)."""
    ours = _parameter_type(definition["type"])
    if ours is None:
        return None
    entry: ParameterEntry = {"name": name, "type": ours}
    # the document passed NoDL's checks (_check_document): these have the contract's value types
    if "default_value" in definition:
        entry["default_value"] = definition["default_value"]
    if "read_only" in definition:
        entry["read_only"] = definition["read_only"]
    if "description" in definition:
        entry["description"] = definition["description"]
    if "additional_constraints" in definition:
        entry["additional_constraints"] = definition["additional_constraints"]
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


def to_contract_node(data: Mapping[str, Any], fqn: str) -> ContractNode:
    """One NoDL document (checked) as a contract node (six lists and its parameters)."""
    node = ContractNode()
    for list_name in LISTS:
        entries = []
        for entry in data.get(list_name) or ():
            out: InterfaceEntry = {"name": resolve_name(entry["name"], fqn), "type": _full_type(entry["type"], list_name)}
            if list_name in TOPIC_LISTS and "qos" in entry:
                out["qos"] = cast(QosFields, dict(entry["qos"]))
            entries.append(out)
        node[list_name] = entries
    parameters = [_parameter_entry(name, d) for name, d in (data.get(PARAMETERS) or {}).items()]
    node[PARAMETERS] = [p for p in parameters if p is not None]
    return node


# ---------------------------------------------------------------------------- comparing


def project(actual: Mapping[str, ContractNode], expected: Mapping[str, ContractNode]) -> ContractNodes:
    """``actual`` (a capture's nodes in contract form) cut down to what NoDL can state and the
    document (``expected``, its contract nodes) does state, so that nothing else is compared."""
    out: ContractNodes = {}
    for fqn, node in actual.items():
        wanted = expected.get(fqn) or ContractNode()
        projected = ContractNode()
        for list_name in LISTS:
            stated = {e["name"]: e for e in wanted.get(list_name) or ()}
            entries = []
            for entry in node.get(list_name) or ():
                kept: InterfaceEntry = {"name": entry["name"], "type": entry["type"]}
                if list_name in TOPIC_LISTS and "qos" in entry:
                    fields = qos_module.expand(entry["qos"])
                    if entry["name"] in stated:
                        keys = set(stated[entry["name"]].get("qos") or ())
                    else:
                        keys = set(nodl_qos(entry["qos"]))
                    if keys:
                        kept["qos"] = cast(QosFields, {k: fields[k] for k in QOS_KEYS if k in keys})
                entries.append(kept)
            projected[list_name] = entries
        if PARAMETERS in node:
            stated_params = {e["name"]: e for e in wanted.get(PARAMETERS) or ()}
            params = []
            for parameter in node[PARAMETERS]:
                if parameter.get("type") is None:
                    continue
                keys = set(stated_params[parameter["name"]]) if parameter["name"] in stated_params else set(parameter)
                params.append(cast(ParameterEntry, {k: v for k, v in parameter.items()
                                                    if k in ("name", "type") or (k in keys and k not in _PARAMETER_ONLY_HERE)}))
            projected[PARAMETERS] = params
        out[fqn] = projected
    return out


# ---------------------------------------------------------------------------- writing


def nodl_qos(qos: Any) -> QosFields:
    """A contract QoS (any spelling) as NoDL writes it: history, depth (KEEP_LAST), reliability,
    durability, and the other policies that differ from their default."""
    contract_form = qos_module.from_capture(qos_module.expand(qos))
    return cast(QosFields, {k: contract_form[k] for k in QOS_KEYS if k in contract_form})


def nodl_parameters(entries: Sequence[ParameterEntry]) -> tuple[dict[str, Any], list[str]]:
    """NoDL ``parameters`` of contract parameter entries, and a comment line for each one NoDL
    cannot describe (no type)."""
    out: dict[str, Any] = {}
    left_out: list[str] = []
    for p in sorted(entries, key=lambda p: str(p["name"])):
        type_name = p.get("type")
        if type_name is None:
            left_out.append(f"# parameter {p['name']} (no type) left out: NoDL v2 has no such type")
            continue
        definition: dict[str, Any] = {"type": _TO_NODL_TYPE.get(type_name, type_name)}
        if p.get("default_value") is not None:
            definition["default_value"] = p["default_value"]
        for key in ("description", "additional_constraints"):
            if p.get(key):
                definition[key] = p[key]
        if p.get("read_only"):
            definition["read_only"] = True
        out[str(p["name"])] = definition
    return out, left_out


def _written_entry(list_name: str, entry: InterfaceEntry) -> dict[str, Any]:
    written: dict[str, Any] = {"name": entry["name"], "type": entry["type"]}
    if list_name in TOPIC_LISTS and entry.get("qos") is not None:
        written["qos"] = nodl_qos(entry["qos"])
    return written


def _left_to_includes(fqn: str, node: ContractNode, previous: Document) -> tuple[set[tuple[str, str]], set[str]]:
    """The entities and parameters of ``node`` that ``previous``'s ``include:`` references still
    describe as they are (so the rewritten document keeps the references and leaves them out).
    Raises ValueError when the node changed one of them: that change belongs in the included file."""
    included = to_contract_node(previous.included, fqn)
    entities: set[tuple[str, str]] = set()
    for list_name in LISTS:
        have = {str(e["name"]): e for e in node.get(list_name) or ()}
        for entry in included[list_name]:
            now = have.get(entry["name"])
            stated = {k: v for k, v in _written_entry(list_name, now).items() if k in entry} if now else None
            if stated != ({**entry, "qos": nodl_qos(entry["qos"])} if "qos" in entry else entry):
                change = "no longer has it" if now is None else "has it otherwise"
                raise ValueError(f"{list_name} {entry['name']} comes from an included document and the node {change}: "
                                 "update the included document (or move the entity into this one) and run again")
            entities.add((list_name, str(entry["name"])))
    parameters = {str(p["name"]) for p in node.get(PARAMETERS) or ()}
    missing = sorted(set(previous.included.get(PARAMETERS) or {}) - parameters)
    if missing:
        raise ValueError(f"parameter {missing[0]} comes from an included document and the node no longer declares it: "
                         "update the included document and run again")
    return entities, set(previous.included.get(PARAMETERS) or {})


def _document(fqn: str, node: ContractNode, previous: Document | None) -> str:
    import yaml  # ~20 ms: only writing NoDL needs it

    doc: dict[str, Any] = {"nodl_version": VERSION}
    for key in ("description", "codegen", "include"):  # what a person wrote, kept
        if previous and key in previous.data:
            doc[key] = previous.data[key]
    from_includes, parameters_from_includes = (_left_to_includes(fqn, node, previous)
                                               if previous is not None and previous.included else (set(), set()))
    comments = [f"# node: {fqn}"]
    if node.get(LIFECYCLE) is not None:
        comments.append(f"# lifecycle: {node[LIFECYCLE]} (a lifecycle node: NoDL v2 cannot say so, not compared)")
    params, left_out = nodl_parameters([p for p in node.get(PARAMETERS) or () if p["name"] not in parameters_from_includes])
    comments += left_out
    if params:
        doc[PARAMETERS] = params
    for list_name in LISTS:
        entries = [_written_entry(list_name, entry)
                   for entry in sorted(node.get(list_name) or (), key=lambda e: str(e["name"]))
                   if (list_name, str(entry["name"])) not in from_includes]
        if entries:
            doc[list_name] = entries
    return "\n".join(comments) + "\n" + yaml.safe_dump(doc, sort_keys=False, default_flow_style=False,
                                                       allow_unicode=True)


def bind(source: NodlSource, nodes: Mapping[str, ContractNode], node_names: Sequence[str], shown: str) -> ContractNodes:
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


def render(nodes: Mapping[str, ContractNode], previous: NodlSource | None = None,
           path: Path | None = None) -> str:
    """The NoDL file of contract ``nodes``: a document per node, each under its ``# node:``
    line (a YAML stream), with the description, codegen and include blocks of ``previous`` (read
    from ``path``) kept, and what the included documents describe left to them. Raises
    ContractError when the nodes changed something an included document describes."""
    before: dict[str, Document] = {}
    if previous is not None:
        for doc in previous.documents:
            before[doc.node or previous.default_node] = doc
        if previous.unnamed and len(nodes) == 1:
            before[next(iter(nodes))] = previous.documents[0]
    try:
        return "---\n" + "---\n".join(_document(fqn, nodes[fqn], before.get(fqn)) for fqn in sorted(nodes))
    except ValueError as exc:
        raise ContractError(path, "include", str(exc)) from None
