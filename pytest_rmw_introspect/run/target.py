"""What to run: target options → one validated spec → what the runner starts.

The same keys are accepted everywhere (the capture API, a contract's ``target`` block, the
``interfaces`` marker's keyword arguments, and some of them as pytest options, ini keys and
``rmw-introspect`` flags): the table ``model.option_tables.TARGET`` names them with their types,
defaults, help and front ends (``options_reference.render_markdown("target")`` renders it). This
module decides what each value means (:func:`_convert`) and how a target is started:
:func:`resolve` turns a :class:`TargetSpec` into a :class:`ResolvedTarget` (command line,
complete environment, working directory, warm or cold start and why), the one value the runner
starts.

Exactly one of ``package``+``executable``, ``command``, ``script``, ``module``, ``entry_point``
names the target. Relative paths (``script``, ``params_file``, ``cwd`` and a ``command`` whose
first element contains a ``/``) are relative to the file that named them.
"""

from __future__ import annotations

import difflib
import math
import os
import re
import shlex
import shutil
import sys
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

from ..errors import ExecutableNotFound, TargetConfigError
from ..model import ament_index, editable_installs
from ..model.option_tables import MAX_SECONDS, TARGET
from ..model.parameters import flatten
from ..model.vocabulary import DEFAULT_LIFECYCLE_TARGET, LIFECYCLE_TARGETS
from . import middleware, ros_env

if TYPE_CHECKING:
    from .warm.client import Plan

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
        prefixes = ament_index.env_prefixes()
        names = package_executables(str(self.package), [*prefixes, Path(sys.prefix)], _python_path(self))
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


# ---------------------------------------------------------------------- ament index


def find_executable(package: str, executable: str, prefixes: Sequence[Path]) -> Path:
    """Find ``<prefix>/lib/<package>/<executable>`` like ``ros2 run``.

    A prefix provides ``package`` when it has
    ``share/ament_index/resource_index/packages/<package>``. The first prefix (in
    ``AMENT_PREFIX_PATH`` order) providing the package wins, like ``ros2 run``.
    """
    providers = ament_index.providers(package, prefixes)
    searched = [str(p) for p in prefixes]
    if not providers:
        raise ExecutableNotFound(
            f"Package '{package}' was not found in the ament index. Searched the prefixes "
            f"{searched or '(none: AMENT_PREFIX_PATH is empty)'}"
            " for share/ament_index/resource_index/packages/" + package + ". Build and source the "
            "workspace that provides it (or add its install prefix to AMENT_PREFIX_PATH)."
            + editable_installs.not_found_hint(package, if_absent=False),
            target=f"{package}/{executable}",
            searched=searched,
        )
    prefix = providers[0]
    lib_dir = prefix / "lib" / package
    candidate = lib_dir / executable
    available = sorted(
        p.name for p in lib_dir.iterdir() if p.is_file() and os.access(p, os.X_OK)
    ) if lib_dir.is_dir() else []
    if not candidate.is_file():
        also = [str(p) for p in providers[1:] if (p / "lib" / package / executable).is_file()]
        hint = ""
        if also:
            hint = (
                f" Other prefixes do have it ({', '.join(also)}) but {prefix} comes first in "
                "AMENT_PREFIX_PATH and shadows them."
            )
        raise ExecutableNotFound(
            f"Executable '{executable}' not found in package '{package}' (looked for {candidate}). "
            + (f"The package has these executables: {', '.join(available)}." if available
               else f"The package has no executables in {lib_dir}.")
            + hint,
            target=f"{package}/{executable}",
            searched=[str(candidate)],
            found=available,
        )
    if not os.access(candidate, os.X_OK):
        raise ExecutableNotFound(
            f"{candidate} exists but is not executable (chmod +x it, or install it with "
            "`install(TARGETS ...)` / a console script entry point).",
            target=f"{package}/{executable}",
            searched=[str(candidate)],
        )
    return candidate


def package_executables(package: str, prefixes: Sequence[Path], python_path: Sequence[str] = ()) -> list[str]:
    """Every executable ``package`` installs: ``lib/<package>/*`` of the first prefix that has the
    package (like ``ros2 run``), else the console scripts of the Python distribution ``package``."""
    providers = ament_index.providers(package, prefixes)
    if providers:
        lib_dir = providers[0] / "lib" / package
        return sorted(p.name for p in lib_dir.iterdir() if p.is_file() and os.access(p, os.X_OK)) if lib_dir.is_dir() else []
    return sorted(console_scripts(package, list(python_path) or sys.path) or {})


def closest(name: str, candidates: Sequence[str]) -> str:
    """`` Did you mean 'x'?`` for the candidate closest to a mistyped ``name`` (empty if none is close)."""
    match = difflib.get_close_matches(name, list(candidates), n=1, cutoff=0.6)
    return f" Did you mean '{match[0]}'?" if match else ""


def build_argv(spec: TargetSpec, prefixes: Sequence[Path] = (), python: str | None = None) -> list[str]:
    """The full command line of ``spec`` (``prefixes``: the ament prefixes to search)."""
    spec.validate()
    python = python or sys.executable
    kind = spec.kind
    if kind == "executable":
        assert spec.package and spec.executable
        try:
            base = [str(find_executable(spec.package, spec.executable, prefixes))]
        except ExecutableNotFound as not_installed:
            # an ament_python package developed in a venv (`pip install -e .`): its executables
            # are console scripts in the venv's bin/, not in lib/<package>/
            scripts = console_scripts(spec.package, _python_path(spec))
            if not scripts or spec.executable not in scripts:
                in_index = bool(ament_index.providers(spec.package, prefixes))
                raise _no_console_script(spec.package, spec.executable, scripts, in_index, not_installed) from None
            base = entry_point_argv(scripts[spec.executable], python, name=spec.executable)
    elif kind == "script":
        assert spec.script is not None
        if not spec.script.is_file():
            raise ExecutableNotFound(
                f"Python script {spec.script} does not exist.",
                target=spec.describe(),
                searched=[str(spec.script)],
            )
        base = [python, str(spec.script)]
    elif kind == "module":
        base = [python, "-m", str(spec.module)]
    elif kind == "entry_point":
        assert spec.entry_point is not None
        base = entry_point_argv(spec.entry_point, python)
    else:
        assert spec.command is not None
        base = list(spec.command)
        base[0] = _which(base[0], spec)
    if spec.params_file is not None and not spec.params_file.is_file():
        raise TargetConfigError(f"params_file {spec.params_file} does not exist.")
    return [*base, *spec.arguments, *ros_arguments(spec)]


def _no_console_script(package: str, executable: str, scripts: dict[str, str] | None, in_index: bool,
                       not_installed: ExecutableNotFound) -> ExecutableNotFound:
    """The error for an executable found neither in the ament index nor among the console scripts
    of a Python distribution named ``package``: led by what the user does have."""
    if scripts is None and not in_index:  # neither an ament package nor a Python distribution
        return ExecutableNotFound(
            f"{not_installed} No Python distribution named '{package}' is installed either (an "
            "ament_python package developed in a venv is installed with `pip install -e .`).",
            target=not_installed.target, searched=not_installed.searched, found=not_installed.found)
    if in_index or scripts is None:  # an ament package: find_executable listed its executables already
        return ExecutableNotFound(f"{not_installed}{closest(executable, not_installed.found)}",
                                  target=not_installed.target, searched=not_installed.searched,
                                  found=not_installed.found)
    names = sorted(scripts)
    listed = (f"its console scripts are: {', '.join(names)}.{closest(executable, names)}" if names else
              "it has no console scripts (declare them under `entry_points={'console_scripts': [...]}` "
              "in setup.py, or `[project.scripts]` in pyproject.toml, and reinstall it).")
    return ExecutableNotFound(
        f"Executable '{executable}' not found in package '{package}': the package is installed as a Python "
        f"distribution (pip), not in the ament index, and {listed}",
        target=not_installed.target, searched=not_installed.searched, found=names)


#: what pip's console-script wrapper does: import the module, call the function, exit with its result
_ENTRY_POINT_LAUNCHER = (
    "import importlib, sys\n"
    "target = sys.argv.pop(1)\n"
    "module, _, attribute = target.partition(':')\n"
    "sys.argv[0] = sys.argv.pop(1)\n"
    "function = importlib.import_module(module)\n"
    "for part in attribute.split('.'):\n"
    "    function = getattr(function, part)\n"
    "sys.exit(function())\n"
)


def entry_point_argv(entry_point: str, python: str, name: str | None = None) -> list[str]:
    """The command line that calls ``package.module:function`` like its console script;
    ``sys.argv[0]`` is ``name`` (the script's name) or the function's."""
    return [python, "-c", _ENTRY_POINT_LAUNCHER, entry_point, name or entry_point.rpartition(":")[2]]


def command_as_typed(argv: Sequence[str]) -> list[str]:
    """``argv`` as the user would type it: a console script started through our launcher
    (:func:`entry_point_argv`) is shown as the script (``<venv>/bin/<name>`` when it is there)."""
    if len(argv) >= 5 and argv[1] == "-c" and argv[2] == _ENTRY_POINT_LAUNCHER:
        name = argv[4]
        script = Path(argv[0]).parent / name
        return [str(script) if script.is_file() else name, *argv[5:]]
    return list(argv)


def _python_path(spec: TargetSpec) -> list[str]:
    """Where the target's interpreter finds distributions: its PYTHONPATH, then ours."""
    extra = [p for p in (spec.env.get("PYTHONPATH") or os.environ.get("PYTHONPATH") or "").split(os.pathsep) if p]
    return [*extra, *sys.path]


def _normalized(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def console_scripts(package: str, path: Sequence[str]) -> dict[str, str] | None:
    """The ``console_scripts`` entry points (name -> ``module:function``) of the Python distribution
    named ``package`` (``-``/``_`` and case ignored) found on ``path``; None if there is no such
    distribution (an empty mapping if it has no console scripts)."""
    from importlib import metadata  # ~15 ms (+ email): only console scripts need it

    wanted = _normalized(package)
    for dist in metadata.distributions(path=list(path)):
        if _normalized(dist.metadata["Name"] or "") == wanted:
            return {ep.name: str(ep.value) for ep in dist.entry_points if ep.group == "console_scripts"}
    return None


def _which(program: str, spec: TargetSpec) -> str:
    if "/" in program:
        if not os.path.isfile(program):
            raise ExecutableNotFound(
                f"Command {program} does not exist.", target=spec.describe(), searched=[program]
            )
        if not os.access(program, os.X_OK):
            raise ExecutableNotFound(
                f"Command {program} is not executable (chmod +x it).",
                target=spec.describe(),
                searched=[program],
            )
        return program
    found = shutil.which(program, path=(spec.env or {}).get("PATH") or os.environ.get("PATH"))
    if found is None:
        raise ExecutableNotFound(
            f"Command '{program}' was not found on PATH.",
            target=spec.describe(),
            searched=(os.environ.get("PATH") or "").split(os.pathsep),
        )
    return found


# ---------------------------------------------------------------------- resolution

#: the directory of a capture's files that rcl's log files go to (``ROS_LOG_DIR``)
LOG_DIR = "ros_log"
#: the capture file of each process (the middleware substitutes the process id: every ROS
#: process of the target writes its own file)
OUTPUT_PATTERN = "capture.<pid>.json"


def environment(
    spec: TargetSpec,
    library: Path,
    ros: ros_env.RosEnvironment,
    output: Path,
    base: Mapping[str, str] | None = None,
) -> dict[str, str]:
    """The complete environment of the target process; ``output`` may contain ``<pid>``, which
    the middleware replaces with each process's id. rcl's log files of the capture go to
    ``ros_log`` beside ``output`` (``ROS_LOG_DIR``), unless the environment or the target's
    ``env`` says where logs go (``ROS_LOG_DIR`` or ``ROS_HOME``)."""
    env = dict(os.environ if base is None else base)
    # the target's own variables first, then the activation merged with them: a target's
    # LD_PRELOAD, LD_LIBRARY_PATH or AMENT_PREFIX_PATH extends the middleware's, never drops it
    env.update(spec.env)
    if "ROS_LOG_DIR" not in env and "ROS_HOME" not in env:
        # A capture is an analysis of the node, not a run of it: its log file (one per process,
        # as `ros2 run` writes) is removed with the capture's files instead of piling up in
        # ~/.ros/log, a file per capture and CI run; RMW_INTROSPECT_KEEP_FILES keeps it.
        env["ROS_LOG_DIR"] = str(Path(output).parent / LOG_DIR)
    env.update(ros_env.activation_env(library, ros, base=env))
    env["RMW_INTROSPECT_OUTPUT"] = str(output)
    env["RMW_INTROSPECT_FORMAT"] = "json"
    env["RMW_INTROSPECT_EXIT"] = "1"
    env["RMW_INTROSPECT_AUTO_EXPORT"] = "1"
    env["RMW_INTROSPECT_SETTLE_MS"] = str(max(0, round(spec.effective_settle() * 1000)))
    env["RMW_INTROSPECT_HORIZON_MS"] = str(max(0, round(spec.effective_horizon() * 1000)))
    env["RMW_INTROSPECT_LIFECYCLE"] = spec.effective_lifecycle()
    env["RMW_INTROSPECT_PARAMETERS"] = "1" if spec.effective_read_parameters() else "0"
    if spec.stimuli:
        env["RMW_INTROSPECT_STIMULI"] = ",".join(spec.stimuli)
    env.setdefault("PYTHONUNBUFFERED", "1")
    # numpy's OpenBLAS (rclpy imports numpy) starts a worker thread per core that spins for 2^28
    # cycles before it sleeps: ~40 ms of a core, at the start of every cold Python target, during
    # which the middleware cannot prove the process idle. 2^4 cycles: they sleep at once. (A warm
    # child has no such threads: its server loaded OpenBLAS single-threaded.)
    env.setdefault("OPENBLAS_THREAD_TIMEOUT", "4")
    return env


@dataclass(frozen=True)
class ResolvedTarget:
    """A target resolved into what the runner starts (:func:`resolve`): everything the runner
    needs to start it, wait for it and word its errors, so that it asks the spec nothing more.
    Frozen, its mappings read-only."""

    #: a short name for messages (``TargetSpec.describe``)
    name: str
    #: where each of its processes writes its capture file (``<pid>``: the process id)
    output: Path
    #: the full command line
    argv: tuple[str, ...]
    #: the command line as messages show it (:func:`command_as_typed`: a console script as itself)
    shown_argv: tuple[str, ...]
    #: the complete environment of the process (:func:`environment`)
    env: Mapping[str, str]
    #: its working directory (None: the runner's)
    cwd: Path | None
    #: seconds to wait for it before it is stopped
    timeout: float
    #: the lifecycle state the middleware drives lifecycle nodes to
    lifecycle: str
    #: the topics and services the middleware sends a default message or request to
    stimuli: tuple[str, ...]
    #: how it starts warm (forked from a warm start server); None: it starts cold
    warm: Plan | None
    #: why it starts cold (None: it starts warm)
    cold_because: str | None
    #: the module of a ``module`` target and the target's own ``env:`` (where ``python -m``
    #: finds it: asked only when it created no node)
    module: str | None
    own_env: Mapping[str, str]
    #: the ament prefixes its executables and packages were looked up in
    prefixes: tuple[Path, ...]
    #: the ROS 2 distribution it runs on (None: not known)
    ros_distribution: str | None

    @property
    def how(self) -> str:
        """``warm`` or ``cold``."""
        return "cold" if self.warm is None else "warm"

    def started_cold(self, because: str) -> ResolvedTarget:
        """The same target, started cold ``because`` (a warm start that failed)."""
        return replace(self, warm=None, cold_because=because)


def resolve(
    spec: TargetSpec,
    *,
    workdir: Path,
    library: str | Path | None = None,
    ros: ros_env.RosEnvironment | None = None,
    python: str | None = None,
    cold_note: str | None = None,
) -> ResolvedTarget:
    """Resolve ``spec`` into what the runner starts, its capture files in ``workdir``
    (:data:`OUTPUT_PATTERN`) and its log files beside them. ``library``: the middleware library (default: ``middleware.ensure_library``);
    ``ros``: the ROS environment (default: ``ros_env.detect()``); ``python``: the interpreter of
    Python targets (default: this one); ``cold_note``: start it cold, for this reason, without
    asking whether it could start warm. Raises :class:`TargetConfigError` for a spec that names
    no target (or two), :class:`ExecutableNotFound` for one that cannot be found."""
    spec.validate()
    ros = ros or ros_env.detect()
    if library is None:
        library = middleware.ensure_library(ros)
    # like `ros2 run`: AMENT_PREFIX_PATH as it is now, then the prefixes of the detected install
    prefixes = ros_env.ament_prefixes(tuple(getattr(ros, "ament_prefixes", ())))
    argv = build_argv(spec, prefixes, python=python)
    output = workdir / OUTPUT_PATTERN
    env = environment(spec, Path(library), ros, output)
    describe = spec.describe()
    if spec.cwd is not None and not spec.cwd.is_dir():
        raise ExecutableNotFound(f"Working directory {spec.cwd} of target {describe} does not exist.", target=describe)
    warm: Plan | None = None
    because = cold_note
    if because is None:
        because = "cold_start asked for it" if spec.cold_start else None
    if because is None:
        from .warm import client as warm_client

        how = warm_client.plan(argv, env, python)
        if isinstance(how, warm_client.Plan):
            warm = how
        else:
            because = how
    return ResolvedTarget(
        name=describe,
        output=output,
        argv=tuple(argv),
        shown_argv=tuple(command_as_typed(argv)),
        env=MappingProxyType(env),
        cwd=spec.cwd,
        timeout=spec.effective_timeout(),
        lifecycle=spec.effective_lifecycle(),
        stimuli=spec.stimuli,
        warm=warm,
        cold_because=because,
        module=spec.module,
        own_env=MappingProxyType(dict(spec.env)),
        prefixes=tuple(prefixes),
        ros_distribution=getattr(ros, "distro", None),
    )
