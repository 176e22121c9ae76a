"""System contracts (``*.system.yaml``): a whole robot, as a launch file starts it.

::

    # comments and keys above `processes:` survive updates
    system_version: 1
    interface_version: 2.0.0         # optional: the version the `diff --against` gate compares
    launch:                          # what starts the system
      package: my_robot_bringup      # with `file`: found like `ros2 launch PACKAGE FILE`
      file: robot.launch.xml         # (or `path: launch/robot.launch.xml`, relative to this file)
      arguments: {use_lidar: "true"}
      allow_unsupported: false       # true: capture what the launch reader supports, note the rest
    rmw: rmw_cyclonedds_cpp          # optional: the middleware the robot runs (its QoS rules judge QoS)
    target: {timeout: 30}            # optional: settle, timeout, horizon, lifecycle, read_parameters, env
    options: {fail_on: any, system_fail_on: breaking}
    external:                        # what comes from outside the launch files, and who provides it
      publishers: {/initialpose: rviz, /cmd_vel: teleop}
      service_servers: {/robot/set_map: fleet manager}
    stand_ins:                       # processes not run here (they need hardware): model.stand_ins
      - {executable: lidar_driver, contract: contracts/lidar.interfaces.yaml}
    processes:                       # every process the launch file starts, in launch order
      - package: my_robot_bringup
        executable: lidar_driver
        name: /robot/lidar           # the node name the launch file gives (null: the program's)
        nodes: [/robot/lidar]        # the nodes the process created
    nodes:                           # every node of the system, as in a node contract
      /robot/lidar: {publishers: [...], ...}

``nodes`` is exactly the ``nodes`` block of a node contract, so a system drifts like a node
contract does (``compare.drift``). ``processes`` says which process created which node: the
compatibility rules (``compare.compatibility.check_launched``) read it for duplicate node names and for
launched processes that created no node. ``external`` declares the outside world: a
requester nobody in the system provides for fails the check unless it is declared there
(``compare.wiring``). Two processes creating one node name share one entry
under ``nodes`` (the union of their interfaces; the duplicate itself is a BREAKING system problem).

Loading validates against the node contract schema's definitions (``schema()`` builds the
system schema from them) and reports file, line, place and reason like the node contract
loader. Writing is deterministic; updating keeps the text above the top-level ``processes:``
key byte for byte and regenerates ``processes`` and ``nodes``.
"""

from __future__ import annotations

import copy
import functools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal, cast, get_args

import yaml

from ..errors import ContractError, InputError
from . import acceptance, middlewares, stand_ins, untrusted
from . import contract as contract_module
from . import qos as qos_module
from . import unstable_names as unstable_model
from .contract_shapes import ContractNode, ContractNodes, ContractOptions, LaunchBlock, ProcessEntry, TargetBlock, empty_node
from .locate import line_at
from .option_tables import COMPARISON, TARGET, FrontEnd, schema_definition
from .paths import shown
from .stand_ins import StandIn
from .vocabulary import LABELS, LISTS

SYSTEM_VERSION = 1
#: the key that says which middleware the system runs on (``model.middlewares``)
RMW_KEY = "rmw"
SUFFIX = ".system.yaml"
#: target options that apply to every process of a system
SYSTEM_TARGET_KEYS = TARGET.names(FrontEnd.SYSTEM)
#: the keys of a process entry, in the order they are written
ProcessKey = Literal["package", "executable", "name", "nodes"]
PROCESS_KEYS: tuple[ProcessKey, ...] = get_args(ProcessKey)

DEFAULT_HEADER = (
    "# System contract checked by pytest-rmw-introspect: every process a launch file starts,\n"
    "# the nodes they create and their interfaces. Regenerate with `pytest --update-golden` or\n"
    "# `rmw-introspect check --update`; comments and keys above `processes:` are kept.\n"
    f"system_version: {SYSTEM_VERSION}\n"
)


@functools.lru_cache(maxsize=1)
def schema() -> dict[str, Any]:
    """The JSON Schema of system contracts, built from the node contract schema's definitions."""
    base = contract_module.schema()
    definitions = copy.deepcopy(base["definitions"])
    definitions["options"] = schema_definition(COMPARISON, FrontEnd.SYSTEM)
    target = definitions["target"]
    definitions["system_target"] = {
        "description": "Target options applied to every process of the system.",
        "type": "object",
        "additionalProperties": False,
        "properties": {k: target["properties"][k] for k in SYSTEM_TARGET_KEYS},
    }
    definitions["launch"] = {
        "description": "The launch file that starts the system.",
        "type": "object",
        "additionalProperties": False,
        "properties": {
            "package": {"type": "string", "minLength": 1},
            "file": {"type": "string", "minLength": 1},
            "path": {"type": "string", "minLength": 1},
            "arguments": {"type": "object", "additionalProperties": {"type": ["string", "number", "boolean"]}},
            "allow_unsupported": {"type": "boolean"},
        },
    }
    declarations = {"type": ["object", "null"], "propertyNames": {"pattern": "^/"},
                    "additionalProperties": {"type": "string", "minLength": 1}}
    definitions["external"] = {
        "description": "Interfaces provided or requested outside the launch files, by fully qualified name, "
                       "with who provides or requests them (`/initialpose: rviz`).",
        "type": ["object", "null"],
        "additionalProperties": False,
        "properties": {list_name: declarations for list_name in LISTS},
    }
    definitions["stand_ins"] = copy.deepcopy(stand_ins.SCHEMA)
    definitions["process"] = {
        "type": "object",
        "additionalProperties": False,
        "required": ["executable", "nodes"],
        "properties": {
            "package": {"type": ["string", "null"]},
            "executable": {"type": "string", "minLength": 1},
            "name": {"type": ["string", "null"]},
            "nodes": {"type": "array", "items": {"type": "string"}},
        },
    }
    return {
        "$schema": base.get("$schema", "http://json-schema.org/draft-07/schema#"),
        "title": "pytest-rmw-introspect system contract",
        "type": "object",
        "required": ["system_version", "launch"],
        "additionalProperties": False,
        "properties": {
            "system_version": {"const": SYSTEM_VERSION},
            contract_module.VERSION_KEY: {"$ref": "#/definitions/interface_version"},
            "launch": {"$ref": "#/definitions/launch"},
            RMW_KEY: {"description": "The middleware (rmw implementation) the system runs on: QoS is judged by its "
                                     "rules (default: RMW_IMPLEMENTATION in the launch environment, else the DDS "
                                     "rules of rmw_dds_common).", "enum": list(middlewares.KNOWN)},
            "target": {"$ref": "#/definitions/system_target"},
            "options": {"$ref": "#/definitions/options"},
            "external": {"$ref": "#/definitions/external"},
            stand_ins.SECTION_KEY: {"$ref": "#/definitions/stand_ins"},
            "processes": {"type": ["array", "null"], "items": {"$ref": "#/definitions/process"}},
            "nodes": copy.deepcopy(base["properties"]["nodes"]) | {"type": ["object", "null"]},
            "accept": {"$ref": "#/definitions/accept"},
            "unstable_names": {"$ref": "#/definitions/unstable_names"},
        },
        "definitions": definitions,
    }


@dataclass
class SystemContract:
    """A loaded system contract (``nodes`` normalised like a node contract's)."""

    path: Path | None
    launch: LaunchBlock
    processes: list[ProcessEntry]
    nodes: ContractNodes
    target: TargetBlock | None = None
    options: ContractOptions = field(default_factory=lambda: ContractOptions())
    text: str = ""
    #: the findings it accepts on purpose (``accept:``)
    accept: tuple[acceptance.Acceptance, ...] = ()
    #: the declared outside world: list name → interface name → who provides or requests it
    external: dict[str, dict[str, str]] = field(default_factory=dict)
    #: processes not run where the system is checked, and the files their interfaces come from
    stand_ins: tuple[StandIn, ...] = ()
    #: the patterns of node names that change every run it declares (``unstable_names:``)
    unstable_names: tuple[unstable_model.NamePattern, ...] = ()
    #: the version of the interface it promises (``interface_version: MAJOR.MINOR.PATCH``), if stated
    interface_version: str | None = None
    #: the middleware it says it runs on (``rmw:``), if stated
    rmw: str | None = None

    def middleware(self, option: str | None = None, launched: Sequence[tuple[str, Mapping[str, str]]] = ()) -> str | None:
        """The middleware whose QoS rules judge this system: ``rmw:``, else RMW_IMPLEMENTATION in its
        launch environment (its ``target: {env:}`` and what the launch file gives each process,
        ``launched``: where, environment), else ``option`` (``--rmw``), else None (the DDS rules).
        Raises ContractError when the launch environment names a middleware the rules do not know,
        or several."""
        if self.rmw is not None:
            return self.rmw
        shown_path = shown(self.path) if self.path else "<system contract>"
        environments = [("target.env", (self.target or {}).get("env") or {}), *launched]
        return middlewares.choose(environments, option, shown=shown_path)

    def process_nodes(self) -> list[tuple[ProcessEntry, ContractNodes]]:
        """Each process with the contract entries of the nodes it created."""
        return [(p, {fqn: self.nodes.get(fqn) or empty_node() for fqn in p.get("nodes") or []})
                for p in self.processes]


# ---------------------------------------------------------------------------- loading


def load(path: str | Path) -> SystemContract:
    """Read and validate a system contract (raises ContractError)."""
    path = Path(path)
    try:
        text = untrusted.read_text(path)
    except FileNotFoundError:
        raise ContractError(path, None, "the file does not exist") from None
    except InputError as exc:
        raise ContractError(path, None, exc.reason) from None
    return loads(text, path=path)


def loads(text: str, *, path: str | Path | None = None) -> SystemContract:
    """Parse and validate system contract text; ``path`` is used in messages and to resolve
    ``launch: {path: ...}``."""
    path = Path(path) if path is not None else None
    # the same bounded reading as node contracts: unique string keys, bounded nesting and aliases
    try:
        root = untrusted.compose_yaml(text)
        if root is not None:
            untrusted.check_tree(root)
        data = untrusted.construct(root) if root is not None else None
    except InputError as exc:
        raise ContractError(path, contract_module.format_location(list(exc.location)) or None, exc.reason,
                            line=exc.line) from None
    if data is None:
        raise ContractError(path, None, "the file is empty; it needs at least `system_version: 1` and `launch:`")
    if not isinstance(data, Mapping):
        raise ContractError(path, None, f"the document is a {type(data).__name__}, not a mapping", line=1)
    if "contract_version" in data and "system_version" not in data:  # named *.system.yaml
        raise ContractError(path, None, "this is a node contract (it says `contract_version`), but a name ending "
                            f"in {SUFFIX} marks a system contract: rename it to NAME.interfaces.yaml, or make it "
                            "a system contract (`system_version: 1` and `launch:`)",
                            line=line_at(root, ["contract_version"]))
    _validate(root, data, path)
    # validated by the schema from here on: the blocks have the keys and value types of their shapes
    launch = cast(LaunchBlock, dict(data["launch"]))
    has_file = "file" in launch or "package" in launch
    if has_file == ("path" in launch) or ("file" in launch) != ("package" in launch):
        raise ContractError(path, "launch", "name the launch file with `package` and `file` (like ros2 launch), "
                            "or with `path` (relative to this file), not both", line=line_at(root, ["launch"]))
    too_broad = unstable_model.refused(data)
    if too_broad is not None:
        raise ContractError(path, contract_module.format_location(too_broad[0]), too_broad[1],
                            line=line_at(root, too_broad[0]))
    nodes = contract_module.normalize_nodes(data.get("nodes") or {})
    for fqn, node in nodes.items():
        for list_name in LISTS:
            seen: set[str] = set()
            for i, entry in enumerate(node[list_name]):
                location = ["nodes", fqn, list_name, i]
                if entry["name"] in seen:
                    raise ContractError(path, contract_module.format_location(location + ["name"]),
                                        f"duplicate {LABELS[list_name]} {entry['name']!r} in node {fqn}",
                                        line=line_at(root, location))
                seen.add(entry["name"])
                if "qos" in entry:
                    try:
                        qos_module.expand(entry["qos"])
                    except ValueError as exc:
                        raise ContractError(path, contract_module.format_location(location + ["qos"]), str(exc),
                                            line=line_at(root, location + ["qos"])) from None
    contract_module.check_parameters(root, nodes, path)
    processes = [cast(ProcessEntry, dict(p)) for p in data.get("processes") or []]
    for i, process in enumerate(processes):
        for fqn in process.get("nodes") or []:
            if fqn not in nodes:
                raise ContractError(path, f"processes[{i}].nodes", f"node {fqn} is not listed under `nodes:`",
                                    line=line_at(root, ["processes", i, "nodes"]))
    return SystemContract(path=path, launch=launch, processes=processes, nodes=nodes,
                          target=cast(TargetBlock, dict(data["target"])) if data.get("target") is not None else None,
                          options=cast(ContractOptions, dict(data.get("options") or {})), text=text,
                          accept=acceptance.from_entries(data.get(acceptance.SECTION_KEY),
                                                         source=shown(path) if path else "<system contract>",
                                                         line_of=lambda i: line_at(root, [acceptance.SECTION_KEY, i])),
                          external={k: dict(v) for k, v in (data.get("external") or {}).items() if v},
                          stand_ins=stand_ins.from_entries(data.get(stand_ins.SECTION_KEY),
                                                           line_of=lambda i: line_at(root, [stand_ins.SECTION_KEY, i])),
                          unstable_names=unstable_model.from_entries(data.get(unstable_model.SECTION_KEY)),
                          interface_version=data.get(contract_module.VERSION_KEY), rmw=data.get(RMW_KEY))


def _validate(root: yaml.Node | None, data: Any, path: Path | None) -> None:
    # Imported here, not at the top: jsonschema costs ~80 ms (as in model.contract).
    import jsonschema

    errors = list(jsonschema.Draft7Validator(schema()).iter_errors(data))
    if errors:
        raise contract_module.schema_error(root, errors, path, _reason)


def _reason(error: Any) -> str:
    """What a schema error of a system contract says."""
    if error.validator == "additionalProperties" and isinstance(error.instance, Mapping):
        allowed = sorted((error.schema.get("properties") or {}).keys())
        extra = sorted(set(error.instance) - set(allowed))
        return f"unknown key(s) {', '.join(map(repr, extra))}; allowed: {', '.join(allowed)}"
    if error.validator == "required":
        return str(error.message).replace("is a required property", "is required")
    if error.validator == "enum":
        return f"{error.instance!r} is not one of: {', '.join(map(str, error.validator_value))}"
    if error.validator == "const" and list(error.absolute_path) == ["system_version"]:
        return f"system_version {error.instance!r} is not supported; this plugin reads system_version {SYSTEM_VERSION}"
    return str(error.message)


# ---------------------------------------------------------------------------- writing


def _scalar(value: Any) -> str:
    if value is None:
        return "null"
    return yaml.safe_dump(value, default_flow_style=True, width=float("inf")).strip().removesuffix("\n...").strip()


def dump_processes(processes: Sequence[ProcessEntry]) -> str:
    """The ``processes:`` block, deterministic (launch order kept)."""
    if not processes:
        return "processes: []\n"
    lines = ["processes:"]
    for process in processes:
        keys = [k for k in PROCESS_KEYS if k in process]
        for n, key in enumerate(keys):
            lead = "  - " if n == 0 else "    "
            if key == "nodes":
                text = "[" + ", ".join(_scalar(v) for v in process["nodes"]) + "]"
            else:
                text = _scalar(process[key])
            lines.append(f"{lead}{key}: {text}")
    return "\n".join(lines) + "\n"


def render(processes: Sequence[ProcessEntry], nodes: Mapping[str, ContractNode], header: str = DEFAULT_HEADER) -> str:
    """A complete system contract: ``header`` (with ``system_version`` and ``launch:``), then
    ``processes`` and ``nodes``."""
    if header and not header.endswith("\n"):
        header += "\n"
    return header + dump_processes(processes) + contract_module.dump_nodes(nodes)


def update_text(old_text: str, processes: Sequence[ProcessEntry], nodes: Mapping[str, ContractNode]) -> str:
    """``old_text`` with its ``processes`` and ``nodes`` blocks regenerated: the text above the
    first of them is kept byte for byte, and so are top-level keys after them."""
    try:
        root = yaml.compose(old_text, Loader=yaml.SafeLoader)
    except yaml.YAMLError:
        root = None
    if not isinstance(root, yaml.MappingNode) or root.flow_style:
        return render(processes, nodes)
    lines = old_text.splitlines(keepends=True)
    keys = [(k.value if isinstance(k, yaml.ScalarNode) else None, k.start_mark) for k, _ in root.value]
    ours = [i for i, (name, mark) in enumerate(keys) if name in ("processes", "nodes") and mark.column == 0]
    if not ours:
        base = old_text if old_text.endswith("\n") else old_text + "\n"
        return base + dump_processes(processes) + contract_module.dump_nodes(nodes)
    header = "".join(lines[: keys[ours[0]][1].line])
    after = [i for i in range(len(keys)) if i > ours[-1] and keys[i][0] not in ("processes", "nodes")]
    trailer = "".join(lines[keys[after[0]][1].line:]) if after else ""
    if header and not header.endswith("\n"):
        header += "\n"
    return header + dump_processes(processes) + contract_module.dump_nodes(nodes) + trailer


def new_header(launch: LaunchBlock, *, target: TargetBlock | None = None,
               options: ContractOptions | None = None, how: str = "rmw-introspect capture --launch",
               external_proposal: str = "") -> str:
    """The header of a new system contract: how it was written, ``system_version``, ``launch:``
    (and ``target:``, ``options:`` when given), then ``external_proposal`` (a commented-out
    ``external:`` block, ``compare.wiring.proposal``)."""
    header = (
        f"# System contract written by `{how}`:\n"
        "# every process the launch file starts, the nodes they create and their interfaces.\n"
        "# Check it with `rmw-introspect check` or pytest (pytest-rmw-introspect); comments and\n"
        "# keys above `processes:` are kept when it is updated.\n"
        f"system_version: {SYSTEM_VERSION}\n"
    )
    blocks: dict[str, Any] = {"launch": dict(launch)}
    if target:
        blocks["target"] = dict(target)
    if options:
        blocks["options"] = dict(options)
    return header + yaml.safe_dump(blocks, sort_keys=False, default_flow_style=False, allow_unicode=True) \
        + external_proposal
