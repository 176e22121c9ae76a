"""Fixtures of the command-line tests: the `rmw-introspect` console script run as a subprocess
against the real rclpy node scripts of tests/plugin/nodes on the real recording middleware."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import textwrap
from dataclasses import dataclass
from pathlib import Path

import pytest

from pytest_rmw_introspect.errors import SetupError


@pytest.fixture(scope="session")
def middleware_library() -> Path:
    """The middleware library, built once; the CLI processes reuse it (RMW_INTROSPECT_LIBRARY)."""
    from pytest_rmw_introspect.run import middleware

    try:
        return Path(middleware.ensure_library())
    except SetupError as exc:
        pytest.fail(str(exc), pytrace=False)


@dataclass
class Result:
    returncode: int
    stdout: str
    stderr: str

    def __str__(self) -> str:
        return f"exit {self.returncode}\n--- stdout\n{self.stdout}\n--- stderr\n{self.stderr}"


def console_script() -> str:
    found = shutil.which("rmw-introspect", path=str(Path(sys.executable).parent))
    assert found, f"the rmw-introspect console script is not installed next to {sys.executable}"
    return found


class Cli:
    """Runs `rmw-introspect ARGS` in ``cwd`` (default: the test's tmp_path)."""

    def __init__(self, tmp_path: Path, env: dict[str, str]) -> None:
        self.path = tmp_path
        self.env = env

    def __call__(self, *args: str, cwd: Path | None = None, env: dict[str, str] | None = None,
                 module: bool = False, timeout: float = 60) -> Result:
        exe = [sys.executable, "-m", "pytest_rmw_introspect"] if module else [console_script()]
        proc = subprocess.run([*exe, *map(str, args)], cwd=cwd or self.path, env={**self.env, **(env or {})},
                              capture_output=True, text=True, timeout=timeout, check=False)
        return Result(proc.returncode, proc.stdout, proc.stderr)

    def write(self, relpath: str, text: str) -> Path:
        path = self.path / relpath
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(textwrap.dedent(text))
        return path

    def read(self, relpath: str) -> str:
        return (self.path / relpath).read_text()


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
