"""What a launch file gives a node that the node silently ignores.

ROS 2 ignores, without a word, a parameter override the node does not declare, a parameters
file section keyed to a node name that no node has, and a remapping whose ``from`` matches none
of the node's names. Each is a configuration that "works" and has no effect, the typical
misconfiguration a robot ships with. :func:`check` compares what each process of a launched
system was given (:class:`Given`, built from the launch file by ``check.system_pipeline``)
with what its nodes declared and created (their capture), and returns one finding per ignored
setting: ``PARAM_NOT_DECLARED``, ``PARAMS_FILE_SECTION_UNMATCHED``, ``REMAP_NEAR_MISS`` and the
``REMAP_UNUSED*`` notes, and a given parameter name that no ROS parameter can have,
``PARAM_NAME_INVALID``. Each rule's severity is the one its record on real bring-ups supports
(docs/drift-rules.md, "Compatibility rules"): a remapping that changed nothing is a note
(``REMAP_UNUSED`` when another node uses its target, ``REMAP_UNUSED_UNCONNECTED`` when none does:
dead remappings are common in real launch files and harmless) unless its ``from`` is a near miss
of a name the node does create (``REMAP_NEAR_MISS``, BREAKING: the typo that leaves the node
unwired); a parameter value that points at nothing is BREAKING only for the files of an
installed package (``PARAM_PATH_MISSING``), a note for a file of the capture machine
(``PARAM_PATH_MACHINE_LOCAL``, never for a parameter the node writes: :func:`node_writes`) and
for a hardware device (``PARAM_DEVICE_ABSENT``: the capture machine is not the robot).

Parameters files are matched as rclcpp and rclpy match them: a section key is a fully
qualified node name (a leading ``/`` is added when missing, so ``lidar:`` is the node
``/lidar`` only), ``*`` stands for one name token and ``**`` for any number of them; a
nested key (``robot1: {lidar: {ros__parameters: ...}}``) is the path ``/robot1/lidar``.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal

from ..model.contract_shapes import ContractNode
from ..model.name_patterns import section_key_matches
from ..model.parameters import flatten
from ..model.vocabulary import LISTS, PARAMETERS, Severity, is_infrastructure_parameter
from .similarity import typo_distance
from .wiring import near_miss

RULES: dict[str, Severity] = {
    "PARAM_NOT_DECLARED": Severity.BREAKING,
    "PARAM_NAME_INVALID": Severity.BREAKING,
    "PARAMS_FILE_SECTION_UNMATCHED": Severity.BREAKING,
    "REMAP_NEAR_MISS": Severity.BREAKING,
    "REMAP_UNUSED": Severity.NOTE,
    "REMAP_UNUSED_UNCONNECTED": Severity.NOTE,
    "PARAM_PATH_MISSING": Severity.BREAKING,
    "PARAM_PATH_MACHINE_LOCAL": Severity.NOTE,
    "PARAM_DEVICE_ABSENT": Severity.NOTE,
}
#: rules reported among the notes of a check, not as findings (a note never fails, at any threshold)
NOTES = frozenset({"PARAM_DEVICE_ABSENT"})


@dataclass(frozen=True)
class MissingFile:
    """What a parameter value points at that is not there: ``why`` ends a sentence ("...
    points at ``why``"); ``where`` says whose file it is: ``package`` (an installed package's, or
    a package that is not installed: missing on every machine), ``machine`` (outside every ROS
    prefix: a file of one machine) or ``device`` (hardware)."""

    why: str
    where: Literal["package", "machine", "device"]


#: a parameter value → what it points at that is missing (None: not a path, or it exists)
MissingPath = Callable[[str], "MissingFile | None"]

#: the words of a parameter name that say the node writes the file (it need not exist before)
_WRITES = frozenset({"output", "out", "save", "saved", "log", "logs", "logging", "record", "recording", "dump",
                     "write", "export", "cache"})
_DIRECTORY = frozenset({"dir", "directory", "folder"})
#: what a parameter name may hold: name tokens joined by dots; ``/`` for rclcpp's
#: ``qos_overrides./topic.publisher.depth``, ``-`` as some drivers spell names
_PARAMETER_NAME = re.compile(r"[A-Za-z0-9_/-]+(?:\.[A-Za-z0-9_/-]+)*")


def node_writes(name: str) -> bool:
    """Whether the parameter ``name`` names a file or directory the node writes (by its words:
    ``output_file``, ``save_path``, ``log_dir``, ``waypoints_output``, ``map.out_file``)."""
    words = [w for w in re.split(r"[._/-]+", name.lower()) if w]
    return bool(words) and (any(w in _WRITES for w in words) or words[-1] in _DIRECTORY)


def valid_parameter_name(name: str) -> bool:
    """Whether ``name`` can be a ROS parameter name (no spaces, parentheses, colons, commas:
    a YAML comment that lost its ``#`` becomes a key like ``(see x description) (bool, default``)."""
    return _PARAMETER_NAME.fullmatch(name) is not None


@dataclass(frozen=True)
class GivenParameter:
    """A parameter set on the command line the launch file builds (``<param>``, ``-p``)."""

    name: str
    source: str  # where: ``robot.launch.xml:12``


@dataclass(frozen=True)
class ParamsFile:
    """A parameters file given to a process: its node sections and their parameter names."""

    shown: str
    sections: tuple[tuple[str, tuple[str, ...]], ...]  # (node key as written, flattened names)


@dataclass(frozen=True)
class Given:
    """What the launch file gives one process."""

    parameters: tuple[GivenParameter, ...] = ()
    files: tuple[ParamsFile, ...] = ()
    remappings: tuple[tuple[str, str], ...] = ()
    where: str | None = None


def sections(data: Any) -> tuple[tuple[str, tuple[str, ...]], ...]:
    """The node sections of a parsed parameters file: ``(node key, parameter names)``, the
    names flattened with dots (``{a: {b: 1}}`` is ``a.b``), nested node keys joined with ``/``."""
    found: list[tuple[str, tuple[str, ...]]] = []

    def walk(mapping: Mapping, path: list[str]) -> None:
        for key, value in mapping.items():
            if key == "ros__parameters" and path:
                found.append(("/".join(path), tuple(flatten(value))))
            elif isinstance(value, Mapping):
                walk(value, [*path, str(key)])

    if isinstance(data, Mapping):
        walk(data, [])
    return tuple(found)


def section_matches(key: str, fqn: str) -> bool:
    """Whether the parameters file section ``key`` applies to the node ``fqn`` (in linear time
    however many ``**`` it has: issue 50, N26)."""
    return section_key_matches(key, fqn)


def resolve(name: str, node_fqn: str) -> str:
    """A topic, service or action name as the node ``node_fqn`` resolves it (``~`` is the node)."""
    if name.startswith("/"):
        return name
    if name == "~" or name.startswith("~/"):
        return node_fqn + name[1:]
    namespace = node_fqn.rpartition("/")[0]
    return f"{namespace}/{name}"


def _names(node: ContractNode) -> set[str]:
    return {str(entry.get("name")) for kind in LISTS for entry in (node or {}).get(kind) or []}


@dataclass(frozen=True)
class Finding:
    rule: str
    label: str  # the process
    node: str  # the node (or the launch file's name for it)
    name: str  # the parameter, the section key, the remapping
    message: str


def given_findings(processes: Sequence[Any], missing_path: MissingPath | None = None) -> list[Finding]:
    """Every ignored setting of the launched ``processes`` (``compare.compatibility.LaunchedProcess``
    with ``given``), and with ``missing_path`` every parameter value that points at a file that
    does not exist."""
    findings: list[Finding] = []
    # a file given to several processes (one file for the whole robot) is matched against them all
    receivers: dict[str, list[tuple[Any, str]]] = {}
    system = _System(processes)
    for process in processes:
        given: Given | None = getattr(process, "given", None)
        if given is None:
            continue
        for params_file in given.files:
            receivers.setdefault(params_file.shown, []).extend((process, fqn) for fqn in process.nodes)
        # a component of a container gets what its LoadNode request gives it, not the container
        components: Mapping[str, Given] = getattr(process, "component_given", None) or {}
        findings += _invalid_names(process, [given, *components.values()], system)
        # what the process is given reaches every node of it but the components
        findings += _undeclared(process, given, {fqn: n for fqn, n in process.nodes.items() if fqn not in components})
        for fqn, node in process.nodes.items():
            if missing_path is not None:
                findings += _missing_paths(process, fqn, node, missing_path)
            if fqn in components:  # its LoadNode request's parameters and remappings reach this node alone
                findings += _undeclared(process, components[fqn], {fqn: node})
                findings += _unused_remappings(process, components[fqn], {fqn: node}, fqn, system)
        findings += _unused_remappings(process, given, process.nodes, process.expected, system)
    everyone = sorted({fqn for process in processes for fqn in process.nodes})
    seen: set[tuple[str, str]] = set()
    for process in processes:
        given = getattr(process, "given", None)
        if given is None or not process.nodes:  # no node: LAUNCHED_NODE_NOT_CREATED says it
            continue
        for params_file in given.files:
            for key, _ in params_file.sections:
                if (params_file.shown, key) in seen:
                    continue
                seen.add((params_file.shown, key))
                nodes = sorted({fqn for _, fqn in receivers[params_file.shown]})
                if any(section_matches(key, fqn) for fqn in nodes):
                    continue
                elsewhere = [fqn for fqn in everyone if section_matches(key, fqn)]
                why = (f"; {', '.join(elsewhere)} would match it but is not given this file" if elsewhere
                       else "; the node may have been renamed (a section key without a leading / is a node in "
                            "the root namespace; /**/NAME matches NAME in any namespace)")
                findings.append(Finding(
                    "PARAMS_FILE_SECTION_UNMATCHED", process.label, process.expected or nodes[0], key,
                    f"parameters file {params_file.shown} has a section `{key}` that matches none of the nodes it "
                    f"is given to ({', '.join(nodes)}), so its parameters reach no node{why}"))
    return findings


class _System:
    """The names every node of a system uses, and the invalid parameter names already reported."""

    def __init__(self, processes: Sequence[Any]) -> None:
        self.users: dict[str, set[str]] = {}  # topic, service or action name → the nodes that use it
        for process in processes:
            for fqn, node in process.nodes.items():
                for name in _names(node):
                    self.users.setdefault(name, set()).add(fqn)
        self.reported: set[tuple[str, str]] = set()

    def used_elsewhere(self, name: str, nodes: Mapping[str, ContractNode]) -> list[str]:
        """The nodes other than ``nodes`` that use ``name``."""
        return sorted(self.users.get(name, set()) - set(nodes))


def _invalid_names(process: Any, givens: Sequence[Given], system: _System) -> list[Finding]:
    """Every parameter name given to ``process`` that no ROS parameter can have, once per source."""
    out = []
    node = process.expected or (sorted(process.nodes)[0] if process.nodes else process.label)
    for given in givens:
        named = [(p.name, p.source) for p in given.parameters]
        named += [(name, f"{f.shown} [{key}]") for f in given.files for key, names in f.sections for name in names]
        for name, source in named:
            if valid_parameter_name(name) or (source, name) in system.reported:
                continue
            system.reported.add((source, name))
            out.append(Finding(
                "PARAM_NAME_INVALID", process.label, node, name,
                f"`{name}` ({source}) cannot be a ROS parameter name (a parameter name is words of letters, digits "
                "and `_` joined by `.`): no node reads it, whatever it declares or accepts; a comment that lost "
                "its `#`? Restore the `#`, or fix the name"))
    return out


def _undeclared(process: Any, given: Given, nodes: Mapping[str, ContractNode]) -> list[Finding]:
    """The parameters ``given`` to ``nodes`` (the nodes of one process, or one component) that
    no node receiving them declares. A parameter given to the process (``<param>``, ``-p``)
    reaches every node of it, a parameters file section every node it matches, as ROS 2 gives
    them; in a process of several nodes only the node that reads one declares it, so a
    parameter counts as declared when any node it reached declares it (a section keyed to one
    node by its name reaches that node alone, which must declare it)."""
    received: dict[tuple[str, tuple[str, ...]], str] = {}  # (parameter, the nodes it reaches) → where
    for parameter in given.parameters:
        received.setdefault((parameter.name, tuple(sorted(nodes))), parameter.source)
    for params_file in given.files:
        for key, names in params_file.sections:
            reached = tuple(sorted(fqn for fqn in nodes if section_matches(key, fqn)))
            for name in names if reached else ():
                received.setdefault((name, reached), f"{params_file.shown} [{key}]")
    out = []
    for (name, reached), source in sorted(received.items()):
        if is_infrastructure_parameter(name) or not valid_parameter_name(name):
            continue  # an invalid name is PARAM_NAME_INVALID's
        read = [nodes[fqn].get(PARAMETERS) for fqn in reached]
        if not reached or any(parameters is None for parameters in read):
            continue  # parameters not read (a C node, read_parameters: false): nothing to compare with
        declared = {str(p.get("name")) for parameters in read for p in parameters or []}
        if name in declared:
            continue
        close = _closest(name, declared)
        if len(reached) == 1:
            [fqn] = reached
            whom, lists = f"but {fqn} does not declare it", "it declares"
        else:
            fqn = process.expected if process.expected in reached else reached[0]
            whom, lists = f"to the {len(reached)} nodes of its process ({', '.join(reached)}), none of which declares it", "they declare"
        hint = f"; did you mean `{close}`?" if close else f"; {lists}: {', '.join(sorted(declared)) or 'none'}"
        out.append(Finding("PARAM_NOT_DECLARED", process.label, fqn, name,
                           f"parameter `{name}` is given ({source}) {whom}: ROS 2 ignores it without a word{hint}"))
    return out


_PATH_RULES = {"package": "PARAM_PATH_MISSING", "machine": "PARAM_PATH_MACHINE_LOCAL", "device": "PARAM_DEVICE_ABSENT"}
_PATH_CONSEQUENCES = {
    "package": "the node reads nothing (or fails when it needs it), on every machine this package is installed "
               "on; install the file or fix the value",
    "machine": "a file of one machine, outside every ROS prefix: the node finds it only where it was put by "
               "hand; check that the machines that run the node have it, or install it with a package",
}
#: a device note, said once per run beside the findings: short, and without the stand-in advice
#: (that is for a process that failed for lack of its device: ``run.system_capture``)
_DEVICE_NOTE = "not judged: the robot has it"


def _missing_paths(process: Any, fqn: str, node: ContractNode, missing_path: MissingPath) -> list[Finding]:
    out = []
    for parameter in node.get(PARAMETERS) or []:
        value = parameter.get("default_value")
        name = str(parameter.get("name"))
        for text in value if isinstance(value, list) else [value]:
            missing = missing_path(text) if isinstance(text, str) else None
            if missing is None or (missing.where != "device" and node_writes(name)):
                continue  # a file the node writes need not exist before it runs
            if missing.where == "device":  # a note (NOTES): its node is named where it is said
                message = f"parameter `{name}` is {text!r}: {missing.why} ({_DEVICE_NOTE})"
            else:
                message = (f"parameter `{name}` of {fqn} is {text!r}, which points at {missing.why}: "
                           f"{_PATH_CONSEQUENCES[missing.where]}")
            out.append(Finding(_PATH_RULES[missing.where], process.label, fqn, name, message))
    return out


def _closest(name: str, declared: set[str]) -> str | None:
    # a hint only: judged by the declared name's length, so `rte` finds `rate`
    near = [(distance, d) for d in declared if (distance := typo_distance(name, d, shortest=len(d))) is not None]
    return min(near)[1] if near else None


def _unused_remappings(process: Any, given: Given, nodes: Mapping[str, ContractNode],
                       expected: str | None, system: _System) -> list[Finding]:
    """The remappings of ``given`` that change none of the names of ``nodes`` (a process's
    nodes, or the one node a component's load request made): ``REMAP_NEAR_MISS`` (BREAKING)
    when the source is a near miss of a name the node created (a typo: the node stays
    unwired), else a note, whether or not another node uses the target (a leftover, or a name
    the node creates in some configurations only)."""
    out: list[Finding] = []
    if not nodes:
        return out
    for source, target in given.remappings:
        if source.startswith("__") or ":" in source:  # __node, __ns, node-prefixed rules
            continue
        fqn = sorted(nodes)[0]
        wanted, meant = resolve(source, fqn), resolve(target, fqn)
        if wanted == meant:  # an identity remapping changes nothing and means nothing
            continue
        own = set().union(*(_names(node) for node in nodes.values()))
        if meant in own:
            continue
        others = system.used_elsewhere(meant, nodes)
        near = sorted((found[0], name) for name in own if (found := near_miss(wanted, name)) is not None)
        if near:
            rule = "REMAP_NEAR_MISS"
            evidence = (f"; did you mean `{near[0][1]}`, a name the node does create? (`{wanted}` is a near miss of it: "
                        "the node stays unwired)")
        elif others:
            rule = "REMAP_UNUSED"
            evidence = (f"; {', '.join(others)} use{'s' if len(others) == 1 else ''} {meant}, but this node creates "
                        f"nothing named {wanted} (a leftover remapping, or a name it creates in other configurations "
                        "only: a note)")
        else:
            rule = "REMAP_UNUSED_UNCONNECTED"
            evidence = ("; no other node uses the target either (a name the node creates in some configurations "
                        "only?: a note)")
        out.append(Finding(
            rule, process.label, expected or fqn,
            f"{source}:={target}",
            f"the remapping {source} -> {target} (at {given.where or 'the launch file'}) changed none of the names of "
            f"{', '.join(sorted(nodes))}: no topic, service or action is named {meant}, so the node never used "
            f"{wanted}{evidence}"))
    return out
