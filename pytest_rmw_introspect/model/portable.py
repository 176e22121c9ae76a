"""Parameter values written portably: a package's install location as a token.

A node that takes a file from its package gets a value like
``/home/ci/ws/install/my_robot/share/my_robot/maps/office.yaml``; a golden recorded on one
machine would drift on every other one. :func:`portable_value` writes the package's share
directory as ``$(find-pkg-share my_robot)`` (the launch substitution that finds it), so the
recorded value is ``$(find-pkg-share my_robot)/maps/office.yaml`` everywhere, and
:func:`resolve` turns the token (and ``package://``, ``file://``) back into a path on this machine.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

TOKEN = "$(find-pkg-share {package})"
_TOKEN = re.compile(r"^\$\(find-pkg-share ([A-Za-z0-9_]+)\)(.*)$")
_PACKAGE_URL = re.compile(r"^package://([A-Za-z0-9_]+)(/.*)?$")


def portable_value(value: Any, shares: Mapping[str, str]) -> Any:
    """``value`` (a string, or a list of them) with every package share directory of ``shares``
    (share directory → package) written as the ``$(find-pkg-share PACKAGE)`` token."""
    if isinstance(value, str):
        return _portable_text(value, shares)
    if isinstance(value, list):
        return [_portable_text(v, shares) if isinstance(v, str) else v for v in value]
    return value


def _portable_text(text: str, shares: Mapping[str, str]) -> str:
    if "/share/" not in text:
        return text
    for share in sorted(shares, key=len, reverse=True):  # the longest (most specific) first
        if share in text:
            token = TOKEN.format(package=shares[share]).replace("\\", "\\\\")
            text = re.sub(re.escape(share) + r"(?=/|$|[^\w.-])", token, text)
    return text


def resolve(text: str, find_share: Callable[[str], Path | None]) -> tuple[Path | None, str | None] | None:
    """The file a parameter value points at, and the package it names: an absolute path whose
    top directory exists (``/opt/maps/a.yaml``; ``/robot1/scan`` is a name, not a path),
    ``file://``, ``package://PACKAGE/...`` or the ``$(find-pkg-share PACKAGE)`` token
    (``find_share``: the share directory of a package, None when it is not installed). None: not
    a path. The path is None when the package is not installed."""
    if not text or any(c.isspace() for c in text.replace("$(find-pkg-share ", "", 1)):
        return None
    for pattern in (_TOKEN, _PACKAGE_URL):
        match = pattern.match(text)
        if match:
            share = find_share(match.group(1))
            rest = (match.group(2) or "").lstrip("/")
            return (share / rest if rest else share) if share is not None else None, match.group(1)
    if text.startswith("file://"):
        return Path(text[len("file://"):]), None
    if text.startswith("/") and len(text) > 1:
        top = text.split("/")[1]
        if top and Path("/" + top).is_dir() and Path("/" + top) != Path(text):
            return Path(text), None
    return None
