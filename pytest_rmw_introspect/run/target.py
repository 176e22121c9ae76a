"""What to run: target options → one validated spec → what the runner starts.

The same keys are accepted everywhere (the capture API, a contract's ``target`` block, the
``interfaces`` marker's keyword arguments, and some of them as pytest options, ini keys and
``rmw-introspect`` flags): the table ``model.option_tables.TARGET`` names them with their types,
defaults, help and front ends (``options_reference.render_markdown("target")`` renders it). This
module decides what each value means (:func:`_convert`), merges the layers that give them
(:func:`merge`) and writes a spec's ROS arguments (:func:`ros_arguments`). Which program a spec
names is ``run.executables``; how it is started (its command line, environment and warm or cold
start) is ``run.resolution``.

Exactly one of ``package``+``executable``, ``command``, ``script``, ``module``, ``entry_point``
names the target. Relative paths (``script``, ``params_file``, ``cwd`` and a ``command`` whose
first element contains a ``/``) are relative to the file that named them.
"""

from __future__ import annotations

import math
import os
import re
import shlex
import sys
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any

from ..errors import TargetConfigError
from ..model import ament_index
from ..model.option_tables import MAX_SECONDS, TARGET
from ..model.parameters import flatten
from ..model.vocabulary import DEFAULT_LIFECYCLE_TARGET, LIFECYCLE_TARGETS

DEFAULT_TIMEOUT: float = TARGET["timeout"].default
DEFAULT_SETTLE: float = TARGET["settle"].default
DEFAULT_HORIZON: float = TARGET["horizon"].default

#: keys that say *what* to run; a layer that sets one of them replaces the whole choice
KIND_KEYS = ("package", "executable", "command", "script", "module", "entry_point")
#: every target key, in table order
TARGET_KEYS = TARGET.names()


@dataclass(frozen=True)
class TargetSpec:
    """A fully described target. Build it with :meth:`from_mapping` or :func:`merge`."""

    package: str | None = None
    executable: str | None = None
    command: tuple[str, ...] | None = None
    script: Path | None = None
    module: str | None = None
    entry_point: str | None = None
    arguments: tuple[str, ...] = ()
    namespace: str | None = None
    node_name: str | None = None
    remappings: tuple[tuple[str, str], ...] = ()
    parameters: Mapping[str, Any] = field(default_factory=dict)
    params_file: Path | None = None
    env: Mapping[str, str] = field(default_factory=dict)
    cwd: Path | None = None
    settle: float | None = None
    timeout: float | None = None
    horizon: float | None = None
    cold_start: bool | None = None
    lifecycle: str | None = None
    read_parameters: bool | None = None
    stimuli: tuple[str, ...] = ()

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_mapping(
        cls,
        options: Mapping[str, Any] | None,
        *,
        base_dir: str | Path | None = None,
        source: str = "target options",
    ) -> TargetSpec:
        """Validate ``options`` (the documented keys) and build a spec.

        ``source`` names where the options come from in error messages (a contract file,
        a marker, ...). Relative paths are resolved against ``base_dir``.
        """
        return cls()._with(options or {}, base_dir=base_dir, source=source)

    def _with(self, options: Mapping[str, Any], *, base_dir: str | Path | None, source: str) -> TargetSpec:
        unknown = sorted(set(options) - set(TARGET_KEYS))
        if unknown:
            raise TargetConfigError(
                f"{source}: unknown target option(s) {', '.join(map(repr, unknown))}; "
                f"known: {', '.join(TARGET_KEYS)}"
            )
        base = Path(base_dir) if base_dir is not None else None
        values: dict[str, Any] = {}
        given = {k: v for k, v in options.items() if v is not None}
        if any(k in given for k in KIND_KEYS):
            # a new choice of what to run replaces the inherited one entirely
            values.update(package=None, executable=None, command=None, script=None, module=None, entry_point=None)
        for key, value in given.items():
            values[key] = _convert(key, value, base, source)
        spec = replace(self, **values)
        return spec

    def merged(
        self, options: Mapping[str, Any] | None, *, base_dir: str | Path | None = None, source: str = "target options"
    ) -> TargetSpec:
        """This spec with ``options`` layered on top (``options`` win)."""
        return self._with(options or {}, base_dir=base_dir, source=source)

    # ------------------------------------------------------------------ queries
    @property
    def kind(self) -> str | None:
        if self.command is not None:
            return "command"
        if self.script is not None:
            return "script"
        if self.module is not None:
            return "module"
        if self.entry_point is not None:
            return "entry_point"
        if self.package is not None or self.executable is not None:
            return "executable"
        return None

    def describe(self) -> str:
        """A short name for messages: ``demo_nodes_py/talker``, ``script talker.py``, ..."""
        kind = self.kind
        if kind == "executable":
            return f"{self.package}/{self.executable}"
        if kind == "command":
            return "`" + shlex.join(self.command or ()) + "`"
        if kind == "script":
            return f"script {self.script}"
        if kind == "module":
            return f"module {self.module}"
        if kind == "entry_point":
            return f"entry point {self.entry_point}"
        return "(no target)"

    def effective_timeout(self) -> float:
        return DEFAULT_TIMEOUT if self.timeout is None else self.timeout

    def effective_settle(self) -> float:
        return DEFAULT_SETTLE if self.settle is None else self.settle

    def effective_horizon(self) -> float:
        return DEFAULT_HORIZON if self.horizon is None else self.horizon

    def effective_lifecycle(self) -> str:
        return DEFAULT_LIFECYCLE_TARGET if self.lifecycle is None else self.lifecycle

    def effective_read_parameters(self) -> bool:
        return True if self.read_parameters is None else self.read_parameters

    def validate(self) -> None:
        """Raise :class:`TargetConfigError` unless exactly one way of running is chosen."""
        chosen = [
            name
            for name, present in (
                ("package/executable", self.package is not None or self.executable is not None),
                ("command", self.command is not None),
                ("script", self.script is not None),
                ("module", self.module is not None),
                ("entry_point", self.entry_point is not None),
            )
            if present
        ]
        if not chosen:
            raise TargetConfigError(
                "No target to run: give `package` and `executable`, `command`, `script`, `module` "
                "or `entry_point` (in the marker's keyword arguments, the contract's `target:` block, "
                "or the capture() call)."
            )
        if len(chosen) > 1:
            raise TargetConfigError(f"Ambiguous target: both {' and '.join(chosen)} are set; choose one.")
        if chosen[0] == "package/executable" and (not self.package or not self.executable):
            missing = "executable" if self.package else "package"
            raise TargetConfigError(self._incomplete_package_target(missing))
        if self.command is not None and not self.command:
            raise TargetConfigError("Target `command` is empty.")
        for key, value in (("timeout", self.timeout), ("settle", self.settle)):
            if value is not None and (value < 0 or value > MAX_SECONDS or (key == "timeout" and value == 0)):
                raise TargetConfigError(f"Target `{key}` must be {seconds_range(key)}, got {value:g}.")

    def _incomplete_package_target(self, missing: str) -> str:
        """What to say when only one of ``package`` and ``executable`` is given."""
        if missing == "package":
            return (f"Target package/executable is incomplete: `package` is missing (executable "
                    f"'{self.executable}' was given): name the ROS package that installs it.")
        from .executables import package_executables, python_path  # the lookup, for this message only

        prefixes = ament_index.env_prefixes()
        names = package_executables(str(self.package), [*prefixes, Path(sys.prefix)], python_path(self))
        listed = (f"The package has these executables: {', '.join(names)}" if names else
                  f"No executable of package '{self.package}' was found (is it installed?)")
        return (f"Target package/executable is incomplete: `executable` is missing for package "
                f"'{self.package}'. {listed}; choose one with `executable` (--executable on the command line).")

    def to_mapping(self) -> dict[str, Any]:
        """The non-default options as plain data (for messages and reports)."""
        out: dict[str, Any] = {}
        for f in fields(self):
            value = getattr(self, f.name)
            if value is None or value == () or value == {}:
                continue
            if isinstance(value, Path):
                value = str(value)
            elif f.name == "remappings":
                value = {a: b for a, b in value}
            elif isinstance(value, tuple):
                value = list(value)
            elif isinstance(value, Mapping):
                value = dict(value)
            out[f.name] = value
        return out


# ---------------------------------------------------------------------- conversions


def seconds_range(key: str) -> str:
    """What a duration option (``settle``, ``timeout``, ``horizon``) takes, said the same way wherever it is checked."""
    if key == "timeout":  # a target that gets no time at all cannot be captured
        return f"a number of seconds more than 0 and at most {MAX_SECONDS:g}"
    return f"a number of seconds from 0 to {MAX_SECONDS:g}"


def _fail(source: str, key: str, expected: str, value: Any) -> TargetConfigError:
    return TargetConfigError(f"{source}: `{key}` must be {expected}, got {value!r}")


def _path(value: Any, base: Path | None, source: str, key: str) -> Path:
    if not isinstance(value, (str, os.PathLike)) or not str(value):
        raise _fail(source, key, "a path", value)
    p = Path(os.path.expanduser(str(value)))
    if not p.is_absolute() and base is not None:
        p = base / p
    return p


def _str_list(value: Any, source: str, key: str) -> tuple[str, ...]:
    if isinstance(value, str):
        return tuple(shlex.split(value))
    if isinstance(value, (list, tuple)) and all(isinstance(v, (str, int, float, os.PathLike)) for v in value):
        return tuple(str(v) for v in value)
    raise _fail(source, key, "a list of strings", value)


#: a fully qualified ROS name: `/` then tokens of letters, digits and `_`, none starting with a digit
_FULL_NAME = re.compile(r"^(/[A-Za-z_][A-Za-z0-9_]*)+$")


def _stimuli(value: Any, source: str) -> tuple[str, ...]:
    if isinstance(value, str):
        names = [n for n in re.split(r"[,\s]+", value) if n]
    elif isinstance(value, (list, tuple)) and all(isinstance(v, str) for v in value):
        names = [n.strip() for n in value]
    else:
        raise _fail(source, "stimuli", "a list of topic or service names", value)
    unique: list[str] = []
    for name in names:
        if not _FULL_NAME.match(name):
            raise TargetConfigError(
                f"{source}: `stimuli`: {name!r} is not a fully resolved topic or service name; write it as the "
                "capture shows it, with its namespace (`/camera_info`, `/robot1/reset`; no `~`, no relative names)"
            )
        if name not in unique:
            unique.append(name)
    return tuple(unique)


_ENTRY_POINT = re.compile(r"^[A-Za-z_][\w]*(\.[A-Za-z_][\w]*)*:[A-Za-z_][\w]*(\.[A-Za-z_][\w]*)*$")


def _convert(key: str, value: Any, base: Path | None, source: str) -> Any:
    if key in ("package", "executable", "module", "node_name"):
        if not isinstance(value, str) or not value:
            raise _fail(source, key, "a non-empty string", value)
        return value
    if key == "entry_point":
        if not isinstance(value, str) or not _ENTRY_POINT.match(value.strip()):
            raise _fail(source, key, "a function as `package.module:function`", value)
        return value.strip()
    if key == "namespace":
        if not isinstance(value, str):
            raise _fail(source, key, "a string", value)
        return value if value.startswith("/") else "/" + value
    if key == "command":
        cmd = _str_list(value, source, key)
        if cmd and "/" in cmd[0] and base is not None and not os.path.isabs(cmd[0]):
            cmd = (str(base / cmd[0]),) + cmd[1:]
        return cmd
    if key == "arguments":
        return _str_list(value, source, key)
    if key in ("script", "params_file", "cwd"):
        return _path(value, base, source, key)
    if key == "remappings":
        return _remappings(value, source)
    if key == "parameters":
        if isinstance(value, bool):
            raise _fail(source, key, "a mapping of parameter names to values (the -p values given to the node; "
                        "`read_parameters: false` stops reading the node's parameters)", value)
        if not isinstance(value, Mapping) or not all(isinstance(k, str) for k in value):
            raise _fail(source, key, "a mapping of parameter names to values", value)
        return dict(value)
    if key == "env":
        if not isinstance(value, Mapping):
            raise _fail(source, key, "a mapping of variable names to strings", value)
        env = {str(k): _env_value(v) for k, v in value.items()}
        _refuse_runner_variables(env, source)
        return env
    if key == "cold_start":
        if not isinstance(value, bool):
            raise _fail(source, key, "true or false", value)
        return value
    if key == "stimuli":
        return _stimuli(value, source)
    if key in ("settle", "timeout", "horizon"):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise _fail(source, key, "a number of seconds", value)
        if not 0 <= value <= MAX_SECONDS or (key == "timeout" and value == 0):
            raise _fail(source, key, seconds_range(key), value)
        return float(value)
    if key == "lifecycle":
        if not isinstance(value, str) or value.strip().lower() not in LIFECYCLE_TARGETS:
            raise _fail(source, key, f"one of {', '.join(LIFECYCLE_TARGETS)}", value)
        return value.strip().lower()
    if key == "read_parameters":
        if isinstance(value, str) and value.strip().lower() in ("true", "false", "1", "0", "yes", "no", "on", "off"):
            return value.strip().lower() in ("true", "1", "yes", "on")
        if not isinstance(value, bool):
            raise _fail(source, key, "true or false", value)
        return value
    raise AssertionError(key)  # pragma: no cover


#: middleware variables the runner sets for every capture from the target options (an `env:`
#: entry would be overwritten without a word): the option to use instead, or None (no option)
RUNNER_VARIABLES = {
    "RMW_INTROSPECT_SETTLE_MS": "settle (seconds)",
    "RMW_INTROSPECT_HORIZON_MS": "horizon (seconds)",
    "RMW_INTROSPECT_LIFECYCLE": "lifecycle",
    "RMW_INTROSPECT_PARAMETERS": "read_parameters",
    "RMW_INTROSPECT_STIMULI": "stimuli",
    "RMW_INTROSPECT_OUTPUT": None,
    "RMW_INTROSPECT_FORMAT": None,
    "RMW_INTROSPECT_EXIT": None,
    "RMW_INTROSPECT_AUTO_EXPORT": None,
}


def _refuse_runner_variables(env: Mapping[str, str], source: str) -> None:
    owned = [name for name in env if name in RUNNER_VARIABLES]
    if not owned:
        return
    reasons = []
    for name in owned:
        option = RUNNER_VARIABLES[name]
        reasons.append(f"{name}: set the target option `{option}` instead" if option else
                       f"{name}: the runner sets it for every capture (where the capture goes, its format, "
                       "ending the target once it settled); remove it")
    raise TargetConfigError(f"{source}: `env` sets middleware variables the runner owns, which would be "
                            "overwritten:\n  " + "\n  ".join(reasons))


def _env_value(v: Any) -> str:
    if isinstance(v, bool):
        return "1" if v else "0"
    return str(v)


def _remappings(value: Any, source: str) -> tuple[tuple[str, str], ...]:
    pairs: list[tuple[str, str]] = []
    if isinstance(value, Mapping):
        items: Iterable[Any] = value.items()
    elif isinstance(value, (list, tuple)):
        items = value
    else:
        raise _fail(source, "remappings", "a mapping from → to or a list of 'from:=to'", value)
    for item in items:
        if isinstance(item, str) and ":=" in item:
            a, b = item.split(":=", 1)
        elif isinstance(item, (list, tuple)) and len(item) == 2:
            a, b = item
        else:
            raise _fail(source, "remappings", "a mapping from → to or a list of 'from:=to'", value)
        if not isinstance(a, str) or not isinstance(b, str) or not a or not b:
            raise _fail(source, "remappings", "non-empty strings", item)
        pairs.append((a, b))
    return tuple(pairs)


def merge(*layers: tuple[Mapping[str, Any] | None, str | Path | None, str]) -> TargetSpec:
    """Layer target options: ``(options, base_dir, source)`` triples, later layers win."""
    spec = TargetSpec()
    for options, base, source in layers:
        spec = spec.merged(options, base_dir=base, source=source)
    return spec


# ---------------------------------------------------------------------- parameters


def ros_argument_value(value: Any) -> str:
    """Encode a parameter value the way rcl parses ``-p name:=<value>`` (a YAML scalar or flow list).

    Strings that YAML would read as something else (``"true"``, ``"1"``, ``""``) are quoted;
    floats always carry a decimal point so that ``1.0`` stays a double.
    """
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(ros_argument_value(v) for v in value) + "]"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return ".nan"
        if math.isinf(value):
            return ".inf" if value > 0 else "-.inf"
        text = repr(value)
        if "e" in text or "E" in text:
            mantissa, exp = text.lower().split("e")
            if "." not in mantissa:
                mantissa += ".0"
            text = f"{mantissa}e{exp}"
        elif "." not in text:
            text += ".0"
        return text
    if isinstance(value, (bytes, bytearray)):
        return "[" + ", ".join(str(b) for b in value) + "]"
    if isinstance(value, str):
        import yaml  # ~20 ms: only a string parameter value needs it

        dumped = yaml.safe_dump(value, default_flow_style=True, width=math.inf, allow_unicode=True)
        dumped = dumped.strip()
        if dumped.endswith("\n..."):
            dumped = dumped[: -len("\n...")]
        elif dumped.endswith("..."):
            dumped = dumped[:-3].rstrip()
        # plain scalars that contain ", " or brackets would confuse a flow list: quote those
        if dumped == value and any(c in value for c in ",[]{}#") and not value.startswith(("'", '"')):
            dumped = "'" + value.replace("'", "''") + "'"
        return dumped
    raise TargetConfigError(f"parameter value {value!r} has a type ROS parameters cannot hold")


def ros_arguments(spec: TargetSpec) -> list[str]:
    """The ``--ros-args ...`` part of the command line (empty when there is nothing to pass)."""
    args: list[str] = []
    if spec.namespace is not None:
        args += ["-r", f"__ns:={spec.namespace}"]
    if spec.node_name is not None:
        args += ["-r", f"__node:={spec.node_name}"]
    for a, b in spec.remappings:
        args += ["-r", f"{a}:={b}"]
    for name, value in flatten(spec.parameters).items():
        args += ["-p", f"{name}:={ros_argument_value(value)}"]
    if spec.params_file is not None:
        args += ["--params-file", str(spec.params_file)]
    return ["--ros-args", *args] if args else []
