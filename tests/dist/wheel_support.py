"""What the slow tier's tests and fixtures share (imported by name: pytest puts tests/dist on sys.path)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _dist_script():
    """scripts/dist.py, which the wheel fixture runs: the venvs it builds each library with."""
    spec = importlib.util.spec_from_file_location("rmwi_dist_script", ROOT / "scripts" / "dist.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


#: the ROS 2 Kilted venv of `make bootstrap DISTRO=kilted` (Python 3.11's, else 3.12's: .ci/run's
#: kilted tier makes that one before the slow tier)
KILTED_VENV = _dist_script().venv_dir("kilted")


def wheel_distros() -> list[str]:
    """The distributions the test wheel is built for: Jazzy, and Kilted where its venv is."""
    return ["jazzy", "kilted"] if (KILTED_VENV / "bin" / "python").is_file() else ["jazzy"]
