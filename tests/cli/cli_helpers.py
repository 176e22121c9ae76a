"""Helpers shared by the command-line tests (imported by name: tests/cli is on sys.path)."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

from cli_process import Result, console_script

__all__ = ["NODES", "Cli", "Result", "console_script", "wait_for_file"]

NODES = Path(__file__).parent.parent / "plugin" / "nodes"
def wait_for_file(path: Path, timeout: float = 30.0) -> int:
    """Wait until ``path`` holds a number (a pid a test process wrote) and return it."""
    import time

    deadline = time.monotonic() + timeout
    while True:
        try:
            text = path.read_text().strip()
        except FileNotFoundError:
            text = ""
        if text.isdigit():
            return int(text)
        assert time.monotonic() < deadline, f"{path} was never written"
        time.sleep(0.05)


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
