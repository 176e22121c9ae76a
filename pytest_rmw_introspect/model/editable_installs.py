"""ament_python packages installed editable (``pip install -e .``): which distributions on the
Python path are, and the source tree each points at. It reads files only.

An editable install writes no ``share/`` and no ament index marker: setuptools (PEP 660) writes
``__editable__.<name>-<version>.pth`` (and a finder) into site-packages and records the source
tree in ``<name>-<version>.dist-info/direct_url.json`` (``{"url": "file:///src", "dir_info":
{"editable": true}}``); the legacy ``setup.py develop`` writes ``<name>.egg-link`` holding the
source path. ``data_files`` (``share/<pkg>/launch``, the index marker, ...) are not installed at
all. ``run.editable`` makes an ament prefix of each such source tree that has a ``package.xml``;
:func:`not_found_hint` is what a "not in the ament index" error adds.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import os
import re
import sys
import urllib.parse
from collections.abc import Sequence
from pathlib import Path

_NAME = re.compile(r"<name>\s*([^<\s]+)\s*</name>")


@dataclasses.dataclass(frozen=True)
class Editable:
    """A Python distribution installed editable: its name as pip knows it and its source tree."""

    distribution: str
    source: Path

    @property
    def package(self) -> str | None:
        """The ament package name of its package.xml (None: not an ament package)."""
        try:
            match = _NAME.search((self.source / "package.xml").read_text(errors="replace"))
        except OSError:
            return None
        return match.group(1) if match else None


def installs(path: Sequence[str] | None = None) -> list[Editable]:
    """The editable installs whose ``.pth`` / ``.egg-link`` files are in a directory of ``path``
    (default: ``sys.path``), in that order."""
    found: dict[Path, Editable] = {}
    for entry in sys.path if path is None else path:
        try:
            modified = os.stat(entry or ".").st_mtime_ns
        except OSError:
            continue
        for editable in _in_directory(entry or ".", modified):
            found.setdefault(editable.source, editable)
    return list(found.values())


@functools.lru_cache(maxsize=64)
def _in_directory(directory: str, modified: int) -> tuple[Editable, ...]:
    """The editable installs of one directory, listed again only when it changed (``modified``:
    its mtime; a site-packages directory of a ROS venv holds a thousand entries)."""
    try:
        names = sorted(name for name in os.listdir(directory) if name.endswith((".pth", ".egg-link")))
    except OSError:
        return ()
    return tuple(e for e in (_editable(Path(directory), name) for name in names) if e is not None)


def _editable(site: Path, name: str) -> Editable | None:
    if name.startswith("__editable__.") and name.endswith(".pth"):
        stem = name[len("__editable__."):-len(".pth")]  # <name>-<version>
        for info in [site / f"{stem}.dist-info", *sorted(site.glob(f"{stem.partition('-')[0]}-*.dist-info"))]:
            source = _direct_url_source(info / "direct_url.json")
            if source is not None:
                return Editable(stem.partition("-")[0], source)
        return None
    if name.endswith(".egg-link"):
        try:
            first = (site / name).read_text().splitlines()[0].strip()
        except (OSError, IndexError):
            return None
        return Editable(name[:-len(".egg-link")], Path(first)) if first and Path(first).is_dir() else None
    return None


def _direct_url_source(path: Path) -> Path | None:
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    url = data.get("url", "") if isinstance(data, dict) else ""
    if not (isinstance(data.get("dir_info"), dict) and data["dir_info"].get("editable")) or not url.startswith("file:"):
        return None
    source = Path(urllib.parse.unquote(urllib.parse.urlparse(url).path))
    return source if source.is_dir() else None


def find(package: str, path: Sequence[str] | None = None) -> Editable | None:
    """The editable install of the Python distribution named ``package`` (``-``/``_``/case
    ignored), if any: what to tell a user whose package was not found."""
    wanted = re.sub(r"[-_.]+", "-", package).lower()
    for editable in installs(path):
        if re.sub(r"[-_.]+", "-", editable.distribution).lower() == wanted or editable.package == package:
            return editable
    return None


def not_found_hint(package: str, path: Sequence[str] | None = None, *, if_absent: bool = True) -> str:
    """What to do when ``package`` is in no ament prefix: said from what an editable install of it
    is or lacks (with no editable install: how to make one, unless ``if_absent`` is false)."""
    editable = find(package, path)
    if editable is None:
        return "" if not if_absent else (f" An ament_python package developed in a venv is found through its source tree once it is "
                f"installed with `pip install -e <its source directory>` (its package.xml, and the data_files of "
                f"setup.py such as share/{package}/launch, are read from there).")
    if editable.package is None:
        return (f" '{package}' is installed with `pip install -e` from {editable.source}, which has no package.xml "
                f"with a <name>: add the package.xml of an ament_python package there (and in setup.py's data_files "
                f"`('share/ament_index/resource_index/packages', ['resource/{package}'])` and "
                f"`('share/{package}', ['package.xml'])`, so that colcon installs it too); the share files are then "
                f"read from the source tree.")
    return (f" '{editable.package}' is installed with `pip install -e` from {editable.source} (its package.xml says "
            f"'{editable.package}', not '{package}').") if editable.package != package else ""
