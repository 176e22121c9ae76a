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
* composable node containers, ``LoadComposableNodes``, plain ``ExecuteProcess`` actions,
  timers and event handlers are :class:`Unsupported` (their processes would never be
  captured), skipped only when their condition is false.

The ROS 2 PyPI wheels do not include ``launch`` or ``launch_ros``; there, a Python launch file
is a :class:`LaunchError` that says so (write the launch file in XML or YAML, or give a
``record.json`` written by ``dump_launch`` on a machine with ROS 2 installed).
"""

from __future__ import annotations

import importlib
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from types import ModuleType
from typing import Any

from ..model.paths import shown
from .launch_model import LaunchedNode, LaunchError, LaunchResult, Unsupported, Where

_NOT_AVAILABLE = (
    "{file} is a Python launch file, which is read through the ROS 2 `launch` and `launch_ros` packages; "
    "they cannot be imported here ({reason}). The ROS 2 PyPI wheels do not include them. Run the check where "
    "ROS 2 is installed (source /opt/ros/jazzy/setup.bash), write the launch file in XML or YAML (read without "
    "launch_ros), or give the record.json that play_launch's dump_launch writes for it."
)


def modules() -> tuple[ModuleType, ModuleType]:
    """``launch`` and ``launch_ros`` (raises ImportError with the reason when not usable)."""
    launch = importlib.import_module("launch")
    if not hasattr(launch, "LaunchDescription") or not hasattr(launch, "LaunchContext"):
        raise ImportError(f"the module `launch` at {getattr(launch, '__file__', '?')} is not ROS 2's launch "
                          "(the PyPI package named `launch` is an unrelated project)")
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
            existing = [p for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
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
        source = launch.launch_description_sources.PythonLaunchDescriptionSource(str(path))
        description = source.get_launch_description(context)
        _Walker(launch, launch_ros, context, result, path, base_env).walk(description)
    except LaunchError:
        raise
    except Exception as exc:  # noqa: BLE001 - a launch file is arbitrary Python: say which and why
        raise LaunchError(f"{where}: reading the Python launch file {shown(path)} through launch_ros failed: "
                          f"{type(exc).__name__}: {exc}") from None
    finally:
        os.environ.clear()
        os.environ.update(saved)


class _Walker:
    def __init__(self, launch: Any, launch_ros: Any, context: Any, result: LaunchResult, path: Path,
                 base_env: Mapping[str, str]) -> None:
        self.launch, self.launch_ros, self.context = launch, launch_ros, context
        self.result, self.path, self.base_env = result, path, base_env
        actions, ros_actions = launch.actions, launch_ros.actions
        self.unsupported_types: list[tuple[Any, str]] = [
            (ros_actions.ComposableNodeContainer, "composable node containers are not supported"),
            (ros_actions.LoadComposableNodes, "loading composable nodes is not supported"),
        ]
        for name, what in (("TimerAction", "delayed actions (TimerAction) are not supported"),
                           ("RegisterEventHandler", "event handlers (RegisterEventHandler) are not supported")):
            if hasattr(actions, name):
                self.unsupported_types.append((getattr(actions, name), what))

    def where(self, entity: Any) -> Where:
        # launch keeps no line numbers for Python entities: name the file and the entity
        return Where(self.path)

    def skip(self, entity: Any) -> bool:
        condition = getattr(entity, "condition", None)
        return condition is not None and not condition.evaluate(self.context)

    def walk(self, entity: Any) -> None:
        for kind, what in self.unsupported_types:
            if isinstance(entity, kind):
                if not self.skip(entity):
                    self.result.unsupported.append(Unsupported(self.where(entity), f"{type(entity).__name__}: {what}"))
                return
        if isinstance(entity, self.launch_ros.actions.Node):
            if not self.skip(entity):
                self.node(entity)
            return
        if isinstance(entity, self.launch.actions.ExecuteProcess):
            if not self.skip(entity):
                self.result.unsupported.append(Unsupported(
                    self.where(entity), "ExecuteProcess: plain processes are not captured: start ROS nodes with "
                    "launch_ros.actions.Node"))
            return
        for sub in entity.visit(self.context) or ():
            self.walk(sub)

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
        self.result.nodes.append(LaunchedNode(
            executable=self.text(node.node_executable) or command[0],
            package=package or None,
            where=self.where(node),
            name=fqn.rsplit("/", 1)[-1] if named else None,
            namespace=namespace if has_namespace else None,
            env=env,
            cwd=Path(description.final_cwd) if description.final_cwd else None,
            command=command,
        ))
