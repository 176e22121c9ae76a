"""A hash of a source tree's files, keying the builds the tests cache (pytest's ``pythonpath``
puts this directory on ``sys.path``)."""

from __future__ import annotations

import hashlib
from pathlib import Path


def tree_hash(root: Path, exclude: tuple[str, ...] = ()) -> str:
    """``exclude``: top-level entries of ``root`` that the build does not read (e.g. ``contracts``)."""
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*")):
        if path.is_file() and "__pycache__" not in path.parts and path.relative_to(root).parts[0] not in exclude:
            digest.update(str(path.relative_to(root)).encode() + b"\0" + path.read_bytes())
    return digest.hexdigest()[:16]
