"""The slow tier (tests/conftest.py): the wheel of `make dist` (scripts/dist.py) built once per
session and installed, with the ROS 2 Jazzy wheels at the lock's versions, into a fresh venv
outside the repository, as a user's `pip install 'pytest-rmw-introspect[jazzy]'` installs it."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import pytest
from wheel_support import wheel_distros

ROOT = Path(__file__).resolve().parents[2]
#: names of the build tools a user without a compiler lacks: hidden from the fresh venv's PATH
BUILD_TOOLS = re.compile(r"^(cmake|ctest|cpack|make|gmake|ninja|cc|c\+\+|gcc|g\+\+|clang|clang\+\+|ld)(-[0-9.]+)?$"
                         r"|^x86_64-linux-gnu-(gcc|g\+\+|cpp|ld)(-[0-9.]+)?$")


@dataclass(frozen=True)
class InstalledWheel:
    wheel: Path
    venv: Path
    #: time.monotonic() when `pip install` of the wheel finished
    installed_at: float
    install_seconds: float
    #: PATH with the venv's bin/ and the system's tools, but no CMake, make or compiler
    path_without_compiler: str

    def bin(self, name: str) -> str:
        return str(self.venv / "bin" / name)

    def env(self, **extra: str) -> dict[str, str]:
        """The environment of a user of this venv who has no compiler (and a cache of their own), on
        their own machine: CI's variables are left out, since `--update-golden` refuses to write
        goldens where CI is set and these tests play the user's first hour, not a CI job."""
        env = {key: value for key, value in os.environ.items()
               if not key.startswith(("PYTEST_", "RMW_INTROSPECT", "AMENT_", "VIRTUAL_ENV", "_ROS_WHEELS", "LD_", "CXX", "CC",
                                      "GITHUB_", "GITLAB_"))
               and key not in {"PYTHONPATH", "COV_CORE_SOURCE", "CI"}}
        env.update(PATH=self.path_without_compiler, VIRTUAL_ENV=str(self.venv), **extra)
        return env


def _pins(lock: Path) -> str:
    """The lock's `name==version` lines (its hashes left out: a constraints file has none)."""
    return "\n".join(line.split()[0] for line in lock.read_text().splitlines() if re.match(r"^[A-Za-z0-9][^ ]*==", line)) + "\n"


def _path_without_build_tools(where: Path) -> str:
    """A directory of links to every program on PATH but the build tools (BUILD_TOOLS)."""
    where.mkdir()
    for directory in os.environ.get("PATH", "").split(os.pathsep):
        if not directory or ".venv" in directory:
            continue
        try:
            names = os.listdir(directory)
        except OSError:
            continue
        for name in names:
            source = Path(directory) / name
            if BUILD_TOOLS.match(name) or (where / name).exists() or not os.access(source, os.X_OK) or source.is_dir():
                continue
            (where / name).symlink_to(source)
    assert shutil.which("cmake", path=str(where)) is None and shutil.which("c++", path=str(where)) is None
    return str(where)


@pytest.fixture(scope="session")
def built_wheel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The Linux x86_64 wheel of scripts/dist.py, with the middleware prebuilt for Jazzy (and
    Kilted, where its venv is)."""
    out = tmp_path_factory.mktemp("dist")
    result = subprocess.run([sys.executable, str(ROOT / "scripts" / "dist.py"), "--out", str(out),
                             "--distros", ",".join(wheel_distros())],
                            cwd=ROOT, capture_output=True, text=True, timeout=900)
    assert result.returncode == 0, f"scripts/dist.py failed:\n{result.stdout}\n{result.stderr}"
    (wheel,) = out.glob("pytest_rmw_introspect-*manylinux*_x86_64.whl")
    return wheel


@pytest.fixture(scope="session")
def installed_wheel(built_wheel: Path, tmp_path_factory: pytest.TempPathFactory) -> InstalledWheel:
    """A fresh venv outside the repository with the built wheel installed as `<wheel>[jazzy]`,
    every package at the version of requirements/jazzy.txt (pip's cache makes that quick)."""
    home = tmp_path_factory.mktemp("user")
    assert not home.is_relative_to(ROOT)
    venv = home / "venv"
    subprocess.run([sys._base_executable, "-m", "venv", str(venv)], check=True, timeout=120)  # type: ignore[attr-defined]
    constraints = home / "constraints.txt"
    constraints.write_text(_pins(ROOT / "requirements" / "jazzy.txt"))
    path = f"{venv / 'bin'}:{_path_without_build_tools(home / 'bin-without-compiler')}"
    began = time.monotonic()
    result = subprocess.run([str(venv / "bin" / "python"), "-m", "pip", "install", "--disable-pip-version-check", "--quiet",
                             "--constraint", str(constraints), f"{built_wheel}[jazzy]"],
                            capture_output=True, text=True, timeout=1200, cwd=home)
    assert result.returncode == 0, f"pip install of the wheel failed:\n{result.stdout}\n{result.stderr}"
    installed_at = time.monotonic()
    return InstalledWheel(built_wheel, venv, installed_at, installed_at - began, path)
