"""What the slow tier's tests and fixtures share (imported by name: pytest puts tests/dist on sys.path)."""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

#: the ROS 2 Kilted venv of `make bootstrap DISTRO=kilted` (.ci/run makes it before the slow tier)
KILTED_VENV = ROOT / ".venv-kilted"


def wheel_distros() -> list[str]:
    """The distributions the test wheel is built for: Jazzy, and Kilted where its venv is."""
    return ["jazzy", "kilted"] if (KILTED_VENV / "bin" / "python").is_file() else ["jazzy"]
