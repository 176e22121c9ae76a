"""The type-hash lockfile of a package (``rmw-introspect lock``): the RIHS01 hash of every
interface type its contracts use, nested types included.

A contract pins the hash of each interface's own type; a change in a nested type from another
package (``std_msgs/msg/Header`` inside ``sensor_msgs/msg/Image``) changes that hash too, but
the hash cannot say which type changed. The lock records every type's own hash (``model.
type_hash`` computes the nested ones from the contracts' ``types:`` sections), so that ``check``
can name the type that changed and the path to it (``compare.type_lock``).

The file is JSON, sorted, so that locking the same types again changes no byte::

    {
      "format": "rmw_introspect_type_lock",
      "version": 1,
      "contracts": ["contracts/camera.interfaces.yaml"],      # relative to the lock file
      "types": {"builtin_interfaces/msg/Time": "RIHS01_b106...", "sensor_msgs/msg/Image": "RIHS01_d31d..."}
    }

It is found by :func:`find`: ``FILE_NAME`` in the contract's directory or a directory above it,
up to the package root (the first directory with a ``package.xml``, ``setup.py`` or
``pyproject.toml``) or the repository root (``.git``).
"""

from __future__ import annotations

import json
import os
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

from ..errors import TypeLockError, UnreadableFile
from . import type_hash, versioned_json
from .contract_shapes import ContractNode
from .types import ACTION_PART_SUFFIXES, TypeDescription, closure, interface_roots
from .vocabulary import ACTION_HASHED_PARTS, ACTION_LISTS, LISTS

FILE_NAME = "interfaces.lock.json"
FORMAT = "rmw_introspect_type_lock"
VERSION = 1
#: a directory holding one of these is a package (or repository) root: the search stops there
_ROOTS = ("package.xml", "setup.py", "pyproject.toml", ".git")
_HASH = re.compile(r"^RIHS01_[0-9a-f]{64}$")


@dataclass(frozen=True)
class TypeLock:
    """A loaded lock: type name → the hash it was locked at."""

    path: Path
    types: Mapping[str, str]
    contracts: tuple[str, ...] = ()


def recorded_hashes(nodes: Mapping[str, ContractNode]) -> dict[str, str]:
    """The hashes a contract's entries record (``type_hash``), by the type they belong to: an
    interface's own type, or for an action its three hashed parts (``pkg/action/X_SendGoal``, ...)."""
    suffix_of = dict(zip(ACTION_HASHED_PARTS, ACTION_PART_SUFFIXES, strict=True))
    out: dict[str, str] = {}
    for node in nodes.values():
        for list_name in LISTS:
            for entry in node.get(list_name) or ():
                recorded = entry.get("type_hash")
                if isinstance(recorded, str):
                    out[entry["type"]] = recorded
                elif isinstance(recorded, Mapping) and list_name in ACTION_LISTS:
                    for part, value in recorded.items():
                        if part in suffix_of and isinstance(value, str):
                            out[entry["type"] + suffix_of[part]] = value
    return out


def interface_types(nodes: Mapping[str, ContractNode]) -> list[str]:
    """The described types the interfaces of ``nodes`` stand for (``types.interface_roots``)."""
    roots: dict[str, None] = {}
    for node in nodes.values():
        for list_name in LISTS:
            for entry in node.get(list_name) or ():
                roots.update(dict.fromkeys(interface_roots(list_name, entry["type"])))
    return list(roots)


def current_hashes(nodes: Mapping[str, ContractNode], table: Mapping[str, TypeDescription]) -> dict[str, str]:
    """Every type the interfaces of ``nodes`` use, nested ones included, with its hash: the
    hashes the entries record, the others computed from ``table``."""
    computed = type_hash.message_hashes({name: table[name] for name in closure(table, interface_types(nodes))})
    return {**computed, **recorded_hashes(nodes)}


def locked_hashes(nodes: Mapping[str, ContractNode], table: Mapping[str, TypeDescription] | None, shown: str) -> dict[str, str]:
    """What a lock records for one contract (its ``nodes`` and ``types:`` section): every type
    its interfaces use, nested ones included, with its hash. Raises TypeLockError naming the
    contract when its ``types:`` section is missing or does not describe a type it needs."""
    fix = f"write it with `rmw-introspect check --update --include-types {shown}`, then lock again"
    if table is None:
        raise TypeLockError(shown, "the contract has no `types:` section, so its nested types are not known",
                            advice=f"To lock them, {fix}.", subject="cannot lock")
    hashes = current_hashes(nodes, table)
    for root in interface_types(nodes):
        reached = closure(table, [root])
        used = [root, *(r for n in reached for r in table[n].references())]
        missing = [t for t in used if t not in table and t not in hashes]
        if missing:
            raise TypeLockError(shown, f"the `types:` section does not describe {missing[0]} (used by {root})",
                                advice=f"To lock it, {fix}.", subject="cannot lock")
    return hashes


def render(types: Mapping[str, str], contracts: Iterable[Path], path: str | Path) -> str:
    """The lock file at ``path``: JSON, sorted (contracts relative to its directory)."""
    directory = Path(path).absolute().parent
    document = {
        "format": FORMAT,
        "version": VERSION,
        "contracts": sorted({Path(os.path.relpath(Path(c).absolute(), directory)).as_posix() for c in contracts}),
        "types": {name: types[name] for name in sorted(types)},
    }
    return json.dumps(document, indent=2) + "\n"


def load(path: str | Path) -> TypeLock:
    """Read a lock file (raises :class:`TypeLockError` naming the file and what to do)."""
    path = Path(path)
    try:
        document = versioned_json.read(path, file_format=FORMAT, version=VERSION, what="a type lock")
    except UnreadableFile as problem:
        raise TypeLockError(path, problem.reason) from None
    types = document.get("types")
    if not isinstance(types, dict):
        raise TypeLockError(path, "\"types\" is not a mapping of type names to RIHS01 hashes")
    for name, value in types.items():
        if not isinstance(value, str) or not _HASH.match(value):
            raise TypeLockError(path, f"the hash of {name} is {value!r}, not RIHS01_ and 64 lowercase hex digits")
    contracts = document.get("contracts") or []
    return TypeLock(path=path, types=dict(types), contracts=tuple(str(c) for c in contracts))


def find(contract: str | Path) -> Path | None:
    """The lock file that applies to ``contract``: ``FILE_NAME`` in its directory or above, up
    to the package or repository root (see the module docstring)."""
    directory = Path(contract).absolute().parent
    while True:
        candidate = directory / FILE_NAME
        if candidate.is_file():
            return candidate
        if any((directory / marker).exists() for marker in _ROOTS) or directory.parent == directory:
            return None
        directory = directory.parent
