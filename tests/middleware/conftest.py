"""Fixtures for the middleware's own tests: build the library (and its gtests) once, run
real ROS 2 nodes on it and read their captures."""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
from pathlib import Path
from typing import Any

import pytest
import rmwi_helpers as h
from build_identity import prefix_identity, toolchain_identity
from source_trees import tree_hash

from pytest_rmw_introspect.run import middleware

REPO = Path(__file__).resolve().parents[2]
SOURCES = REPO / "rmw_introspect_cpp"


def _build_key(root: Path) -> str:
    """A cache key for a build of ``root`` against this environment's ROS prefixes: its sources,
    what the prefixes hold (a Jazzy venv, a Kilted venv, a sourced install) and the toolchain,
    not where they are. Two environments never reuse, or reconfigure, each other's build, and a
    fresh clone's new venv of the same lock reuses the build of the clone before it (issue 48):
    the binaries find the current venv's libraries through ``LD_LIBRARY_PATH``
    (``h.ros_environment``), which is searched before the run path they were linked with."""
    keyed = [tree_hash(root), *(prefix_identity(p) for p in h.ament_prefixes()), toolchain_identity()]
    return hashlib.sha256("\0".join(keyed).encode()).hexdigest()[:16]


def _building(dest: Path) -> Any:
    """A lock held while ``dest`` is checked and built: xdist workers each set up their session
    fixtures, and two that build the same directory at once undo each other's build (one removes
    the tree the other is building; seen as a failed C node build in a fresh clone's CI run)."""
    from filelock import FileLock

    dest.parent.mkdir(parents=True, exist_ok=True)
    return FileLock(str(dest) + ".lock")


def _cmake_build(src: Path, build_dir: Path, *extra: str) -> None:
    """Configure and build with CMake against the ROS prefix(es) of this environment."""
    env = h.ros_environment()
    log = build_dir.parent / (build_dir.name + ".log")
    build_dir.parent.mkdir(parents=True, exist_ok=True)
    with log.open("w") as out:
        for cmd in (
            ["cmake", "-S", str(src), "-B", str(build_dir), f"-DCMAKE_PREFIX_PATH={h.ament_prefix_path()}", *extra],
            ["cmake", "--build", str(build_dir), "-j", str(os.cpu_count() or 2)],
        ):
            out.write("$ " + " ".join(cmd) + "\n")
            out.flush()
            if subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT, env=env).returncode != 0:
                tail = "\n".join(log.read_text(errors="replace").splitlines()[-40:])
                pytest.fail(f"build of {src} failed (log {log}):\n{tail}", pytrace=False)


@pytest.fixture(scope="session")
def gtest_build_dir() -> Path:
    """The package built with BUILD_TESTING=ON (cached by its sources and ROS prefix)."""
    dest = middleware.cache_root() / f"gtest-{_build_key(SOURCES)}"
    stamp = dest / "complete"
    with _building(dest):
        if not stamp.exists():
            shutil.rmtree(dest, ignore_errors=True)
            _cmake_build(SOURCES, dest / "build", "-DCMAKE_BUILD_TYPE=RelWithDebInfo", "-DBUILD_TESTING=ON")
            stamp.write_text("ok\n")
    return dest / "build"


@pytest.fixture(scope="session")
def c_node(tmp_path_factory) -> Path:
    """The compiled rcl C node (no Python interpreter in the process)."""
    src = Path(__file__).parent / "c_node"
    dest = middleware.cache_root() / f"c_node-{_build_key(src)}"
    exe = dest / "build" / "rmwi_c_node"
    stamp = dest / "complete"
    with _building(dest):
        if not stamp.exists():
            shutil.rmtree(dest, ignore_errors=True)
            import sysconfig

            _cmake_build(
                src, dest / "build", "-DCMAKE_BUILD_TYPE=Release",
                f"-DPYTHON_LIBDIR={sysconfig.get_config_var('LIBDIR')}",
                f"-DPYTHON_LIBRARY_NAME=python{sysconfig.get_config_var('LDVERSION')}",
            )
            stamp.write_text("ok\n")
    return exe


@pytest.fixture
def run(middleware_library, tmp_path):
    """run(argv, **options) -> h.Run: spawn a process on the recording middleware."""

    def _run(argv, **kwargs):
        return h.run_on_middleware(middleware_library, argv, tmp_path, **kwargs)

    return _run
