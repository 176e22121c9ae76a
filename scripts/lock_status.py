#!/usr/bin/env python3
"""How a virtual environment differs from a lock file (`scripts/bootstrap.sh` asks it).

Usage: ``python scripts/lock_status.py LOCK [--ignore NAME ...] [--require NAME ...]``, run with
the venv's Python.
Prints one line per difference and exits 1 when there is any, 0 when the installed set is the
lock's exactly:

    missing NAME==VERSION       in the lock, not installed
    differs NAME INSTALLED -> LOCKED
    extra NAME==VERSION          installed by pip or uv, not in the lock (to uninstall)

Only distributions an installer recorded itself for (an ``INSTALLER`` file: pip, uv) count as
extra: what CMake installed into the venv (the example package's egg-info) is not pip's to
remove. ``--ignore`` names distributions that are not in the lock on purpose; ``--require``
names those that must be installed although the lock does not pin them (the project itself,
installed editable on top of it: ``missing NAME``).

No dependency beyond the standard library: it runs before anything is installed.
"""

from __future__ import annotations

import argparse
import re
import sys
from importlib import metadata
from pathlib import Path

#: ``name==version`` at the start of a line of a pip requirements file written by a locker
_PIN = re.compile(r"^([A-Za-z0-9][A-Za-z0-9._-]*)(?:\[[^\]]*\])?==([^\s;\\]+)")


def normalize(name: str) -> str:
    """A distribution name as PEP 503 compares them (``Foo_Bar`` is ``foo-bar``)."""
    return re.sub(r"[-_.]+", "-", name).lower()


def read_lock(path: Path) -> dict[str, str]:
    """Normalized name → pinned version, for every ``name==version`` line of the lock."""
    pins: dict[str, str] = {}
    for line in path.read_text(encoding="utf-8").splitlines():
        match = _PIN.match(line)
        if match:
            pins[normalize(match.group(1))] = match.group(2)
    if not pins:
        raise ValueError(f"{path} pins no package (expected lines like `name==1.2.3`): is it a lock file?")
    return pins


def installed(paths: list[str] | None = None) -> dict[str, tuple[str, bool]]:
    """Normalized name → (version, recorded by an installer) for the distributions on ``paths``
    (default: this interpreter's ``sys.path``)."""
    found: dict[str, tuple[str, bool]] = {}
    for dist in metadata.distributions(path=paths if paths is not None else sys.path):
        name = dist.metadata["Name"]
        if not name or normalize(name) in found:  # the first on the path is the one imported
            continue
        by_installer = bool((dist.read_text("INSTALLER") or "").strip())
        found[normalize(name)] = (dist.version, by_installer)
    return found


def differences(lock: dict[str, str], present: dict[str, tuple[str, bool]], ignore: set[str],
                require: set[str] | None = None) -> list[str]:
    """The lines :func:`main` prints, sorted by name."""
    require = require or set()
    lines: list[tuple[str, str]] = [(name, f"missing {name}") for name in require if name not in present]
    ignore = ignore | require
    for name, version in lock.items():
        if name in ignore:
            continue
        if name not in present:
            lines.append((name, f"missing {name}=={version}"))
        elif present[name][0] != version:
            lines.append((name, f"differs {name} {present[name][0]} -> {version}"))
    for name, (version, by_installer) in present.items():
        if name not in lock and name not in ignore and by_installer:
            lines.append((name, f"extra {name}=={version}"))
    return [text for _name, text in sorted(lines)]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("lock", type=Path)
    parser.add_argument("--ignore", action="append", default=[], metavar="NAME")
    parser.add_argument("--require", action="append", default=[], metavar="NAME")
    args = parser.parse_args(argv)
    try:
        lock = read_lock(args.lock)
    except (OSError, ValueError) as exc:
        print(f"lock_status: {exc}", file=sys.stderr)
        return 2
    lines = differences(lock, installed(), {normalize(n) for n in args.ignore}, {normalize(n) for n in args.require})
    for line in lines:
        print(line)
    return 1 if lines else 0


if __name__ == "__main__":
    sys.exit(main())
