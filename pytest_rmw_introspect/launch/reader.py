"""Launch files as system targets: which processes a launch file starts, with which command line.

:func:`read` reads an XML or YAML launch file itself (no ``launch``/``launch_ros`` needed, so
it works with the ROS 2 PyPI wheels), a Python launch file through ``launch``/``launch_ros``
when they are importable (``python_file``), or a ``record.json`` written by play_launch's
``dump_launch`` (``record``), and gives a :class:`LaunchResult`: the nodes it starts
(:class:`LaunchedNode`: package, executable, name, namespace, arguments, parameters,
remappings, environment, and the file and line that starts it), the launch arguments it
declares, and everything it contains that this reader does not support.

Supported (XML and YAML, ``-`` and ``_`` spellings alike):

==========================  ===============================================================
``launch``                  the root
``arg``                     ``name``, ``default``, ``description``, ``<choice value=...>``
``let``                     ``name``, ``value``
``node``                    ``pkg``, ``exec``, ``name``, ``namespace``, ``args``, ``ros_args``,
                            ``cwd``; children ``param``, ``remap``, ``env``
``param``                   ``name`` + ``value`` (``value_sep``), ``from`` (a parameters file),
                            nested ``param`` (``outer.inner``)
``remap``                   ``from``, ``to``
``env``                     ``name``, ``value`` (inside ``node``)
``set_env``                 ``name``, ``value``: for the processes started after it in its scope
``group``                   ``scoped`` (default true), ``forwarding`` (default true), children
``push_ros_namespace``      ``namespace``: for the nodes after it in its scope
``set_remap``               ``from``, ``to``: a remapping for the nodes after it in its scope (before
                            each node's own, as launch_ros puts them: the first matching rule wins)
``set_parameter``           ``name``, ``value``: a parameter for the nodes after it in its scope (before
                            each node's own parameters, which override it, as launch_ros puts them)
``set_parameters_from_file`` ``filename``: a parameters file for the nodes after it in its scope
``include``                 ``file``; children ``arg`` (``name``, ``value``)
``node_container``          a ``node`` (same attributes and children) whose ``composable_node``
                            children are loaded into it
``load_composable_node``    ``target`` (a container this launch starts); ``composable_node`` children
``composable_node``         ``pkg``, ``plugin``, ``name``, ``namespace``; children ``param``, ``remap``,
                            ``extra_arg``: the LoadNode request launch_ros makes (``components``),
                            kept on the container's :class:`LaunchedNode` (``components``)
``if``, ``unless``          on every entity
==========================  ===============================================================

The scope of ``set_remap``, ``set_parameter`` and ``set_parameters_from_file`` is launch_ros's
(jazzy), measured, not the one its documentation promises: each kind is one list kept in the
launch configurations, and a group copies the configurations but not the list, so a rule
written inside a group also applies after the group when a rule of the same kind was set
before the group (in an enclosing scope or an earlier include); a group with
``forwarding="false"`` starts without any.

Substitutions: ``substitutions``. Relative paths (``include file``, ``param from``,
``node cwd``) are relative to the directory of the launch file that names them (``ros2 launch``
takes them relative to where it is started; ``$(dirname)`` or ``$(find-pkg-share ...)`` make a
launch file independent of both). Attributes that do not change what a node creates
(``output``, ``respawn``, ``emulate_tty``, ...) are accepted and have no effect. Anything else
(an unknown tag, ``launch-prefix``, an unsupported substitution)
is an :class:`Unsupported` entry with its file and line; :meth:`LaunchResult.require_supported`
turns them into one :class:`LaunchError`.

Launch files may come from anywhere, so reading one is bounded like reading a contract: the
files themselves (``entities``), substitutions (``substitutions``), and here the
work of a launch: each file is parsed once however often it is included, at most
:data:`MAX_INCLUDES` includes are followed and :data:`MAX_ENTITIES` entities interpreted, and
groups and includes nest at most :data:`MAX_NESTING` levels together. Each limit is a
:class:`LaunchError` with the file and line.
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
import shlex
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import ComponentParameterError, EntityFormatError, InputError, SubstitutionError, UnsupportedSubstitution
from ..model import untrusted
from ..model.paths import shown
from . import components, entities, python_file, record, substitutions
from .entities import Entity
from .result import (
    ComponentLoad,
    DeclaredArgument,
    LaunchedNode,
    LaunchError,
    LaunchParameter,
    LaunchResult,
    Unsupported,
    Where,
    find_package_prefix,
    join_namespace,
)
from .substitutions import Context

#: attributes that do not change what a node creates: accepted, no effect
IGNORED_NODE_ATTRIBUTES = frozenset({
    "output", "respawn", "respawn_delay", "emulate_tty", "sigterm_timeout", "sigkill_timeout", "exec_name",
    "log_cmd", "additional_env",
})
_CONDITION = frozenset({"if", "unless"})
#: tag → (attributes it takes, child tags it takes)
_TAGS: dict[str, tuple[frozenset[str], frozenset[str]]] = {
    "launch": (frozenset({"version"}), frozenset()),
    "arg": (frozenset({"name", "default", "description"}), frozenset({"choice"})),
    "let": (frozenset({"name", "value"}), frozenset()),
    "set_env": (frozenset({"name", "value"}), frozenset()),
    "group": (frozenset({"scoped", "forwarding"}), frozenset()),
    "push_ros_namespace": (frozenset({"namespace"}), frozenset()),
    "set_remap": (frozenset({"from", "to"}), frozenset()),
    "set_parameter": (frozenset({"name", "value"}), frozenset()),
    "set_parameters_from_file": (frozenset({"filename"}), frozenset()),
    "include": (frozenset({"file"}), frozenset({"arg"})),
    "node": (frozenset({"pkg", "exec", "name", "namespace", "args", "ros_args", "cwd"}) | IGNORED_NODE_ATTRIBUTES,
             frozenset({"param", "remap", "env"})),
    "node_container": (frozenset({"pkg", "exec", "name", "namespace", "args", "ros_args", "cwd"})
                       | IGNORED_NODE_ATTRIBUTES, frozenset({"param", "remap", "env", "composable_node"})),
    "load_composable_node": (frozenset({"target"}), frozenset({"composable_node"})),
}
#: attributes and child tags of a <composable_node>
_COMPONENT = (frozenset({"pkg", "plugin", "name", "namespace"}), frozenset({"param", "remap", "extra_arg"}))
_UNSUPPORTED_HINTS = {
    "composable_node_container": "write <node_container> (the launch front ends' name for a "
                                 "ComposableNodeContainer)",
    "composable_node": "a <composable_node> belongs inside a <node_container> or a <load_composable_node>",
    "executable": "plain processes (<executable>) are not captured: start ROS nodes with <node>",
    "timer": "delayed actions (<timer>) are not supported",
}
MAX_INCLUDE_DEPTH = 40
#: the most includes one launch may follow (each file is parsed once, but every include of it
#: is interpreted again with its own arguments: 18 files that each include the next twice
#: would be 2^18 includes)
MAX_INCLUDES = 1_000
#: the most entities one launch may interpret, over all its includes
MAX_ENTITIES = 50_000
#: the deepest nesting of groups and includes together (the reader recurses once per level)
MAX_NESTING = 100


@dataclass
class _Scope:
    configurations: dict[str, str]
    namespace: str | None
    env: dict[str, str]
    #: <set_remap> rules for the nodes after them, and <set_parameter>/<set_parameters_from_file>
    #: settings: launch_ros keeps each kind as one list in the launch configurations (None: not
    #: set yet). A scope copies the configurations but shares these lists (see :meth:`copy`).
    remaps: list[tuple[str, str]] | None = None
    parameters: list[LaunchParameter] | None = None
    #: the <include> that reads the current file (None: the top-level file)
    included_from: Where | None = None

    def copy(self) -> _Scope:
        # launch_ros (jazzy) appends to the list it finds in the configurations, and a scope
        # copies the configurations dict, not the lists in it: a rule set inside a group is
        # seen after the group whenever the list existed before it (measured with launch_ros
        # 0.26.6); one set where no list existed yet makes a new list, which the scope drops
        return _Scope(dict(self.configurations), self.namespace, dict(self.env), self.remaps,
                      self.parameters, self.included_from)


def launch_file_of_package(package: str, file: str, prefixes: Sequence[Path]) -> Path:
    """``ros2 launch PACKAGE FILE``: FILE in the package's share directory (a relative path, or a
    name searched for below it). Raises LaunchError."""
    try:
        share = find_package_prefix(package, prefixes) / "share" / package
    except SubstitutionError as exc:
        raise LaunchError(f"launch file {file} of package {package}: {exc}") from None
    if "/" in file:
        path = share / file
        problem = untrusted.file_problem(path)
        if problem is not None:
            raise LaunchError(f"launch file {file} of package {package}: {path} {problem}")
        return path
    found = sorted(p for p in share.rglob(file) if p.is_file())
    if not found:
        raise LaunchError(
            f"package {package} has no launch file named {file} (searched {share}); install it "
            "(`install(DIRECTORY launch DESTINATION share/${PROJECT_NAME})`) or give its path"
        )
    if len(found) > 1:
        raise LaunchError(f"package {package} has several files named {file}: {', '.join(map(str, found))}; "
                          "give the path relative to the package's share directory")
    return found[0]


# ---------------------------------------------------------------------------- the reader


def read(
    path: str | Path,
    arguments: Mapping[str, Any] | None = None,
    *,
    prefixes: Sequence[Path] = (),
) -> LaunchResult:
    """Read a launch file (XML, YAML, Python, or a dump_launch ``record.json``) with
    ``arguments`` (launch arguments, as ``ros2 launch ... name:=value``). ``prefixes``: the
    ament prefixes for ``$(find-pkg-*)`` and includes. Raises LaunchError."""
    path = Path(path).absolute()
    given = {str(k): argument_text(v) for k, v in (arguments or {}).items()}
    result = LaunchResult(source=path, arguments=given)
    problem = untrusted.file_problem(path)  # a FIFO is never opened: reading it would block
    if problem is not None:
        raise LaunchError(f"launch file {shown(path)} {problem}")
    if path.name.endswith(".json"):
        record.read(path, result)
        return result
    reader = _Reader(result, list(prefixes))
    reader.read_file(path, _Scope(dict(given), None, {}), None, ())
    declared = {d.name for d in result.declared}
    unknown = sorted(set(given) - declared)
    # Python launch files declare their arguments in code this reader does not see
    if unknown and not any(f.suffix == ".py" for f in result.files):
        known = ", ".join(sorted(declared)) or "none"
        raise LaunchError(
            f"{shown(path)}: launch argument(s) {', '.join(unknown)} given but not declared by the launch file "
            f"or its includes (declared: {known}); check the spelling"
        )
    return result


def argument_text(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


class _Reader:
    def __init__(self, result: LaunchResult, prefixes: list[Path]) -> None:
        self.result = result
        self.prefixes = prefixes
        self.anon: dict[str, str] = {}
        self.budget = substitutions.Budget()
        self.parsed: dict[Path, Entity] = {}  # each file is parsed once, however often it is included
        self.includes = 0
        self.interpreted = 0
        self.nesting = 0
        #: the component containers started so far: fully qualified name -> index in result.nodes
        self.containers: dict[str, int] = {}

    # ------------------------------------------------------------ helpers
    def context(self, scope: _Scope, file: Path) -> Context:
        return Context(scope.configurations, substitutions.environment_view(scope.env), file,
                       self.find_package, self.anon, self.budget)

    def find_package(self, package: str) -> Path:
        return find_package_prefix(package, self.prefixes)

    def text(self, value: Any, scope: _Scope, file: Path) -> str:
        if not isinstance(value, str):
            return argument_text(value)
        if not substitutions.has_substitution(value):
            return value
        return substitutions.substitute(value, self.context(scope, file))

    def unsupported(self, where: Where, what: str) -> None:
        self.result.unsupported.append(Unsupported(where, what))

    def error(self, where: Where, reason: str) -> LaunchError:
        return LaunchError(f"{where}: {reason}")

    def path(self, value: Any, scope: _Scope, file: Path) -> Path:
        p = Path(os.path.expanduser(self.text(value, scope, file)))
        return p if p.is_absolute() else file.parent / p

    def condition(self, entity: Entity, scope: _Scope, file: Path) -> bool:
        """False when an ``if``/``unless`` attribute says to skip the entity."""
        where = Where(file, entity.line)
        for key, wanted in (("if", True), ("unless", False)):
            if key not in entity.attributes:
                continue
            text = self.text(entity.attributes[key], scope, file).strip().lower()
            if text in ("true", "1"):
                value = True
            elif text in ("false", "0"):
                value = False
            else:
                raise self.error(where, f"the condition {key}={entity.attributes[key]!r} gives {text!r}; "
                                        "a condition must give true, false, 1 or 0")
            if value is not wanted:
                return False
        return True

    def check_attributes(self, entity: Entity, file: Path, allowed: frozenset[str]) -> None:
        for name in sorted(set(entity.attributes) - allowed - _CONDITION):
            self.unsupported(Where(file, entity.line), f"attribute `{name}` of <{entity.tag}> is not supported")

    def remap_rule(self, entity: Entity, scope: _Scope, file: Path) -> tuple[str, str]:
        """A ``<remap from= to=>`` child of a node or a component: (from, to), substituted."""
        self.check_attributes(entity, file, frozenset({"from", "to"}))
        return (self.text(self.require(entity, file, "from"), scope, file),
                self.text(self.require(entity, file, "to"), scope, file))

    def require(self, entity: Entity, file: Path, name: str) -> Any:
        if name not in entity.attributes or entity.attributes[name] is None:
            raise self.error(Where(file, entity.line), f"<{entity.tag}> needs the attribute `{name}`")
        return entity.attributes[name]

    # ------------------------------------------------------------ files
    def read_file(self, path: Path, scope: _Scope, included_from: Where | None, stack: tuple[Path, ...]) -> None:
        if path in stack or len(stack) > MAX_INCLUDE_DEPTH:
            chain = " -> ".join(shown(p) for p in (*stack, path))
            raise LaunchError(f"{included_from}: include cycle: {chain}")
        if included_from is not None:
            self.includes += 1
            if self.includes > MAX_INCLUDES:
                raise LaunchError(f"{included_from}: the launch follows more than {MAX_INCLUDES:,} includes (files "
                                  "that include the same file several times, at every level?); include each "
                                  "file fewer times")
        problem = untrusted.file_problem(path)
        if problem is not None:
            raise LaunchError(f"{included_from or Where(path)}: launch file {shown(path)} {problem}")
        self.result.files.append(path)
        if path.suffix == ".py":
            python_file.read(path, scope.configurations, scope.namespace, dict(scope.env), self.result,
                               self.prefixes, included_from)
            return
        root = self.parsed.get(path)
        if root is None:
            root = self.parsed[path] = self.parse(path, included_from)
        self.check_attributes(root, path, _TAGS["launch"][0])
        with self.nested(Where(path, root.line)):
            self.entities(root.children, scope, path, (*stack, path))

    def parse(self, path: Path, included_from: Where | None) -> Entity:
        where = included_from or Where(path)
        try:
            root = entities.parse_file(path)
        except FileNotFoundError:
            raise LaunchError(f"{where}: launch file {shown(path)} does not exist") from None
        except OSError as exc:
            raise LaunchError(f"{where}: cannot read {shown(path)}: {exc}") from None
        except EntityFormatError as exc:
            if exc.line is None and included_from is not None:  # the file as a whole: say who includes it
                raise LaunchError(f"{included_from}: {shown(path)}: {exc.reason}") from None
            raise LaunchError(f"{Where(path, exc.line)}: {exc.reason}") from None
        if root.tag != "launch":
            raise LaunchError(f"{Where(path, root.line)}: the root element is <{root.tag}>, not <launch>")
        return root

    @contextlib.contextmanager
    def nested(self, where: Where) -> Iterator[None]:
        """One more level of groups and includes (bounded: the reader recurses once per level)."""
        if self.nesting >= MAX_NESTING:
            raise self.error(where, f"groups and includes are nested more than {MAX_NESTING} levels deep")
        self.nesting += 1
        try:
            yield
        finally:
            self.nesting -= 1

    def entities(self, entities: Sequence[Entity], scope: _Scope, file: Path, stack: tuple[Path, ...]) -> None:
        for entity in entities:
            self.interpreted += 1
            if self.interpreted > MAX_ENTITIES:
                raise self.error(Where(file, entity.line), f"the launch has more than {MAX_ENTITIES:,} entities "
                                                           "over all its includes")
            try:
                if not self.condition(entity, scope, file):
                    continue
                self.entity(entity, scope, file, stack)
            except UnsupportedSubstitution as exc:
                self.unsupported(Where(file, entity.line), f"<{entity.tag}>: {exc}")
            except SubstitutionError as exc:
                raise self.error(Where(file, entity.line), f"<{entity.tag}>: {exc}") from None

    def entity(self, entity: Entity, scope: _Scope, file: Path, stack: tuple[Path, ...]) -> None:
        tag = entity.tag
        where = Where(file, entity.line)
        if tag not in _TAGS or tag == "launch":
            hint = _UNSUPPORTED_HINTS.get(tag, "this tag is not supported")
            self.unsupported(where, f"<{tag}>: {hint}")
            return
        attributes, child_tags = _TAGS[tag]
        self.check_attributes(entity, file, attributes)
        if tag not in ("group", "include"):
            for child in entity.children:
                if child.tag not in child_tags:
                    self.unsupported(Where(file, child.line), f"<{child.tag}> inside <{tag}> is not supported")
        getattr(self, f"tag_{tag}")(entity, scope, file, stack)

    # ------------------------------------------------------------ tags
    def tag_arg(self, entity: Entity, scope: _Scope, file: Path, stack: tuple[Path, ...]) -> None:
        where = Where(file, entity.line)
        name = str(self.require(entity, file, "name"))
        default = entity.attributes.get("default")
        choices = tuple(self.text(self.require(c, file, "value"), scope, file)
                        for c in entity.children if c.tag == "choice")
        description = entity.attributes.get("description")
        self.result.declared.append(DeclaredArgument(name, None if default is None else str(default),
                                                     None if description is None else str(description), choices, where))
        if name not in scope.configurations:
            if default is None and scope.included_from is not None:
                raise self.error(where, f"launch argument '{name}' is required (it has no default) and the <include> "
                                        f"at {scope.included_from} does not pass it; add "
                                        f"<arg name=\"{name}\" value=\"...\"/> to that <include>")
            if default is None:
                raise self.error(where, f"launch argument '{name}' is required (it has no default) and was not given; "
                                        f"pass it: arguments: {{{name}: ...}} (--launch-arg {name}:=VALUE)")
            scope.configurations[name] = self.text(default, scope, file)
        value = scope.configurations[name]
        if choices and value not in choices:
            raise self.error(where, f"launch argument '{name}' is {value!r}; it must be one of {', '.join(choices)}")

    def tag_let(self, entity: Entity, scope: _Scope, file: Path, stack: tuple[Path, ...]) -> None:
        name = str(self.require(entity, file, "name"))
        scope.configurations[name] = self.text(self.require(entity, file, "value"), scope, file)

    def tag_set_env(self, entity: Entity, scope: _Scope, file: Path, stack: tuple[Path, ...]) -> None:
        name = self.text(self.require(entity, file, "name"), scope, file)
        scope.env[name] = self.text(self.require(entity, file, "value"), scope, file)

    def tag_set_remap(self, entity: Entity, scope: _Scope, file: Path, stack: tuple[Path, ...]) -> None:
        rule = (self.text(self.require(entity, file, "from"), scope, file),
                self.text(self.require(entity, file, "to"), scope, file))
        scope.remaps = scope.remaps if scope.remaps is not None else []
        scope.remaps.append(rule)

    def tag_set_parameter(self, entity: Entity, scope: _Scope, file: Path, stack: tuple[Path, ...]) -> None:
        name = self.text(self.require(entity, file, "name"), scope, file)
        # launch_ros reads the value as YAML once its substitutions are performed
        text = self.text(self.require(entity, file, "value"), scope, file)
        try:
            value = entities.yaml_value(text)
        except ValueError as exc:
            raise SubstitutionError(str(exc)) from None
        self.set_parameter(scope, LaunchParameter(name=name, value=value, where=Where(file, entity.line)))

    def tag_set_parameters_from_file(self, entity: Entity, scope: _Scope, file: Path,
                                     stack: tuple[Path, ...]) -> None:
        path = self.path(self.require(entity, file, "filename"), scope, file)
        if not path.is_file():
            raise self.error(Where(file, entity.line), f"parameters file {shown(path)} does not exist")
        self.set_parameter(scope, LaunchParameter(file=path, where=Where(file, entity.line)))

    @staticmethod
    def set_parameter(scope: _Scope, parameter: LaunchParameter) -> None:
        scope.parameters = scope.parameters if scope.parameters is not None else []
        scope.parameters.append(parameter)

    def tag_push_ros_namespace(self, entity: Entity, scope: _Scope, file: Path, stack: tuple[Path, ...]) -> None:
        scope.namespace = join_namespace(scope.namespace, self.text(self.require(entity, file, "namespace"), scope, file))

    def flag(self, entity: Entity, name: str, default: bool, scope: _Scope, file: Path) -> bool:
        if name not in entity.attributes:
            return default
        text = self.text(entity.attributes[name], scope, file).strip().lower()
        if text not in ("true", "false", "1", "0"):
            raise self.error(Where(file, entity.line), f"`{name}` must be true or false, got {text!r}")
        return text in ("true", "1")

    def tag_group(self, entity: Entity, scope: _Scope, file: Path, stack: tuple[Path, ...]) -> None:
        scoped = self.flag(entity, "scoped", True, scope, file)
        forwarding = self.flag(entity, "forwarding", True, scope, file)
        inner = scope.copy() if scoped else scope
        if not forwarding:  # launch_ros keeps <set_remap>, <set_parameter> with the configurations
            inner.configurations.clear()
            inner.remaps = inner.parameters = None
        with self.nested(Where(file, entity.line)):
            self.entities(entity.children, inner, file, stack)

    def tag_include(self, entity: Entity, scope: _Scope, file: Path, stack: tuple[Path, ...]) -> None:
        where = Where(file, entity.line)
        target = self.path(self.require(entity, file, "file"), scope, file)
        inner = scope.copy()
        inner.included_from = where
        for child in entity.children:
            if child.tag != "arg":
                self.unsupported(Where(file, child.line), f"<{child.tag}> inside <include> is not supported")
                continue
            if not self.condition(child, scope, file):
                continue
            self.check_attributes(child, file, frozenset({"name", "value"}))
            name = self.text(self.require(child, file, "name"), scope, file)
            inner.configurations[name] = self.text(self.require(child, file, "value"), scope, file)
        self.read_file(target, inner, where, stack)

    def tag_node(self, entity: Entity, scope: _Scope, file: Path, stack: tuple[Path, ...]) -> None:
        where = Where(file, entity.line)
        a = entity.attributes
        executable = self.text(self.require(entity, file, "exec"), scope, file)
        package = self.text(a["pkg"], scope, file) if a.get("pkg") is not None else None
        name = self.text(a["name"], scope, file) if a.get("name") is not None else None
        namespace = join_namespace(scope.namespace, self.text(a["namespace"], scope, file)
                                   if a.get("namespace") is not None else None)
        arguments = tuple(shlex.split(self.text(a["args"], scope, file))) if a.get("args") is not None else ()
        ros_arguments = tuple(shlex.split(self.text(a["ros_args"], scope, file))) if a.get("ros_args") is not None else ()
        cwd = self.path(a["cwd"], scope, file) if a.get("cwd") is not None else None
        parameters: list[LaunchParameter] = []
        remappings: list[tuple[str, str]] = []
        env = dict(scope.env)
        for child in entity.children:
            if not self.condition(child, scope, file):
                continue
            if child.tag == "param":
                parameters += self.parameters(child, "", scope, file)
            elif child.tag == "remap":
                remappings.append(self.remap_rule(child, scope, file))
            elif child.tag == "env":
                self.check_attributes(child, file, frozenset({"name", "value"}))
                env[self.text(self.require(child, file, "name"), scope, file)] = self.text(
                    self.require(child, file, "value"), scope, file)
        if not executable:
            raise self.error(where, "<node> has an empty `exec`")
        self.result.nodes.append(LaunchedNode(
            executable=executable, package=package or None, where=where, name=name or None, namespace=namespace,
            arguments=arguments, ros_arguments=ros_arguments, parameters=(*(scope.parameters or ()), *parameters),
            remappings=tuple(remappings), scope_remappings=tuple(scope.remaps or ()), env=env, cwd=cwd))

    def tag_node_container(self, entity: Entity, scope: _Scope, file: Path, stack: tuple[Path, ...]) -> None:
        """A container is a node; its <composable_node> entries are loaded into it."""
        self.tag_node(entity, scope, file, stack)
        container = self.result.nodes[-1]
        if container.expected_fqn is None:
            raise self.error(Where(file, entity.line), "<node_container> needs a `name` (its components are loaded "
                                                       "through the container's name)")
        self.containers[container.expected_fqn] = len(self.result.nodes) - 1
        self.components(container.expected_fqn, entity, scope, file)

    def tag_load_composable_node(self, entity: Entity, scope: _Scope, file: Path, stack: tuple[Path, ...]) -> None:
        target = self.text(self.require(entity, file, "target"), scope, file)
        if target not in self.containers:
            started = ", ".join(sorted(self.containers)) or "none"
            self.unsupported(Where(file, entity.line),
                             f"<load_composable_node>: the target container {target} is not started by this launch "
                             f"(containers it starts: {started}), so its components cannot be captured; start the "
                             "container in the same launch")
            return
        self.components(target, entity, scope, file)

    def components(self, container: str, entity: Entity, scope: _Scope, file: Path) -> None:
        """The <composable_node> children of ``entity``, as LoadNode requests onto ``container``."""
        loads = []
        for child in entity.children:
            if child.tag != "composable_node" or not self.condition(child, scope, file):
                continue
            self.check_attributes(child, file, _COMPONENT[0])
            for inner in child.children:
                if inner.tag not in _COMPONENT[1]:
                    self.unsupported(Where(file, inner.line), f"<{inner.tag}> inside <composable_node> is not supported")
            loads.append(self.component(child, scope, file))
        if loads:
            index = self.containers[container]
            node = self.result.nodes[index]
            self.result.nodes[index] = dataclasses.replace(node, components=(*node.components, *loads))

    def component(self, entity: Entity, scope: _Scope, file: Path) -> ComponentLoad:
        where = Where(file, entity.line)
        a = entity.attributes
        name = self.text(self.require(entity, file, "name"), scope, file)
        own_namespace = self.text(a["namespace"], scope, file) if a.get("namespace") is not None else None
        namespace = join_namespace(scope.namespace, own_namespace)
        given: list[LaunchParameter] = list(scope.parameters or ())
        remaps = [f"{source}:={target}" for source, target in scope.remaps or ()]
        extras: list[LaunchParameter] = []
        for child in entity.children:
            if not self.condition(child, scope, file):
                continue
            if child.tag == "param":
                given += self.parameters(child, "", scope, file)
            elif child.tag == "remap":
                remaps.append(":=".join(self.remap_rule(child, scope, file)))
            elif child.tag == "extra_arg":
                self.check_attributes(child, file, frozenset({"name", "value"}))
                extras.append(LaunchParameter(name=self.text(self.require(child, file, "name"), scope, file),
                                        value=self.value(self.require(child, file, "value"), None, scope, file)))
        try:
            parameters = components.parameters(given, name, namespace)
            extra_arguments = components.parameters(extras, name, namespace)
        except (ComponentParameterError, OSError, InputError) as exc:
            raise self.error(where, f"<composable_node name=\"{name}\">: {exc}") from None
        return ComponentLoad(
            package=self.text(self.require(entity, file, "pkg"), scope, file),
            plugin=self.text(self.require(entity, file, "plugin"), scope, file), where=where, name=name,
            namespace=namespace, remap_rules=tuple(remaps), scope_remap_rules=len(scope.remaps or ()),
            parameters=parameters, extra_arguments=extra_arguments)

    def parameters(self, entity: Entity, prefix: str, scope: _Scope, file: Path) -> list[LaunchParameter]:
        where = Where(file, entity.line)
        a = entity.attributes
        self.check_attributes(entity, file, frozenset({"name", "value", "value_sep", "from", "allow_substs"}))
        if a.get("from") is not None:
            if prefix:
                raise self.error(where, "a parameters file (`from`) cannot be nested inside a <param>")
            path = self.path(a["from"], scope, file)
            if not path.is_file():
                raise self.error(where, f"parameters file {shown(path)} does not exist")
            return [LaunchParameter(file=path)]
        name = prefix + str(self.text(self.require(entity, file, "name"), scope, file))
        nested = [c for c in entity.children if c.tag == "param"]
        if nested:
            out: list[LaunchParameter] = []
            for child in nested:
                if self.condition(child, scope, file):
                    out += self.parameters(child, name + ".", scope, file)
            return out
        if "value" not in a:
            raise self.error(where, f"<param name=\"{name}\"> needs `value`, `from` or nested <param> entries")
        return [LaunchParameter(name=name, value=self.value(a["value"], a.get("value_sep"), scope, file))]

    def value(self, raw: Any, separator: Any, scope: _Scope, file: Path) -> Any:
        """A parameter value typed as launch_ros types it."""
        if isinstance(raw, list):
            return [self.value(v, None, scope, file) for v in raw]
        if not isinstance(raw, str):
            return raw
        text = self.text(raw, scope, file)
        if separator is not None:
            sep = self.text(separator, scope, file)
            return [guess_type(part) for part in text.split(sep)] if text else []
        if substitutions.has_substitution(raw):
            try:
                return entities.yaml_value(text)
            except ValueError as exc:
                raise SubstitutionError(str(exc)) from None
        return guess_type(text)


def guess_type(text: str) -> Any:
    """A launch-file value without a type: an integer, a float, true/false, or the text."""
    for convert in (int, float):
        try:
            return convert(text)
        except ValueError:
            pass
    if text.lower() in ("true", "false"):
        return text.lower() == "true"
    return text


__all__ = [
    "DeclaredArgument", "LaunchError", "LaunchResult", "LaunchedNode", "LaunchParameter", "Unsupported", "Where",
    "find_package_prefix", "guess_type", "join_namespace", "launch_file_of_package", "read",
]
