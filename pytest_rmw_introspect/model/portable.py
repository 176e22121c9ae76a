"""Parameter values written portably: a package's install location as a token.

A node that takes a file from its package gets a value like
``/home/ci/ws/install/my_robot/share/my_robot/maps/office.yaml``; a golden recorded on one
machine would drift on every other one. :func:`portable_value` writes the package's share
directory as ``$(find-pkg-share my_robot)`` (the launch substitution that finds it), so the
recorded value is ``$(find-pkg-share my_robot)/maps/office.yaml`` everywhere; the user's home
directory is written as ``$(env HOME)`` for the same reason (``/home/alice/.robot/route.csv`` on
the robot, ``/home/ci/...`` in CI). :func:`resolve` turns the tokens (and ``package://``,
``file://``, also around a token) back into a path on this machine, and tells a hardware device
(``/dev/ttyUSB0``, ``/dev/ttyACM0:57600``, ``serial:///dev/ttyACM0``) from a file.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

TOKEN = "$(find-pkg-share {package})"
HOME_TOKEN = "$(env HOME)"
_TOKEN = re.compile(r"^\$\(find-pkg-share ([A-Za-z0-9_]+)\)(.*)$")
_PACKAGE_URL = re.compile(r"^package://([A-Za-z0-9_]+)(/.*)?$")
#: a device file, with the ``:57600`` baud rate suffix drivers such as MAVROS take
_DEVICE = re.compile(r"^/dev/([^:]+)(:\d+)?$")
#: URLs of hardware links (MAVROS's ``fcu_url``, serial bridges): ``serial://``, ``serial-hwfc://``
_SERIAL_URL = re.compile(r"^serial(?:-hwfc)?://(/dev/[^:?]+)")
_NETWORK_URL = re.compile(r"^(?:udp|tcp)(?:-[a-z]+)?://")
#: a device path anywhere in a text (an error message, a parameters file)
_DEVICE_IN_TEXT = re.compile(r"(?<![\w/])/dev/(?:[A-Za-z0-9_.+-]+/)*[A-Za-z0-9_.+-]+")


def device_paths_in(text: str) -> list[str]:
    """Every ``/dev/...`` path written in ``text``, in order."""
    return _DEVICE_IN_TEXT.findall(text)


def portable_value(value: Any, shares: Mapping[str, str], home: str | None = None) -> Any:
    """``value`` (a string, or a list of them) with every package share directory of ``shares``
    (share directory → package) written as the ``$(find-pkg-share PACKAGE)`` token, and the
    home directory ``home`` as ``$(env HOME)``."""
    if isinstance(value, str):
        return _portable_text(value, shares, home)
    if isinstance(value, list):
        return [_portable_text(v, shares, home) if isinstance(v, str) else v for v in value]
    return value


def _portable_text(text: str, shares: Mapping[str, str], home: str | None) -> str:
    if "/share/" in text:
        for share in sorted(shares, key=len, reverse=True):  # the longest (most specific) first
            if share in text:
                token = TOKEN.format(package=shares[share]).replace("\\", "\\\\")
                text = re.sub(re.escape(share) + r"(?=/|$|[^\w.-])", token, text)
    home = (home or "").rstrip("/")
    if len(home) > 1:  # never "/" itself
        for prefix in ("", "file://"):
            if text == prefix + home or text.startswith(prefix + home + "/"):
                return prefix + HOME_TOKEN + text[len(prefix + home):]
    return text


@dataclass(frozen=True)
class Located:
    """What a parameter value points at: a file (``path``; None when ``package`` is not
    installed), or a hardware ``device``."""

    path: Path | None
    package: str | None = None
    device: bool = False


def resolve(text: str, find_share: Callable[[str], Path | None], home: str | None = None) -> Located | None:
    """What a parameter value points at: a hardware device (``/dev/ttyUSB0``, with or without a
    ``:57600`` suffix, ``serial:///dev/ttyACM0:57600``: the device file), or a file: an absolute
    path whose top directory exists (``/opt/maps/a.yaml``; ``/robot1/scan`` is a name, not a
    path), ``file://`` (around any of the others), ``package://PACKAGE/...``, the
    ``$(find-pkg-share PACKAGE)`` token (``find_share``: the share directory of a package, None
    when it is not installed) or the ``$(env HOME)`` token (``home``). None: not a path, or a
    network link (``udp://``, ``tcp://``) that is no file at all."""
    if not text or any(c.isspace() for c in text.replace("$(find-pkg-share ", "", 1).replace(HOME_TOKEN, "", 1)):
        return None
    if text.startswith("file://"):
        # every file:// at once, not one call each: ~1,000 of them were a RecursionError (issue 50, N25)
        inner_text = text
        while inner_text.startswith("file://"):
            inner_text = inner_text[len("file://"):]
        inner = resolve(inner_text, find_share, home)
        return inner if inner is not None else Located(Path(inner_text))
    if _NETWORK_URL.match(text):
        return None
    serial = _SERIAL_URL.match(text)
    device = _DEVICE.match(serial.group(1) if serial else text)
    if device:
        return Located(Path("/dev") / device.group(1), device=True)
    for pattern in (_TOKEN, _PACKAGE_URL):
        match = pattern.match(text)
        if match:
            share = find_share(match.group(1))
            rest = (match.group(2) or "").lstrip("/")
            return Located((share / rest if rest else share) if share is not None else None, match.group(1))
    if text == HOME_TOKEN or text.startswith(HOME_TOKEN + "/"):
        return Located((Path(home) if home else Path.home()) / text[len(HOME_TOKEN):].lstrip("/"))
    if text.startswith("/") and len(text) > 1:
        top = text.split("/")[1]
        if top and Path("/" + top).is_dir() and Path("/" + top) != Path(text):
            return Located(Path(text))
    return None
