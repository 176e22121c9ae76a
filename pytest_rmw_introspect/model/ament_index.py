"""The ament index: ``<prefix>/share/ament_index/resource_index/<type>/<name>`` marks that an
install prefix provides ``name`` (a package for the type ``packages``, a NoDL document for
``nodl_desc``, ...). Prefixes are searched in ``AMENT_PREFIX_PATH`` order and the first that
provides a name wins, as ``ros2 run`` and ``$(find-pkg-share)`` do.

The one reader of the index: ``run`` (a target's package and executables, the installed
middleware, the share directories of ROS detection), ``launch`` (``$(find-pkg-*)``, ``ros2 launch
PACKAGE``) and ``model.nodl`` (``nodl://`` references) ask it. It reads files only. A package
installed with ``pip install -e .`` has no index entry; ``run.editable`` makes a prefix that has
one (``model.editable_installs`` finds such installs).
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path

#: the resource type that lists packages
PACKAGES = "packages"
#: where the index is inside a prefix
INDEX = Path("share", "ament_index", "resource_index")


def env_prefixes(environ: Mapping[str, str] | None = None) -> list[Path]:
    """The prefixes of ``AMENT_PREFIX_PATH`` in ``environ`` (default: this process's), in order,
    empty entries dropped."""
    value = (os.environ if environ is None else environ).get("AMENT_PREFIX_PATH", "")
    return [Path(p) for p in value.split(os.pathsep) if p]


def resource(prefix: str | Path, name: str, resource_type: str = PACKAGES) -> Path:
    """Where ``prefix`` registers ``name`` under ``resource_type`` (whether it does or not)."""
    return Path(prefix) / INDEX / resource_type / name


def providers(name: str, prefixes: Sequence[str | Path], resource_type: str = PACKAGES) -> list[Path]:
    """The prefixes that register ``name`` under ``resource_type``, in the order given."""
    return [Path(p) for p in prefixes if resource(p, name, resource_type).exists()]


def names(prefix: str | Path, resource_type: str = PACKAGES) -> list[str]:
    """Every name ``prefix`` registers under ``resource_type`` ([] when it has no such index)."""
    try:
        return [entry.name for entry in os.scandir(Path(prefix) / INDEX / resource_type)]
    except OSError:
        return []
