"""What a cached C/C++ build is built from, independent of where: the ROS 2 prefix's content and
the toolchain. A fresh clone's new venv of the same lock names the same build, so it reuses the
build instead of redoing it (issue 48 item 5). Used by the middleware tests' gtest and C node
builds (tests/middleware/conftest.py) and by the conformance suite's (scripts/conformance/run.py).
"""

from __future__ import annotations

import hashlib
import subprocess
from pathlib import Path


def prefix_identity(prefix: Path) -> str:
    """A venv of the ROS 2 wheels by its wheels (name-version: every venv made from the same lock
    has the same ones, wherever it is) and its Python; another prefix (a sourced install, an
    overlay) by its path and its rmw package version."""
    wheels = sorted(p.name for p in prefix.glob("lib/python3*/site-packages/ros_*.dist-info"))
    if wheels:
        pythons = sorted(p.name for p in prefix.glob("lib/python3*"))
        return "\n".join([*pythons, *wheels])
    package_xml = prefix / "share" / "rmw" / "package.xml"
    return f"{prefix.resolve()}\n" + (hashlib.sha256(package_xml.read_bytes()).hexdigest()
                                       if package_xml.is_file() else "")


def first_line(cmd: list[str]) -> str:
    """The first line ``cmd`` prints ("" when it cannot run): a tool's version."""
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, timeout=60).stdout
    except (OSError, subprocess.TimeoutExpired):
        return ""
    return (out.splitlines() or [""])[0]


def toolchain_identity() -> str:
    """The C++ compiler's and CMake's versions."""
    return first_line(["c++", "--version"]) + "\n" + first_line(["cmake", "--version"])
