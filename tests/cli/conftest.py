"""Fixtures of the command-line tests: the `rmw-introspect` console script run as a subprocess
against the real rclpy node scripts of tests/plugin/nodes on the real recording middleware."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from cli_helpers import Cli


@pytest.fixture
def cli(tmp_path: Path, middleware_library: Path) -> Cli:
    env = dict(os.environ)
    env["RMW_INTROSPECT_LIBRARY"] = str(middleware_library)
    for name in ("CI", "PYTEST_ADDOPTS"):
        env.pop(name, None)
    return Cli(tmp_path, env)


@pytest.fixture
def cli_nodes_only(tmp_path: Path) -> Cli:
    """For commands that run nothing (diff, compat, usage errors): no middleware needed."""
    env = {k: v for k, v in os.environ.items() if k not in ("CI", "PYTEST_ADDOPTS")}
    return Cli(tmp_path, env)
