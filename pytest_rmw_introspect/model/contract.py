"""Contract files: load (YAML + JSON Schema + semantic checks), deterministic dump, update.

A contract (docs/design.md section 2) is YAML::

    # comments, the target block and the options block above `nodes:` survive updates
    contract_version: 1
    ros_distribution: jazzy   # optional: the distribution it was captured on
    interface_version: 1.2.0  # optional: the version the `diff --against` gate compares
    target: {...}      # optional
    options: {...}     # optional
    nodes:
      /talker:
        lifecycle: active   # a lifecycle node only: the state it is described in
        publishers: [...]
        ...
        parameters: [...]   # optional: left out, they are not compared

Loading reports every problem a person can make with the file, the place inside it
(``nodes./talker.publishers[0].qos.reliability``), the line when known, and the reason:
YAML syntax errors, schema violations (``schema/contract.schema.json``), bad QoS values,
duplicate YAML keys, duplicate interface and parameter names, parameter values that do not fit
their type.

Writing is deterministic: nodes sorted by name, ``lifecycle`` first (then ``destroyed_at``,
for a node the program destroyed), entries sorted by ``name``, keys in the order ``name, type,
type_hash, qos, destroyed_at``, the six lists always present, QoS
on one line in field order, then ``parameters`` when the node states them (sorted by name, keys
in ``parameters.ENTRY_KEYS`` order, values and ranges on one line).
``dump(load(x))`` of a file this module wrote is byte-identical.

Updating a file (``update_text``) keeps everything *above* the top-level ``nodes:`` key
verbatim (comments, ``contract_version``, ``target``, ``options``; a golden write keeps only its
``ros_distribution:`` line, where it has one, up to date: :func:`with_distribution`) and
everything after the
``nodes`` block that starts a new top-level key, and rewrites only the ``nodes`` block. This
is a deliberate decision: it needs no round-trip YAML library, and the part people annotate
(the header) survives byte for byte. Comments *inside* the ``nodes`` block do not survive an
update.
"""

from __future__ import annotations

import difflib
import functools
import json
import math
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any, cast

import yaml

from ..errors import ContractError, EntryProblem, InputError, SectionError
from . import acceptance, nodl, untrusted, yaml_blocks
from . import parameters as parameter_model
from . import qos as qos_module
from . import types as type_model
from . import unstable_names as unstable_model
from .contract_shapes import ContractNode, ContractNodes, ContractOptions, InterfaceEntry, ParameterEntry, TargetBlock
from .locate import LineIndex, line_at, line_index, node_at
from .paths import shown
from .vocabulary import (
    ACTION_HASHED_PARTS,
    DESTROYED_AT,
    DESTROYED_AT_TOLERANCE_S,
    LABELS,
    LIFECYCLE,
    LISTS,
    PARAMETERS,
    SERVICE_LISTS,
)

CONTRACT_VERSION = 1
ENTRY_KEYS = ("name", "type", "type_hash", "qos", DESTROYED_AT)
#: the top-level key recording the ROS 2 distribution a contract was captured on
DISTRIBUTION_KEY = "ros_distribution"
#: the top-level key of the interface version (node and system contracts; ``compare.versioning``)
VERSION_KEY = "interface_version"

DEFAULT_HEADER = (
    "# Interface contract checked by pytest-rmw-introspect.\n"
    "# Regenerate with `pytest --update-golden`; comments and keys above `nodes:` are kept.\n"
    f"contract_version: {CONTRACT_VERSION}\n"
)

@functools.lru_cache(maxsize=1)
def schema() -> dict[str, Any]:
    """The JSON Schema of contract files shipped with the package."""
    text = resources.files("pytest_rmw_introspect").joinpath("schema", "contract.schema.json").read_text("utf-8")
    loaded: dict[str, Any] = json.loads(text)
    return loaded


@dataclass
class Contract:
    """A loaded contract. ``nodes`` is as written (QoS spellings kept), normalised so that
    every node has the six lists (and ``parameters`` / ``lifecycle`` when it states them);
    :meth:`expanded_nodes` gives QoS as explicit fields."""

    path: Path | None
    nodes: ContractNodes
    target: TargetBlock | None = None
    options: ContractOptions = field(default_factory=lambda: ContractOptions())
    contract_version: int = CONTRACT_VERSION
    text: str = ""
    #: the generated ``types:`` section (``model.types``); None when the file has none
    types: dict[str, type_model.TypeDescription] | None = None
    #: the ROS 2 distribution the contract was captured on (``ros_distribution:``), if recorded
    ros_distribution: str | None = None
    #: the findings it accepts on purpose (``accept:``)
    accept: tuple[acceptance.Acceptance, ...] = ()
    #: the version of the interface it promises (``interface_version: MAJOR.MINOR.PATCH``), if stated
    interface_version: str | None = None
    #: read from a NoDL file (``model.nodl``): its documents, and what is not compared
    nodl: nodl.NodlSource | None = None
    #: the patterns of node names that change every run it declares (``unstable_names:``)
    unstable_names: tuple[unstable_model.NamePattern, ...] = ()
    #: read from a system contract (``model.contract_kind.as_node_contract``): the middleware it
    #: says it runs on (``rmw:``, its launch environment), which its comparisons follow
    middleware: str | None = None

    def name_rules(self) -> unstable_model.NameRules:
        """What decides the keys of captured nodes checked against this contract: its declared
        patterns, its pattern keys, its literal names (``unstable_names.NameRules``)."""
        return unstable_model.NameRules.of_contract(self.unstable_names, self.nodes)

    def expanded_nodes(self) -> ContractNodes:
        """``nodes`` with every topic QoS expanded to all fields (``qos.expand``)."""

        out: ContractNodes = {}
        for fqn, node in self.nodes.items():
            expanded = ContractNode()
            if unstable_model.NODE_KEY in node:
                expanded["unstable_name"] = node["unstable_name"]
            if LIFECYCLE in node:
                expanded["lifecycle"] = node["lifecycle"]
            if DESTROYED_AT in node:
                expanded["destroyed_at"] = node["destroyed_at"]
            if PARAMETERS in node:
                expanded["parameters"] = node["parameters"]
            for list_name in LISTS:
                entries = []
                for entry in node[list_name]:
                    entry = entry.copy()
                    if "qos" in entry:
                        entry["qos"] = qos_module.expand(entry["qos"])
                    entries.append(entry)
                expanded[list_name] = entries
            out[fqn] = expanded
        return out

    def lines(self) -> LineIndex:
        """Where the file writes each node, interface and parameter (for annotations)."""
        if self.nodl is not None:
            return self.nodl.lines(bound=next(iter(self.nodes)) if self.nodl.unnamed and self.nodes else None)
        return line_index(self.text)

    def dump(self) -> str:
        """The file text with the ``nodes`` block regenerated (header kept); NoDL stays NoDL."""
        if self.nodl is not None:
            return nodl.render(self.nodes, self.nodl, self.path)
        return update_text(self.text, self.nodes) if self.text else render(self.nodes)


# ---------------------------------------------------------------------------- locations


def format_location(path: Iterator[Any] | list[Any] | tuple[Any, ...]) -> str:
    """``["nodes", "/talker", "publishers", 0, "qos"]`` → ``nodes./talker.publishers[0].qos``."""
    out = ""
    for part in path:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += ("." if out else "") + str(part)
    return out


# ---------------------------------------------------------------------------- loading


def _compose(text: str, path: Path | None) -> tuple[yaml.Node | None, Any]:
    """The node tree (for line numbers) and the data of ``text``, checked on the way: keys are
    unique strings, nesting and alias expansion are bounded (``untrusted``)."""
    try:
        root = untrusted.compose_yaml(text)
        if root is None:
            return None, None
        untrusted.check_tree(root)
        return root, untrusted.construct(root)
    except InputError as exc:
        raise ContractError(path, format_location(list(exc.location)) or None, exc.reason, line=exc.line) from None


def _schema_error(root: yaml.Node | None, data: Any, path: Path | None) -> ContractError | None:
    errors = list(_validator().iter_errors(data))
    return schema_error(root, errors, path, _schema_reason) if errors else None


def _key_line(root: yaml.Node | None, location: list[Any], key: str) -> int | None:
    """The line of ``key`` itself in the mapping at ``location`` (None: not found)."""
    node = node_at(root, location)
    if isinstance(node, yaml.MappingNode):
        for k, _ in node.value:
            if isinstance(k, yaml.ScalarNode) and k.value == key:
                return k.start_mark.line + 1
    return None


def _problem(root: yaml.Node | None, error: Any, reason_of: Callable[[Any], str]) -> tuple[list[Any], str, int | None]:
    """Where a schema error is (its location and line: an unknown key's own line, not its
    mapping's) and what it says."""
    location = list(error.absolute_path)
    if "propertyNames" in error.absolute_schema_path and isinstance(error.instance, str):
        location.append(error.instance)  # point at the offending key itself
    line = line_at(root, location)
    if error.validator == "additionalProperties" and isinstance(error.instance, Mapping):
        unknown = [k for k in error.instance if k not in (error.schema.get("properties") or {})]
        if unknown:
            line = _key_line(root, location, str(unknown[0])) or line
    return location, reason_of(error), line


def schema_error(root: yaml.Node | None, errors: list[Any], path: Path | None,
                 reason_of: Callable[[Any], str]) -> ContractError:
    """One error for every problem the schema found in a file: the most relevant first (jsonschema's
    ``best_match``), then every other one by line, each with its own line and location."""
    import jsonschema  # ~80 ms: only an invalid file needs it here (the caller has it loaded)

    best = jsonschema.exceptions.best_match(errors)
    location, reason, line = _problem(root, best, reason_of)
    others = sorted((_problem(root, error, reason_of) for error in errors if error is not best),
                    key=lambda problem: (problem[2] or 0, format_location(problem[0])))
    return ContractError(path, format_location(location) or None, reason, line=line,
                         others=[(format_location(where) or None, why, at) for where, why, at in others])


@functools.lru_cache(maxsize=1)
def _validator() -> Any:
    import jsonschema

    return jsonschema.Draft7Validator(_inline_refs(schema()))


def _inline_refs(document: dict[str, Any]) -> dict[str, Any]:
    """The schema with every local ``$ref`` replaced by the definition it names (a recursive one
    stays a reference). jsonschema resolves a ``$ref`` anew each time it meets one: once per
    interface of a contract, most of the validation time of a large one."""
    definitions = document.get("definitions", {})

    def inline(value: Any, expanding: tuple[str, ...]) -> Any:
        if isinstance(value, list):
            return [inline(v, expanding) for v in value]
        if not isinstance(value, dict):
            return value
        ref = value.get("$ref")
        if isinstance(ref, str) and ref.startswith("#/definitions/"):
            name = ref[len("#/definitions/"):]
            # Draft 7 ignores the keywords beside a $ref (a description): the definition replaces all.
            if name in definitions and name not in expanding:
                return inline(definitions[name], expanding + (name,))
        return {k: inline(v, expanding) for k, v in value.items()}

    inlined: dict[str, Any] = inline(document, ())
    return inlined


_ACCEPT_REASONS = {
    "rule": "{instance!r} is not a rule id (docs/drift-rules.md lists them: PUB_REMOVED, SUBSCRIPTION_WITHOUT_PUBLISHER, ...)",
    "reason": "an accepted finding needs a reason: say why it is accepted (`reason: published by rviz, not launched`)",
    "node": "{instance!r} is not a fully qualified node name (e.g. /talker or /ns/talker)",
}


def _schema_reason(error: Any) -> str:
    validator = error.validator
    instance = untrusted.Short(error.instance)
    if "propertyNames" in error.absolute_schema_path:
        return (f"node name {instance!r} is not a fully qualified node name (e.g. /talker or /ns/talker) nor a "
                "pattern of names that change every run (/talker_*, /talker_*#2 for its second node)")
    if error.absolute_path and error.absolute_path[0] == unstable_model.SECTION_KEY and validator == "pattern":
        return (f"{instance!r} is not a pattern of node names: a fully qualified name with `*` where the name "
                "changes (e.g. /camera_driver_*)" if error.absolute_path[-1] == "pattern"
                else "a pattern needs a reason: say why the names change every run")
    if error.absolute_path and error.absolute_path[0] == acceptance.SECTION_KEY and validator in ("pattern", "minLength"):
        return _ACCEPT_REASONS.get(str(error.absolute_path[-1]), str(error.message)).format(instance=instance)
    if validator == "pattern" and list(error.absolute_path) == [VERSION_KEY]:
        return (f"interface_version {instance!r} is not MAJOR.MINOR.PATCH with parts of at most 18 digits "
                "(e.g. 1.0.0)")
    if validator == "pattern" and error.absolute_path and error.absolute_path[-1] == "name":
        return f"{instance!r} is not a fully resolved ROS name (it must start with '/')"
    if validator == "pattern" and error.absolute_path and "type_hash" in error.absolute_path:
        return f"{instance!r} is not a type hash (RIHS01_ followed by 64 lowercase hex digits)"
    if validator == "pattern" and error.absolute_path and error.absolute_path[-1] == "type":
        return f"{instance!r} is not an interface type like std_msgs/msg/String"
    if validator == "enum":
        allowed = ", ".join(str(v) for v in error.validator_value)
        return f"{instance!r} is not one of: {allowed}"
    if validator == "const" and list(error.absolute_path) == ["contract_version"]:
        return f"contract_version {instance!r} is not supported; this plugin reads contract_version 1"
    if validator == "required":
        return str(error.message).replace("is a required property", "is required")
    if validator == "additionalProperties":
        allowed_keys = sorted((error.schema.get("properties") or {}).keys())
        extra = sorted(set(error.instance) - set(allowed_keys)) if isinstance(error.instance, Mapping) else []
        if allowed_keys:
            return _unknown_keys_reason(extra, allowed_keys)
    if validator == "type":
        expected = error.validator_value
        expected = " or ".join(expected) if isinstance(expected, list) else expected
        if list(error.absolute_path) == ["nodes"] and error.instance is None:
            return "`nodes:` is empty; write `nodes: {}` for a contract without nodes (fill it with --update-golden)"
        if error.absolute_path and error.absolute_path[-1] == PARAMETERS and error.instance is None:
            return ("`parameters:` is empty; write `parameters: []` for a node without parameters, or leave the "
                    "key out not to compare them")
        return f"{instance!r} is not of type {expected}"
    return str(error.message)


#: where the keys each part of a contract takes are listed, for messages too long to list them
SCHEMA_HINT = "allowed keys: see the contract schema, pytest_rmw_introspect/schema/contract.schema.json"
#: the longest list of allowed keys a message spells out (longer ones, a node's keys among them, point at the
#: schema with the closest key)
_LISTED_KEYS_CHARS = 130


def _unknown_keys_reason(extra: list[Any], allowed_keys: list[str]) -> str:
    """Unknown keys, with the allowed ones when they are few, else the closest one and the schema."""
    reason = (f"unknown key{'s' if len(extra) > 1 else ''} {', '.join(untrusted.shorten(e, 40) for e in extra[:5])}"
              f"{' and more' if len(extra) > 5 else ''}")
    listed = ", ".join(allowed_keys)
    if len(listed) <= _LISTED_KEYS_CHARS:
        return f"{reason}; allowed: {listed}"
    close = difflib.get_close_matches(str(extra[0]), allowed_keys, n=1) if len(extra) == 1 else []
    return reason + (f"; did you mean {close[0]!r}?" if close else "") + f" ({SCHEMA_HINT})"


def load(path: str | Path) -> Contract:
    """Read and validate a contract file (raises :class:`ContractError`)."""
    path = Path(path)
    try:
        text = untrusted.read_text(path)
    except FileNotFoundError:
        raise ContractError(path, None, "the file does not exist") from None
    except InputError as exc:
        raise ContractError(path, None, exc.reason) from None
    return loads(text, path=path)


def loads(text: str, *, path: str | Path | None = None) -> Contract:
    """Parse and validate contract text; ``path`` is used in messages."""
    with untrusted.gc_paused():
        return _loads(text, Path(path) if path is not None else None)


def _loads(text: str, path: Path | None) -> Contract:
    if nodl.is_nodl(text, path):
        source = nodl.load_text(text, path)
        return Contract(path=path, nodes=normalize_nodes(source.nodes()), text=text, nodl=source)
    root, data = _compose(text, path)
    if data is None:
        raise ContractError(path, None, "the file is empty; it needs at least `contract_version: 1` and `nodes:`")
    if not isinstance(data, Mapping):
        raise ContractError(path, None, f"the document is a {type(data).__name__}, not a mapping", line=1)
    error = _schema_error(root, data, path)
    if error is not None:
        raise error
    too_broad = unstable_model.refused(data)
    if too_broad is not None:
        raise ContractError(path, format_location(too_broad[0]), too_broad[1], line=line_at(root, too_broad[0]))
    nodes = normalize_nodes(data.get("nodes") or {})
    _check_semantics(root, nodes, path)
    types = None
    if type_model.SECTION_KEY in data:
        try:
            types = type_model.from_contract(data[type_model.SECTION_KEY])
        except SectionError as exc:
            raise ContractError(path, format_location(exc.location), exc.reason,
                                line=line_at(root, exc.location)) from None
    return Contract(
        path=path,
        nodes=nodes,
        # validated by the schema: the blocks have the keys and value types of their shapes
        target=cast(TargetBlock, dict(data["target"])) if data.get("target") is not None else None,
        options=cast(ContractOptions, dict(data.get("options") or {})),
        contract_version=int(data["contract_version"]),
        text=text,
        types=types,
        ros_distribution=data.get(DISTRIBUTION_KEY),
        interface_version=data.get(VERSION_KEY),
        accept=acceptance.from_entries(data.get(acceptance.SECTION_KEY), source=shown(path) if path else "<contract>",
                                       line_of=lambda i: line_at(root, [acceptance.SECTION_KEY, i])),
        unstable_names=unstable_model.from_entries(data.get(unstable_model.SECTION_KEY)),
    )


def normalize_nodes(nodes: Mapping[str, Any]) -> ContractNodes:
    """Every node with the six lists (a list left out or ``null`` is empty), its ``lifecycle``
    state when it states one, and its ``parameters`` when it states them (left out: not stated,
    not compared). ``nodes`` is a ``nodes:`` block the schema has accepted (a node may be
    ``null``), or nodes this package made."""
    out: ContractNodes = {}
    for fqn, node in nodes.items():
        node = node or {}
        entry = ContractNode()
        if node.get(unstable_model.NODE_KEY) is not None:
            entry["unstable_name"] = node[unstable_model.NODE_KEY]
        if node.get(LIFECYCLE) is not None:
            entry["lifecycle"] = node[LIFECYCLE]
        if node.get(DESTROYED_AT) is not None:
            entry["destroyed_at"] = node[DESTROYED_AT]
        for list_name in LISTS:
            entry[list_name] = [cast(InterfaceEntry, dict(e)) for e in (node.get(list_name) or [])]
        if node.get(PARAMETERS) is not None:
            entry["parameters"] = [cast(ParameterEntry, dict(e)) for e in node[PARAMETERS]]
        out[fqn] = entry
    return out


def check_parameters(root: yaml.Node | None, nodes: Mapping[str, ContractNode], path: Path | None) -> None:
    """What the schema cannot say about the nodes' ``parameters`` (``parameters.check_contract_parameters``:
    unique names, values of the stated type); raises ContractError with the place and line."""
    for fqn, node in nodes.items():
        try:
            parameter_model.check_contract_parameters(node.get(PARAMETERS) or [])
        except EntryProblem as problem:
            where = ["nodes", fqn, PARAMETERS, *problem.location]
            raise ContractError(path, format_location(where), f"{problem.reason} (node {fqn})",
                                line=line_at(root, where)) from None


def _check_semantics(root: yaml.Node | None, nodes: ContractNodes, path: Path | None) -> None:
    check_parameters(root, nodes, path)

    for fqn, node in nodes.items():
        for list_name in LISTS:
            first_index: dict[str, int] = {}
            for i, entry in enumerate(node[list_name]):
                where = ["nodes", fqn, list_name, i]
                name = entry["name"]
                if name in first_index:
                    raise ContractError(
                        path,
                        format_location(where + ["name"]),
                        f"duplicate {LABELS[list_name]} {name!r} in node {fqn} "
                        f"(also at {list_name}[{first_index[name]}]); each name may appear once per list",
                        line=line_at(root, where + ["name"]),
                    )
                first_index[name] = i
                if "qos" in entry:
                    try:
                        qos_module.expand(entry["qos"])
                    except ValueError as exc:
                        raise ContractError(
                            path, format_location(where + ["qos"]), str(exc), line=line_at(root, where + ["qos"])
                        ) from None


# ---------------------------------------------------------------------------- writing


def _scalar(value: Any) -> str:
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isinf(value) or math.isnan(value):
            return yaml.safe_dump(value).splitlines()[0]
        return repr(value)
    text = yaml.safe_dump(str(value), default_flow_style=True, width=math.inf, allow_unicode=True).rstrip("\n")
    text = text.removesuffix("\n...")
    if any(c in text for c in ",[]{}") and not text.startswith(("'", '"')):
        text = "'" + str(value).replace("'", "''") + "'"
    return text


def _qos_text(value: Any) -> str:

    if isinstance(value, str):
        return _scalar(value)
    order = ("profile",) + tuple(qos_module.FIELDS)
    keys = [k for k in order if k in value] + sorted(k for k in value if k not in order)
    return "{" + ", ".join(f"{k}: {_scalar(value[k])}" for k in keys) + "}"


def _float_text(value: float) -> str:
    """A float YAML 1.1 reads back as a float (PyYAML wants a '.' in the mantissa: ``1.0e+300``)."""
    if math.isinf(value) or math.isnan(value):
        return yaml.safe_dump(value).splitlines()[0]
    text = repr(value)
    if "e" in text and "." not in text.split("e")[0]:
        mantissa, exponent = text.split("e")
        text = f"{mantissa}.0e{exponent}"
    return text


def _value_text(value: Any) -> str:
    """A parameter value or range on one line (flow style)."""
    if isinstance(value, float):
        return _float_text(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_value_text(v) for v in value) + "]"
    if isinstance(value, Mapping):
        return "{" + ", ".join(f"{k}: {_value_text(v)}" for k, v in value.items()) + "}"
    if isinstance(value, str) and not all(c.isprintable() for c in value):
        return json.dumps(value, ensure_ascii=False)  # a double-quoted YAML scalar, on one line
    return _scalar(value)


def _parameter_lines(entry: Mapping[str, object], indent: str) -> list[str]:
    order = parameter_model.ENTRY_KEYS
    keys = [k for k in order if k in entry] + sorted(k for k in entry if k not in order)
    lines = []
    for n, key in enumerate(keys):
        value = entry[key]
        if key in ("integer_range", "floating_point_range") and isinstance(value, Mapping):
            value = {k: value[k] for k in parameter_model.RANGE_KEYS if k in value}
        lines.append(f"{indent}{'- ' if n == 0 else '  '}{key}: {_value_text(value)}")
    return lines


def _entry_lines(entry: Mapping[str, object], indent: str) -> list[str]:
    keys = [k for k in ENTRY_KEYS if k in entry] + sorted(k for k in entry if k not in ENTRY_KEYS)
    lines: list[str] = []
    for n, key in enumerate(keys):
        lead = indent + ("- " if n == 0 else "  ")
        value = entry[key]
        if key == "qos":
            lines.append(f"{lead}qos: {_qos_text(value)}")
        elif isinstance(value, Mapping):
            lines.append(f"{lead}{key}:")
            sub = [k for k in ACTION_HASHED_PARTS if k in value] + sorted(k for k in value if k not in ACTION_HASHED_PARTS)
            for k in sub:
                lines.append(f"{indent}    {k}: {_scalar(value[k])}")
        else:
            lines.append(f"{lead}{key}: {_scalar(value)}")
    return lines


def dump_nodes(nodes: Mapping[str, ContractNode]) -> str:
    """The ``nodes:`` block, deterministic (see the module docstring)."""
    nodes = normalize_nodes(nodes)
    if not nodes:
        return "nodes: {}\n"
    lines = ["nodes:"]
    for fqn in sorted(nodes):
        lines.append(f"  {_scalar(fqn)}:")
        node = nodes[fqn]
        if unstable_model.NODE_KEY in node:
            lines.append(f"    {unstable_model.NODE_KEY}: {_scalar(node['unstable_name'])}")
        if LIFECYCLE in node:
            lines.append(f"    {LIFECYCLE}: {_scalar(node[LIFECYCLE])}")
        if DESTROYED_AT in node:
            lines.append(f"    {DESTROYED_AT}: {_scalar(node[DESTROYED_AT])}")
        for list_name in LISTS:
            entries = sorted(node[list_name], key=lambda e: str(e.get("name", "")))
            if not entries:
                lines.append(f"    {list_name}: []")
                continue
            lines.append(f"    {list_name}:")
            for entry in entries:
                lines.extend(_entry_lines(entry, "      "))
        if PARAMETERS in node:
            params = sorted(node[PARAMETERS], key=lambda e: str(e.get("name", "")))
            lines.append(f"    {PARAMETERS}:" + ("" if params else " []"))
            for param in params:
                lines.extend(_parameter_lines(param, "      "))
    return "\n".join(lines) + "\n"


def render(nodes: Mapping[str, ContractNode], header: str = DEFAULT_HEADER) -> str:
    """A complete new contract file."""
    if header and not header.endswith("\n"):
        header += "\n"
    return header + dump_nodes(nodes)


def split_text(text: str) -> tuple[str, str] | None:
    """``(header, trailer)`` around the top-level ``nodes`` block of ``text``, or None when the
    file has no block-style top-level ``nodes`` key."""
    block = yaml_blocks.top_level_block(text, "nodes")
    if block is None:
        return None
    lines, first, end = block
    header = "".join(lines[:first])
    trailer = "".join(lines[end:])  # with the comment lines directly above the next key
    if header and not header.endswith("\n"):
        header += "\n"
    return header, trailer


def update_text(old_text: str, nodes: Mapping[str, ContractNode]) -> str:
    """``old_text`` with only its ``nodes`` block replaced (see the module docstring). Files are
    written by :mod:`pytest_rmw_introspect.check.golden`, the one writer."""
    parts = split_text(old_text) if old_text.strip() else None
    if parts is None:
        if old_text.strip() and "contract_version" in old_text and split_text(old_text + "\nnodes: {}\n"):
            # a file without `nodes:` (only a header): keep it all and append the block
            base = old_text if old_text.endswith("\n") else old_text + "\n"
            return base + dump_nodes(nodes)
        return render(nodes)
    header, trailer = parts
    return header + dump_nodes(nodes) + trailer


def with_distribution(text: str, distribution: str | None, *, add_missing: bool = True) -> str:
    """``text`` recording ``distribution`` in its top-level ``ros_distribution:`` line: the line
    is replaced where the header has one, else (``add_missing``) added after
    ``contract_version:`` (or first). None, or a text with no ``nodes:`` block to find the
    header by, leaves it unchanged."""
    parts = split_text(text) if distribution else None
    if parts is None:
        return text
    header, _trailer = parts
    line = f"{DISTRIBUTION_KEY}: {distribution}\n"
    lines = header.splitlines(keepends=True)
    for i, old in enumerate(lines):
        if old.startswith(f"{DISTRIBUTION_KEY}:"):
            lines[i] = line
            break
    else:
        if not add_missing:
            return text
        at = next((i + 1 for i, old in enumerate(lines) if old.startswith("contract_version:")), 0)
        lines.insert(at, line)
    return "".join(lines) + text[len(header):]


def _keep_destroyed_at(old: ContractNode | InterfaceEntry, new: ContractNode | InterfaceEntry) -> None:
    """``new`` keeps ``old``'s ``destroyed_at`` when both are ages of the same destruction."""
    before, now = old.get(DESTROYED_AT), new.get(DESTROYED_AT)
    if isinstance(before, (int, float)) and isinstance(now, (int, float)) \
            and abs(before - now) <= DESTROYED_AT_TOLERANCE_S:
        new[DESTROYED_AT] = before


def preserve_spelling(old_nodes: Mapping[str, ContractNode], new_nodes: Mapping[str, ContractNode]) -> ContractNodes:
    """Adopt the contract's own spelling where it means the same as the capture.

    For an entry present in both: a QoS written as a profile name (or with fewer fields) that
    expands to the captured QoS is kept as written; a ``type_hash`` or ``qos`` the contract
    leaves out (not compared) stays left out, and so does a parameter's ``default_value``; a
    ``destroyed_at`` within ``DESTROYED_AT_TOLERANCE_S`` of the contract's is kept as written.
    New entries are taken as captured (a node that did not state its parameters gets them).
    """

    old_nodes = normalize_nodes(old_nodes)
    out = normalize_nodes(new_nodes)
    for fqn, node in out.items():
        old_node = old_nodes.get(fqn)
        if old_node is None:
            continue
        _keep_destroyed_at(old_node, node)
        old_params = {e.get("name"): e for e in old_node.get(PARAMETERS) or []}
        for i, parameter in enumerate(node.get(PARAMETERS) or []):
            old_parameter = old_params.get(parameter.get("name"))
            if old_parameter is not None and "default_value" not in old_parameter and "default_value" in parameter:
                parameter = parameter.copy()
                del parameter["default_value"]
                node[PARAMETERS][i] = parameter
        for list_name in LISTS:
            old_by_name = {e.get("name"): e for e in old_node[list_name]}
            for i, entry in enumerate(node[list_name]):
                old = old_by_name.get(entry.get("name"))
                if old is None:
                    continue
                entry = entry.copy()
                _keep_destroyed_at(old, entry)
                if "type_hash" not in old:
                    entry.pop("type_hash", None)
                if "qos" in entry:
                    # a service without `qos` has the services default (a capture writes it only
                    # where it differs): a new value is written; a topic's is not compared
                    if "qos" not in old:
                        if list_name not in SERVICE_LISTS:
                            entry.pop("qos")
                    else:
                        try:
                            if qos_module.expand(old["qos"]) == qos_module.expand(entry["qos"]):
                                entry["qos"] = old["qos"]
                        except ValueError:
                            pass
                node[list_name][i] = entry
    return out
