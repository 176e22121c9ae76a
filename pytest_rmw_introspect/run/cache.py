"""Where the plugin keeps what it builds and makes: ``RMW_INTROSPECT_CACHE``, else
``$XDG_CACHE_HOME/pytest-rmw-introspect`` (``~/.cache/pytest-rmw-introspect``)."""

from __future__ import annotations

import os
from pathlib import Path


def cache_root() -> Path:
    explicit = os.environ.get("RMW_INTROSPECT_CACHE")
    if explicit:
        return Path(explicit)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "pytest-rmw-introspect"
