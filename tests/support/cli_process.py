"""The `rmw-introspect` console script of this interpreter's venv run as a subprocess, and what it
returned: shared by the command-line tests (tests/cli) and the precision suite (tests/precision)."""

from __future__ import annotations

import shutil
import sys
from dataclasses import dataclass
from pathlib import Path


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
