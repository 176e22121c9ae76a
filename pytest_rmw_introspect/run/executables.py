"""Which program a target names: ``ros2 run``'s lookup of a package's executable in the ament
prefixes (and the console scripts and editable installs that stand in for one), entry points and
modules, the command line a :class:`~.target.TargetSpec` starts (:func:`build_argv`) and how
messages show it."""

from __future__ import annotations

import difflib
import os
import re
import shutil
import sys
from collections.abc import Sequence
from pathlib import Path

from ..errors import ExecutableNotFound, TargetConfigError
from ..model import ament_index, editable_installs
from .target import TargetSpec, ros_arguments


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
            scripts = console_scripts(spec.package, python_path(spec))
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


def python_path(spec: TargetSpec) -> list[str]:
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


