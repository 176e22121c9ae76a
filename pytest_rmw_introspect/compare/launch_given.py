"""What a launch file gives a node that the node silently ignores.

ROS 2 ignores, without a word, a parameter override the node does not declare, a parameters
file section keyed to a node name that no node has, and a remapping whose ``from`` matches none
of the node's names. Each is a configuration that "works" and has no effect, the typical
misconfiguration a robot ships with. :func:`check` compares what each process of a launched
system was given (:class:`Given`, built from the launch file by ``check.system_pipeline``)
with what its nodes declared and created (their capture), and returns one finding per ignored
setting: ``PARAM_NOT_DECLARED``, ``PARAMS_FILE_SECTION_UNMATCHED``, ``REMAP_UNUSED`` (all
BREAKING; rationale in docs/drift-rules.md, "Compatibility rules").

Parameters files are matched as rclcpp and rclpy match them: a section key is a fully
qualified node name (a leading ``/`` is added when missing, so ``lidar:`` is the node
``/lidar`` only), ``*`` stands for one name token and ``**`` for any number of them; a
nested key (``robot1: {lidar: {ros__parameters: ...}}``) is the path ``/robot1/lidar``.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from ..model.contract_shapes import ContractNode
from ..model.vocabulary import LISTS, PARAMETERS, Severity, is_infrastructure_parameter
from .similarity import typo_distance

RULES: dict[str, Severity] = {
    "PARAM_NOT_DECLARED": Severity.BREAKING,
    "PARAMS_FILE_SECTION_UNMATCHED": Severity.BREAKING,
    "REMAP_UNUSED": Severity.BREAKING,
    "PARAM_PATH_MISSING": Severity.BREAKING,
}
#: a parameter value → why the file it points at is missing (None: not a path, or it exists)
MissingPath = Callable[[str], "str | None"]


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
                found.append(("/".join(path), tuple(_flatten(value))))
            elif isinstance(value, Mapping):
                walk(value, [*path, str(key)])

    if isinstance(data, Mapping):
        walk(data, [])
    return tuple(found)


def _flatten(value: Any, prefix: str = "") -> list[str]:
    if not isinstance(value, Mapping):
        return [prefix] if prefix else []
    names: list[str] = []
    for key, inner in value.items():
        names += _flatten(inner, f"{prefix}{key}.") if isinstance(inner, Mapping) else [f"{prefix}{key}"]
    return names


def _key_pattern(key: str) -> re.Pattern[str]:
    tokens = [t for t in key.strip("/").split("/") if t]
    parts = ["(?:/[^/]+)*" if token == "**" else "/" + re.escape(token).replace(r"\*", "[^/]*")
             for token in tokens]
    return re.compile("".join(parts) or "/")


def section_matches(key: str, fqn: str) -> bool:
    """Whether the parameters file section ``key`` applies to the node ``fqn``."""
    return _key_pattern(key).fullmatch(fqn) is not None


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
    for process in processes:
        given: Given | None = getattr(process, "given", None)
        if given is None:
            continue
        for params_file in given.files:
            receivers.setdefault(params_file.shown, []).extend((process, fqn) for fqn in process.nodes)
        # a component of a container gets what its LoadNode request gives it, not the container
        components: Mapping[str, Given] = getattr(process, "component_given", None) or {}
        for fqn, node in process.nodes.items():
            findings += _undeclared(process, components.get(fqn, given), fqn, node)
            if missing_path is not None:
                findings += _missing_paths(process, fqn, node, missing_path)
            if fqn in components:  # its LoadNode request's remappings reach this node alone
                findings += _unused_remappings(process, components[fqn], {fqn: node}, fqn)
        findings += _unused_remappings(process, given, process.nodes, process.expected)
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


def _undeclared(process: Any, given: Given, fqn: str, node: ContractNode) -> list[Finding]:
    if node.get(PARAMETERS) is None:  # parameters not read: nothing to compare with
        return []
    declared = {str(p.get("name")) for p in node[PARAMETERS]}
    sources: dict[str, str] = {}
    for params_file in given.files:
        for key, names in params_file.sections:
            if section_matches(key, fqn):
                for name in names:
                    sources.setdefault(name, f"{params_file.shown} [{key}]")
    for parameter in given.parameters:
        sources[parameter.name] = parameter.source
    out = []
    for name, source in sorted(sources.items()):
        if name in declared or is_infrastructure_parameter(name):
            continue
        close = _closest(name, declared)
        hint = f"; did you mean `{close}`?" if close else f"; it declares: {', '.join(sorted(declared)) or 'none'}"
        out.append(Finding("PARAM_NOT_DECLARED", process.label, fqn, name,
                           f"parameter `{name}` is given ({source}) but {fqn} does not declare it: ROS 2 ignores it "
                           f"without a word{hint}"))
    return out


def _missing_paths(process: Any, fqn: str, node: ContractNode, missing_path: MissingPath) -> list[Finding]:
    out = []
    for parameter in node.get(PARAMETERS) or []:
        value = parameter.get("default_value")
        for text in value if isinstance(value, list) else [value]:
            why = missing_path(text) if isinstance(text, str) else None
            if why is not None:
                name = str(parameter.get("name"))
                out.append(Finding("PARAM_PATH_MISSING", process.label, fqn, name,
                                   f"parameter `{name}` of {fqn} is {text!r}, which points at {why}: the node "
                                   "reads nothing (or fails when it needs it); install the file or fix the value"))
    return out


def _closest(name: str, declared: set[str]) -> str | None:
    # a hint only: judged by the declared name's length, so `rte` finds `rate`
    near = [(distance, d) for d in declared if (distance := typo_distance(name, d, shortest=len(d))) is not None]
    return min(near)[1] if near else None


def _unused_remappings(process: Any, given: Given, nodes: Mapping[str, ContractNode],
                       expected: str | None) -> list[Finding]:
    """The remappings of ``given`` that change none of the names of ``nodes`` (a process's
    nodes, or the one node a component's load request made)."""
    out: list[Finding] = []
    if not nodes:
        return out
    for source, target in given.remappings:
        if source.startswith("__") or ":" in source:  # __node, __ns, node-prefixed rules
            continue
        used = any(resolve(target, fqn) in _names(node) for fqn, node in nodes.items())
        if used:
            continue
        fqn = sorted(nodes)[0]
        wanted = resolve(source, fqn)
        out.append(Finding(
            "REMAP_UNUSED", process.label, expected or fqn, f"{source}:={target}",
            f"the remapping {source} -> {target} (at {given.where or 'the launch file'}) changed none of the names of "
            f"{', '.join(sorted(nodes))}: no topic, service or action is named {resolve(target, fqn)}, so the node "
            f"never used {wanted}; check the `from` name against the node's own names"))
    return out
