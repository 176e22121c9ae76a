"""What a launch file gives each process, as the rules of ``compare.launch_given`` read it.

:func:`given` turns a launched node (``launch.result.LaunchedNode``) into a
``compare.launch_given.Given``: the parameters set on its command line (``<param>``, ``<set_parameter>``,
``-p`` in ``ros_args``), the node sections of its parameters files (read here, within the limits of
untrusted input), and its remappings (``<remap>``, ``-r`` in ``ros_args``). A parameters file
that cannot be read is left out: the process itself fails on it, and the capture says so.

:func:`missing_path` says whether a parameter value points at a file that is not there, on this
machine, now (``model.portable.resolve``: absolute paths, ``file://``, ``package://``, the
``$(find-pkg-share)`` and ``$(env HOME)`` tokens, devices), and whose file it is: an installed
package's (inside an ament prefix), the machine's (outside every prefix) or a device.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from pathlib import Path

from ..compare.launch_given import Given, GivenParameter, MissingFile, MissingPath, ParamsFile, sections
from ..errors import InputError
from ..launch.result import ComponentLoad, LaunchedNode
from ..model import portable, untrusted
from ..model.paths import shown
from ..run.ros_env import package_shares


def given(node: LaunchedNode) -> Given:
    """The settings ``node``'s launch file gives it."""
    where = str(node.where)
    parameters: list[GivenParameter] = []
    files: list[ParamsFile] = []
    remappings = list(node.remappings)
    for parameter in node.parameters:
        if parameter.name is not None:  # a <set_parameter> names its own line
            parameters.append(GivenParameter(parameter.name, str(parameter.where or where)))
        elif parameter.file is not None:
            files += _file(parameter.file, None)
        elif parameter.file_text is not None:
            files += _file(None, parameter.file_text, f"the parameters given at {where}")
    words = list(node.ros_arguments)
    for flag, value in zip(words, words[1:], strict=False):
        if flag in ("-p", "--param") and ":=" in value:
            parameters.append(GivenParameter(value.split(":=", 1)[0], f"{where} (ros_args)"))
        elif flag in ("-r", "--remap") and ":=" in value:
            source, target = value.split(":=", 1)
            remappings.append((source, target))
        elif flag == "--params-file":
            files += _file(Path(value), None)
    return Given(parameters=tuple(parameters), files=tuple(files), remappings=tuple(remappings), where=where)


def component_given(load: ComponentLoad) -> Given:
    """The parameters a component's LoadNode request gives it (parameters files already expanded
    into parameters by launch_ros, so each is named where the component is loaded), judged by
    PARAM_NOT_DECLARED, and its own remappings (not the scope's), judged by REMAP_UNUSED against
    the component's node alone."""
    where = str(load.where)
    return Given(parameters=tuple(GivenParameter(name, where) for name, _, _ in load.parameters),
                 remappings=load.own_remappings, where=where)


def _file(path: Path | None, text: str | None, name: str | None = None) -> list[ParamsFile]:
    try:
        if path is not None:
            found = path.stat()  # the file as it is now: an edit between two checks is read again
            parsed = _sections_of_file(str(path), found.st_size, found.st_mtime_ns)
        else:
            parsed = _sections_of_text(text or "")
    except (OSError, InputError):
        return []
    if parsed is None:
        return []
    label = name or (shown(path) if path is not None else "parameters")
    return [ParamsFile(label, parsed)]


# One parse per parameters file (or inline text) and check: every process a launch file gives the
# same file (Nav2's one nav2_params.yaml for nine processes) shares it; parsing it anew for each
# was most of the system rules' time (issue 37: they may add at most 5 % to a system check).
def forget_parsed_files() -> None:
    """Parse every parameters file anew (for measurements: what one check pays)."""
    _sections_of_file.cache_clear()
    _sections_of_text.cache_clear()


@functools.lru_cache(maxsize=256)
def _sections_of_file(path: str, size: int, mtime_ns: int) -> tuple[tuple[str, tuple[str, ...]], ...] | None:
    del size, mtime_ns  # part of the key only
    return _sections_of_text(untrusted.read_text(Path(path)))


@functools.lru_cache(maxsize=256)
def _sections_of_text(text: str) -> tuple[tuple[str, tuple[str, ...]], ...] | None:
    root = untrusted.compose_yaml(text)
    if root is None:
        return None
    untrusted.check_tree(root)
    return sections(untrusted.construct(root))


def missing_path(prefixes: Sequence[Path], home: str | None = None) -> MissingPath:
    """A ``compare.launch_given.MissingPath`` that finds packages in the ament ``prefixes`` and
    ``$(env HOME)`` in ``home`` (default: this user's)."""
    shares = {package: Path(share) for share, package in package_shares(prefixes).items()}
    roots = [Path(p).absolute() for p in prefixes]

    def why_missing(value: str) -> MissingFile | None:
        found = portable.resolve(value, shares.get, home)
        if found is None:
            return None
        if found.path is None:
            return MissingFile(f"package {found.package}, which is not installed (not in the ament index)", "package")
        if found.path.exists():
            return None
        if found.device:
            return MissingFile(f"the device {found.path}, which this machine does not have", "device")
        inside = found.package is not None or any(found.path.is_relative_to(root) for root in roots)
        return MissingFile(f"{shown(found.path)}, which does not exist", "package" if inside else "machine")

    return why_missing
