"""What a launch file starts, as data: the nodes (:class:`LaunchedNode`), the arguments it
declares, what the reader does not support (:meth:`LaunchResult.require_supported` raises
``errors.LaunchError``).

Shared by the readers of each kind of launch source (``reader`` for XML and YAML,
``python_file`` for Python launch files, ``record`` for play_launch's record.json)."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from ..errors import LaunchError, SubstitutionError
from ..model import ament_index, editable_installs
from ..model.paths import shown


@dataclass(frozen=True)
class Where:
    """A place in a launch file."""

    file: Path
    line: int | None = None

    def __str__(self) -> str:
        return shown(self.file) + (f":{self.line}" if self.line is not None else "")


@dataclass(frozen=True)
class LaunchParameter:
    """One ``-p name:=value``, or one ``--params-file`` (``file``, or ``file_text`` to be
    written to a temporary file before the process starts: record.json carries contents)."""

    name: str | None = None
    value: Any = None
    file: Path | None = None
    file_text: str | None = None
    #: where the launch file gives it, when not where the node is started (``<set_parameter>``)
    where: Where | None = None


#: a component's parameter as composition_interfaces/srv/LoadNode carries it: name, its
#: rcl_interfaces/msg/ParameterType number (1 bool, 2 integer, 3 double, 4 string, 6-9 the
#: arrays of those), and its value (a tuple of items for an array)
ComponentParameter = tuple[str, int, Any]


@dataclass(frozen=True)
class ComponentLoad:
    """One component a launch file loads into a component container (a ComposableNode of a
    ``ComposableNodeContainer`` or ``LoadComposableNodes``), as the LoadNode request launch_ros
    sends for it: the scope's namespace, global remappings and parameters already applied."""

    package: str
    plugin: str
    where: Where
    name: str | None = None
    namespace: str | None = None
    log_level: int = 0
    remap_rules: tuple[str, ...] = ()
    #: how many of ``remap_rules`` (the first ones) are the scope's ``<set_remap>``/``SetRemap``
    #: rules rather than the component's own ``<remap>``/``remappings=``
    scope_remap_rules: int = 0
    parameters: tuple[ComponentParameter, ...] = ()
    extra_arguments: tuple[ComponentParameter, ...] = ()

    @property
    def own_remappings(self) -> tuple[tuple[str, str], ...]:
        """The component's own remappings (``from``, ``to``), without the scope's."""
        pairs = (rule.partition(":=") for rule in self.remap_rules[self.scope_remap_rules:])
        return tuple((source, target) for source, sep, target in pairs if sep)

    def describe(self) -> str:
        named = f" as {(self.namespace or '').rstrip('/')}/{self.name}" if self.name else ""
        return f"component {self.plugin}{named} ({self.where})"


@dataclass(frozen=True)
class LaunchedNode:
    """One process a launch file starts, as the launch file describes it."""

    executable: str
    package: str | None
    where: Where
    name: str | None = None
    namespace: str | None = None
    arguments: tuple[str, ...] = ()
    ros_arguments: tuple[str, ...] = ()
    parameters: tuple[LaunchParameter, ...] = ()
    remappings: tuple[tuple[str, str], ...] = ()
    env: Mapping[str, str] = field(default_factory=dict)
    #: the <set_remap> rules in force where the node is started (before its own, as launch_ros
    #: passes them: rcl applies the first rule that matches)
    scope_remappings: tuple[tuple[str, str], ...] = ()
    cwd: Path | None = None
    #: the complete command line, when the launch source gives it (Python launch files:
    #: launch_ros prepared it); otherwise it is built from the fields above
    command: tuple[str, ...] | None = None
    #: a component container: the components the launch file loads into it, in order
    components: tuple[ComponentLoad, ...] = ()

    @property
    def expected_fqn(self) -> str | None:
        """The fully qualified node name the launch file gives (None: the program chooses)."""
        if self.name is None:
            return None
        namespace = self.namespace or "/"
        return namespace.rstrip("/") + "/" + self.name

    def describe(self) -> str:
        what = f"{self.package}/{self.executable}" if self.package else self.executable
        if self.expected_fqn:
            what += f" as {self.expected_fqn}"
        elif self.namespace:
            what += f" in {self.namespace}"
        return f"{what} ({self.where})"

    def ros_argument_list(self, params_file: Callable[[LaunchParameter], Path] | None = None) -> list[str]:
        """``--ros-args ...`` as launch_ros builds it: node name, namespace, parameters in
        order, remappings (``<set_remap>`` ones first), then the ``ros_args`` given (empty list
        when there are none)."""
        args: list[str] = []
        if self.name is not None:
            args += ["-r", f"__node:={self.name}"]
        if self.namespace is not None:
            args += ["-r", f"__ns:={self.namespace}"]
        for parameter in self.parameters:
            if parameter.name is not None:
                args += ["-p", f"{parameter.name}:={yaml_text(parameter.value)}"]
            elif parameter.file is not None:
                args += ["--params-file", str(parameter.file)]
            elif params_file is not None:
                args += ["--params-file", str(params_file(parameter))]
        for source, target in (*self.scope_remappings, *self.remappings):
            args += ["-r", f"{source}:={target}"]
        args += list(self.ros_arguments)
        return ["--ros-args", *args] if args else []


def yaml_text(value: Any) -> str:
    """A parameter value as launch_ros passes it (``-p name:=<YAML>``)."""
    text = yaml.safe_dump(value, default_flow_style=True, width=float("inf")).strip()
    return text.removesuffix("\n...").removesuffix("...").strip()


@dataclass(frozen=True)
class DeclaredArgument:
    name: str
    default: str | None
    description: str | None
    choices: tuple[str, ...]
    where: Where


@dataclass(frozen=True)
class Unsupported:
    where: Where
    what: str


@dataclass
class LaunchResult:
    """What a launch file starts (``nodes``, in launch order) and what it could not read."""

    source: Path
    arguments: dict[str, str]
    nodes: list[LaunchedNode] = field(default_factory=list)
    declared: list[DeclaredArgument] = field(default_factory=list)
    unsupported: list[Unsupported] = field(default_factory=list)
    files: list[Path] = field(default_factory=list)

    def require_supported(self) -> None:
        """Raise one :class:`LaunchError` listing every unsupported construct, if any."""
        if not self.unsupported:
            return
        listing = "\n".join(f"  {u.where}: {u.what}" for u in self.unsupported)
        raise LaunchError(
            f"{shown(self.source)} uses what the launch reader does not support, so the system it starts "
            f"cannot be captured faithfully:\n{listing}\nRemove or rewrite these (or put them under a condition "
            "that is false for the check), or set `allow_unsupported: true` in the system contract's `launch:` "
            "block (--allow-unsupported) to capture the rest; they are then listed as notes."
        )




def join_namespace(base: str | None, namespace: str | None) -> str | None:
    """``namespace`` below ``base`` (an absolute ``namespace`` stands alone), as launch_ros does."""
    if namespace is None or namespace.strip("/") == "" and not namespace.startswith("/"):
        return base
    if namespace.startswith("/"):
        joined = namespace
    else:
        joined = (base or "").rstrip("/") + "/" + namespace
    joined = "/" + joined.strip("/")
    return joined


def find_package_prefix(package: str, prefixes: Sequence[Path]) -> Path:
    """The first ament prefix that has ``package`` (raises SubstitutionError)."""
    found = ament_index.providers(package, prefixes)
    if found:
        return found[0]
    searched = ", ".join(str(p) for p in prefixes) or "none: AMENT_PREFIX_PATH is empty"
    raise SubstitutionError(
        f"package '{package}' is not in the ament index (searched the prefixes {searched}); build and "
        "install it, or add its install prefix to AMENT_PREFIX_PATH." + editable_installs.not_found_hint(package)
    )
