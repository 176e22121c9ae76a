"""How paths are shown to people and written into files: the two rules, defined once."""

from __future__ import annotations

import os
from pathlib import Path


def shown(path: str | Path, base: str | Path | None = None) -> str:
    """``path`` for a message: relative to ``base`` (default: the current directory) unless
    that climbs three or more levels, then as given."""
    try:
        rel = os.path.relpath(path, base if base is not None else os.getcwd())
    except ValueError:
        return str(path)
    return str(path) if rel.startswith("../../..") else rel


def relative_or_absolute(path: Path, base: Path) -> str:
    """``path`` for a file written in ``base`` (a contract's ``target:`` block): relative to
    ``base``, or absolute when that would climb two or more levels (a relative path that far
    up breaks as soon as the file moves)."""
    try:
        rel = os.path.relpath(path, base)
    except ValueError:
        return str(path)
    return str(path.absolute()) if rel == "../.." or rel.startswith("../../") else rel
