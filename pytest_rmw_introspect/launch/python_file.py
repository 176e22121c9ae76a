"""Python launch files, read through ROS 2's own ``launch`` and ``launch_ros`` packages.

A Python launch file is a program: only ``launch`` can say what it starts. When ``launch`` and
``launch_ros`` are importable (a standard ROS 2 install: ``source /opt/ros/jazzy/setup.bash``),
the launch description is walked entity by entity as play_launch's ``dump_launch`` does (see
docs/design.md, "System contracts"), without starting anything:

* every action is visited (``entity.visit(context)``: includes, groups, arguments, opaque
  functions, ... do what they do in a real launch) and the entities it returns are walked in
  order, so scopes push and pop as in a real launch;
* a ``launch_ros.actions.Node`` (also a lifecycle node) is not executed: its substitutions are
  performed and its process description prepared (``Node.prepare``), which gives the exact
  command line, working directory and environment ``ros2 launch`` would use;
* ``SetRemap``, ``SetParameter`` and ``SetParametersFromFile`` are visited like any action:
  launch_ros puts what they set in force on the command lines it prepares; the walker reads the
  parameters (``-p``, ``--params-file``) and remappings back from each command line, so that the
  compatibility rules (``compare.launch_given``) judge them, and names a ``SetParameter``'s own line;
* event handlers (``RegisterEventHandler`` and ``on_exit=``) get the meaning a capture can give
  them (``python_events``);
* a ``ComposableNodeContainer`` is a node (its process is captured) whose components, and those
  ``LoadComposableNodes`` loads into it, are the LoadNode requests launch_ros would send
  (``get_composable_node_load_request``: the scope's namespace, ``SetRemap`` and
  ``SetParameter`` applied), kept as the container's :class:`ComponentLoad` entries: the
  container's middleware sends them to the container itself (``component_loads``);
* ``LoadComposableNodes`` into a container this launch does not start, plain ``ExecuteProcess``
  actions, timers and the event handlers a capture cannot honour are :class:`Unsupported`
  (their processes would never be captured), skipped only when their condition is false.

launch keeps no line numbers for Python entities: while the file is read, the walker notes where
each action is created (the innermost stack frame outside launch's own code, :class:`_Origins`),
so that every node and every unsupported action names its file and line.

The ROS 2 PyPI wheels do not include ``launch`` or ``launch_ros``; there, a Python launch file
is a :class:`LaunchError` that names the one command that installs them (``rmw-introspect
install-launch``, ``cli.install_launch``). Installed so, launch_ros finds no
``composition_interfaces`` (no wheel of it exists): ``composition_stand_in`` supplies its LoadNode
request while launch_ros is imported.
"""

from __future__ import annotations

import contextlib
import dataclasses
import importlib
import os
import sys
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from types import ModuleType
from typing import Any

from ..errors import LaunchError
from ..model import ament_index
from ..model.paths import shown
from . import composition_stand_in, python_events
from .entities import yaml_value
from .result import ComponentLoad, ComponentParameter, LaunchedNode, LaunchParameter, LaunchResult, Unsupported, Where
from .substitutions import anon_name

_NOT_AVAILABLE = (
    "{file} is a Python launch file, which is read through the ROS 2 `launch` and `launch_ros` packages; "
    "they cannot be imported here ({reason}). The ROS 2 PyPI wheels do not include them: run "
    "`rmw-introspect install-launch` once (it installs launch, launch_xml, launch_yaml and launch_ros of your "
    "ROS 2 distribution into this Python environment; `--from DIR` installs them from local checkouts), or "
    "source a ROS 2 install (/opt/ros/<distro>/setup.bash) in the shell that runs the check."
)


def modules() -> tuple[ModuleType, ModuleType]:
    """``launch`` and ``launch_ros`` (raises ImportError with the reason when not usable)."""
    launch = importlib.import_module("launch")
    if not hasattr(launch, "LaunchDescription") or not hasattr(launch, "LaunchContext"):
        raise ImportError(f"the module `launch` at {getattr(launch, '__file__', '?')} is not ROS 2's launch "
                          "(the PyPI package named `launch` is an unrelated project)")
    with composition_stand_in.imported_with_stand_in():  # no wheel of composition_interfaces exists
        launch_ros = importlib.import_module("launch_ros")
        importlib.import_module("launch_ros.actions")
    importlib.import_module("launch.launch_description_sources")
    return launch, launch_ros


def read(
    path: Path,
    configurations: Mapping[str, str],
    namespace: str | None,
    env: Mapping[str, str | None],
    result: LaunchResult,
    prefixes: Sequence[Path],
    included_from: Where | None,
) -> None:
    """Walk the Python launch file ``path`` into ``result`` (raises LaunchError)."""
    where = included_from or Where(path)
    try:
        launch, launch_ros = modules()
    except ImportError as exc:
        raise LaunchError(f"{where}: " + _NOT_AVAILABLE.format(file=shown(path), reason=exc)) from None
    saved = dict(os.environ)  # launch's SetEnvironmentVariable changes os.environ itself
    try:
        if prefixes:  # $(find-pkg-share) and includes in launch look packages up here
            existing = [str(p) for p in ament_index.env_prefixes()]
            os.environ["AMENT_PREFIX_PATH"] = os.pathsep.join(dict.fromkeys([*existing, *map(str, prefixes)]))
        base_env = dict(os.environ)  # what a process gets anyway: its env is what the launch file adds
        for key, value in env.items():
            if value is None:
                os.environ.pop(key, None)
            else:
                os.environ[key] = value
        context = launch.LaunchContext()
        context.launch_configurations.update(configurations)
        if namespace:
            context.launch_configurations["ros_namespace"] = namespace
        with _Origins(launch, launch_ros).noted(), _stable_anon_names(launch):
            source = launch.launch_description_sources.PythonLaunchDescriptionSource(str(path))
            description = source.get_launch_description(context)
            _Walker(launch, launch_ros, context, result, path, base_env).run(description)
    except LaunchError:
        raise
    except Exception as exc:  # noqa: BLE001 - a launch file is arbitrary Python: say which and why
        raise LaunchError(f"{where}: reading the Python launch file {shown(path)} through launch_ros failed: "
                          f"{type(exc).__name__}: {exc}") from None
    finally:
        os.environ.clear()
        os.environ.update(saved)


@contextlib.contextmanager
def _stable_anon_names(launch: ModuleType) -> Iterator[None]:
    """While reading: ``AnonName`` (``$(anon NAME)`` in Python) gives the XML reader's name,
    unique per NAME and stable across runs (``substitutions.anon_name``), not launch's host, pid
    and random number, so that the node the launch file names has one name in the contract."""
    anon = launch.substitutions.AnonName
    original = anon.__dict__["compute_name"]
    names: dict[str, str] = {}
    anon.compute_name = lambda _self, id_value: anon_name(str(id_value), names)
    try:
        yield
    finally:
        anon.compute_name = original


class _Origins:
    """Where the actions of a Python launch file are created (launch keeps no line numbers):
    while :meth:`noted` is in force, ``launch.Action.__init__`` notes on each action the
    innermost stack frame outside launch's, launch_ros's and this package's own code."""

    ATTRIBUTE = "_rmw_introspect_where"

    def __init__(self, launch: ModuleType, launch_ros: ModuleType) -> None:
        # components are descriptions, not actions: noted too
        self.classes = [launch.Action, importlib.import_module("launch_ros.descriptions").ComposableNode]
        libraries = [launch, launch_ros, *(sys.modules[name] for name in ("launch_xml", "launch_yaml")
                                           if name in sys.modules)]
        here = Path(__file__).resolve().parents[1]
        self.skipped = tuple(str(Path(m.__file__ or "").resolve().parent) + os.sep for m in libraries) + (
            str(here) + os.sep, "<")

    def where(self) -> Where | None:
        frame = sys._getframe(2)
        while frame is not None:
            filename = frame.f_code.co_filename
            if not filename.startswith(self.skipped) and not os.path.realpath(filename).startswith(self.skipped):
                return Where(Path(filename), frame.f_lineno) if filename.endswith(".py") else None
            frame = frame.f_back  # type: ignore[assignment]
        return None

    @contextlib.contextmanager
    def noted(self) -> Iterator[None]:
        originals = [cls.__dict__["__init__"] for cls in self.classes]
        for cls, original in zip(self.classes, originals, strict=True):
            cls.__init__ = self.noting(original)
        try:
            yield
        finally:
            for cls, original in zip(self.classes, originals, strict=True):
                cls.__init__ = original

    def noting(self, original: Any) -> Any:
        origins = self

        def init(entity: Any, *args: Any, **kwargs: Any) -> None:
            entity.__dict__.setdefault(origins.ATTRIBUTE, origins.where())
            original(entity, *args, **kwargs)

        return init


class _Walker:
    def __init__(self, launch: Any, launch_ros: Any, context: Any, result: LaunchResult, path: Path,
                 base_env: Mapping[str, str]) -> None:
        self.launch, self.launch_ros, self.context = launch, launch_ros, context
        self.result, self.path, self.base_env = result, path, base_env
        self.unsupported_types: list[tuple[Any, str]] = []
        if hasattr(launch.actions, "TimerAction"):
            self.unsupported_types.append((launch.actions.TimerAction, "delayed actions (TimerAction) are not supported"))
        #: the processes started so far (what OnProcessStart handlers match)
        self.started: list[Any] = []
        #: RegisterEventHandler(OnProcessStart) actions, handled once the launch description is
        #: walked (launch runs them once their process started)
        self.pending: list[Any] = []
        #: each global parameter SetParameter added (by identity) -> where the SetParameter is
        self.global_parameters: dict[int, Where] = {}
        #: the component containers started so far: fully qualified name -> index in result.nodes
        self.containers: dict[str, int] = {}

    def where(self, entity: Any) -> Where:
        return getattr(entity, _Origins.ATTRIBUTE, None) or Where(self.path)

    def unsupported(self, entity: Any, what: str) -> None:
        self.result.unsupported.append(Unsupported(self.where(entity), f"{type(entity).__name__}: {what}"))

    def skip(self, entity: Any) -> bool:
        condition = getattr(entity, "condition", None)
        return condition is not None and not condition.evaluate(self.context)

    def run(self, description: Any) -> None:
        self.walk(description)
        while self.pending:
            registration = self.pending.pop(0)
            handling = python_events.handle(self.launch, registration.event_handler, self.started)
            if handling.unsupported:
                self.unsupported(registration, handling.unsupported)
            for action in handling.now:
                self.walk(action)

    def walk(self, entity: Any) -> None:
        for kind, what in self.unsupported_types:
            if isinstance(entity, kind):
                if not self.skip(entity):
                    self.unsupported(entity, what)
                return
        if isinstance(entity, self.launch.actions.ExecuteProcess):
            if not self.skip(entity):
                self.on_exit(entity)
                if isinstance(entity, self.launch_ros.actions.Node):
                    self.node(entity)
                    if isinstance(entity, self.launch_ros.actions.ComposableNodeContainer):
                        self.containers[entity.node_name] = len(self.result.nodes) - 1
                        self.add_components(entity.node_name, getattr(
                            entity, "_ComposableNodeContainer__composable_node_descriptions", None))
                else:
                    self.unsupported(entity, "plain processes are not captured: start ROS nodes with "
                                             "launch_ros.actions.Node")
            return
        if isinstance(entity, self.launch_ros.actions.LoadComposableNodes):
            if not self.skip(entity):
                self.load_components(entity)
            return
        if isinstance(entity, self.launch.actions.RegisterEventHandler):
            if not self.skip(entity):
                self.event_handler(entity)
            return
        before = self.context.launch_configurations.get("global_params")
        before_ids = {id(p) for p in before or ()}
        for sub in entity.visit(self.context) or ():
            self.walk(sub)
        if isinstance(entity, (self.launch_ros.actions.SetParameter, self.launch_ros.actions.SetParametersFromFile)):
            for item in self.context.launch_configurations.get("global_params") or ():
                if id(item) not in before_ids:
                    self.global_parameters[id(item)] = self.where(entity)

    def event_handler(self, entity: Any) -> None:
        handler = entity.event_handler
        if isinstance(handler, self.launch.event_handlers.OnProcessStart):
            self.pending.append(entity)
            return
        handling = python_events.handle(self.launch, handler, self.started)
        if handling.unsupported:
            self.unsupported(entity, handling.unsupported)

    def on_exit(self, process: Any) -> None:
        """``on_exit=`` of a process: as an OnProcessExit handler of it."""
        actions = python_events.actions_of(getattr(process, "_ExecuteLocal__on_exit", None))
        why = python_events.after_the_end(self.launch, actions, "after the process exits")
        if why:
            self.unsupported(process, f"on_exit: {why}")

    def text(self, value: Any) -> str:
        """A Node attribute as text (it may still be a list of substitutions)."""
        if value is None or isinstance(value, str):
            return value or ""
        utilities = self.launch.utilities
        return str(utilities.perform_substitutions(self.context, utilities.normalize_to_list_of_substitutions(value)))

    def node(self, node: Any) -> None:
        """A Node's command line as ``ros2 launch`` would run it (prepared, not executed)."""
        node_class = self.launch_ros.actions.Node
        node._perform_substitutions(self.context)
        fqn = node.node_name
        named = node_class.UNSPECIFIED_NODE_NAME not in fqn
        namespace = node.expanded_node_namespace
        has_namespace = namespace not in (node_class.UNSPECIFIED_NODE_NAMESPACE, "", None)
        ros_specific: dict[str, Any] = {}
        if named:
            ros_specific["name"] = f"__node:={fqn.rsplit('/', 1)[-1]}"
        if namespace != "":
            ros_specific["ns"] = f"__ns:={namespace}"
        self.context.extend_locals({"ros_specific_arguments": ros_specific})
        node.prepare(self.context)
        description = node.process_description
        command = tuple(description.final_cmd)
        final_env = description.final_env or dict(os.environ)
        env = {k: v for k, v in final_env.items() if self.base_env.get(k) != v}
        package = self.text(node.node_package)
        parameters, scope_remappings, remappings = self.settings(command)
        self.started.append(node)
        self.result.nodes.append(LaunchedNode(
            executable=self.text(node.node_executable) or command[0],
            package=package or None,
            where=self.where(node),
            name=fqn.rsplit("/", 1)[-1] if named else None,
            namespace=namespace if has_namespace else None,
            parameters=parameters,
            scope_remappings=scope_remappings,
            remappings=remappings,
            env=env,
            cwd=Path(description.final_cwd) if description.final_cwd else None,
            command=command,
        ))

    def settings(self, command: Sequence[str]) -> tuple[tuple[LaunchParameter, ...], tuple[tuple[str, str], ...],
                                                         tuple[tuple[str, str], ...]]:
        """The parameters, the SetRemap rules and the node's own remappings on a prepared command
        line (what the compatibility rules judge), each global parameter (SetParameter) with the place
        that set it. The SetRemap rules come first, as in XML (scope_remappings)."""
        origins = self.global_origins()
        scope_rules = [tuple(rule) for rule in self.context.launch_configurations.get("ros_remaps") or ()]
        words = list(command)
        ros = words[words.index("--ros-args") + 1:] if "--ros-args" in words else []
        parameters: list[LaunchParameter] = []
        scope_remappings: list[tuple[str, str]] = []
        remappings: list[tuple[str, str]] = []
        for flag, value in zip(ros, ros[1:], strict=False):
            if flag in ("-p", "--param") and ":=" in value:
                name, text = value.split(":=", 1)
                # the global ones come first: a node's own parameter of the same name is its own
                parameters.append(LaunchParameter(name=name, value=yaml_value(text), where=origins.pop(name, None)))
            elif flag == "--params-file":
                parameters.append(LaunchParameter(file=Path(value), where=origins.pop(os.path.abspath(value), None)))
            elif flag in ("-r", "--remap") and ":=" in value and not value.startswith(("__node:=", "__ns:=")):
                source, target = value.split(":=", 1)
                if len(scope_remappings) < len(scope_rules) and scope_rules[len(scope_remappings)] == (source, target):
                    scope_remappings.append((source, target))
                else:
                    remappings.append((source, target))
        return tuple(parameters), tuple(scope_remappings), tuple(remappings)

    def global_origins(self) -> dict[str, Where]:
        """Parameter name (or parameters file) -> the SetParameter that set it, for the global
        parameters in force."""
        out: dict[str, Where] = {}
        for item in self.context.launch_configurations.get("global_params") or ():
            where = self.global_parameters.get(id(item))
            if where is None:
                continue
            key = item[0] if isinstance(item, tuple) else os.path.abspath(str(item))
            out[key] = where
        return out

    # ------------------------------------------------------------ components

    def load_components(self, entity: Any) -> None:
        """``LoadComposableNodes``: its components, into the container it names."""
        target = entity._LoadComposableNodes__target_container
        if isinstance(target, self.launch_ros.actions.ComposableNodeContainer):
            name = target.node_name
        else:
            name = self.text(target)
        if name not in self.containers:
            started = ", ".join(sorted(self.containers)) or "none"
            self.unsupported(entity, f"the target container {name} is not started by this launch (containers it "
                                     f"starts: {started}), so its components cannot be captured; start the container "
                                     "in the same launch")
            return
        self.add_components(name, entity._LoadComposableNodes__composable_node_descriptions)

    def add_components(self, container: str, descriptions: Any) -> None:
        """The LoadNode requests launch_ros makes of ``descriptions`` now, onto the container."""
        get_composable_node_load_request = importlib.import_module(
            "launch_ros.actions.load_composable_nodes").get_composable_node_load_request
        scope_rules = [f"{source}:={target}" for source, target in self.context.launch_configurations.get("ros_remaps") or ()]
        loads = []
        for description in descriptions or ():
            request = get_composable_node_load_request(description, self.context)
            if request is None:  # its condition is false
                continue
            rules = tuple(request.remap_rules)
            loads.append(ComponentLoad(
                package=request.package_name, plugin=request.plugin_name, where=self.where(description),
                name=request.node_name or None, namespace=request.node_namespace or None,
                log_level=int(request.log_level), remap_rules=rules,
                # launch_ros puts the SetRemap rules first; should it ever not, none is judged as the component's own
                scope_remap_rules=len(scope_rules) if list(rules[:len(scope_rules)]) == scope_rules else len(rules),
                parameters=tuple(component_parameter(p) for p in request.parameters),
                extra_arguments=tuple(component_parameter(p) for p in request.extra_arguments)))
        if loads:
            index = self.containers[container]
            node = self.result.nodes[index]
            self.result.nodes[index] = dataclasses.replace(node, components=(*node.components, *loads))


#: rcl_interfaces/msg/ParameterValue: the field of each ParameterType
_VALUE_FIELDS = {1: "bool_value", 2: "integer_value", 3: "double_value", 4: "string_value", 5: "byte_array_value",
                 6: "bool_array_value", 7: "integer_array_value", 8: "double_array_value", 9: "string_array_value"}


def component_parameter(message: Any) -> ComponentParameter:
    """An rcl_interfaces/msg/Parameter as (name, type, value)."""
    kind = int(message.value.type)
    value = getattr(message.value, _VALUE_FIELDS[kind]) if kind in _VALUE_FIELDS else None
    return (str(message.name), kind, tuple(value) if kind >= 5 and value is not None else value)
