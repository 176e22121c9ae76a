"""What a set-up makes of a capture, with real processes: a damaged middleware library (issue
50, N29), a cache it cannot be built in (N28), a library whose path holds a space (N16), a
program that creates no node."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from pytest_rmw_introspect.errors import NoNodeCreated, TargetExited
from pytest_rmw_introspect.run import middleware, runner
from pytest_rmw_introspect.run.target import TargetSpec

NODES = Path(__file__).parent / "nodes"
TALKER = NODES / "talker.py"


def _damaged_copy(library: Path, where: Path) -> Path:
    """The first 100 bytes of ``library`` (a library cut short: ld.so "cannot read file data")."""
    where.mkdir(parents=True, exist_ok=True)
    damaged = where / library.name
    damaged.write_bytes(library.read_bytes()[:100])
    return damaged


def test_a_target_run_on_a_damaged_library_is_told_to_delete_it(middleware_library, tmp_path):
    """Issue 50, N29: the loader skips a damaged library, rcl finds another middleware and exits
    with status 102; the error named neither the library nor what to do."""
    damaged = _damaged_copy(middleware_library, tmp_path / "cache")
    with pytest.raises(TargetExited) as exited:
        runner.run(TargetSpec(script=TALKER, timeout=20, cold_start=True), library=damaged)
    message = str(exited.value)
    assert f"could not load the recording middleware {damaged} (cannot read file data)" in message
    assert "delete it" in message and "RMW_INTROSPECT_LIBRARY" in message


def test_the_capture_command_refuses_a_damaged_library_before_it_runs_anything(middleware_library, tmp_path):
    damaged = _damaged_copy(middleware_library, tmp_path / "cache")
    env = dict(os.environ, RMW_INTROSPECT_LIBRARY=str(damaged))
    done = subprocess.run([sys.executable, "-m", "pytest_rmw_introspect", "capture", "--", sys.executable, str(TALKER)],
                          capture_output=True, text=True, env=env, timeout=120)
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert f"The recording middleware library {damaged} (environment) is damaged: it is truncated" in done.stderr


def test_the_capture_command_with_a_cache_path_that_is_a_file_exits_2_with_the_reason(tmp_path, monkeypatch):
    """Issue 50, N28 as the user met it: `capture` with RMW_INTROSPECT_CACHE naming a file, where
    the middleware is built in the cache (not installed, not prebuilt)."""
    monkeypatch.delenv("RMW_INTROSPECT_LIBRARY", raising=False)
    if middleware.resolve_library().origin != "built":
        pytest.skip("the middleware is not built in the cache here: no cache is written")
    a_file = tmp_path / "cache"
    a_file.write_text("")
    env = {k: v for k, v in os.environ.items() if k != "RMW_INTROSPECT_LIBRARY"}
    env["RMW_INTROSPECT_CACHE"] = str(a_file)
    done = subprocess.run([sys.executable, "-m", "pytest_rmw_introspect", "capture", "--", "true"],
                          capture_output=True, text=True, env=env, timeout=120)
    assert done.returncode == 2, done.stderr
    assert "Traceback" not in done.stderr
    assert f"{a_file} is a file, not a directory" in done.stderr and "RMW_INTROSPECT_CACHE" in done.stderr


def test_the_capture_command_works_with_a_library_whose_path_holds_a_space(middleware_library, tmp_path):
    """Issue 50, N16: the loader splits LD_PRELOAD at spaces, so the prebuilt wheel in a venv whose
    path has a space captured nothing (and the message did not say why)."""
    spaced = tmp_path / "My Projects" / "venv lib" / middleware_library.name
    spaced.parent.mkdir(parents=True)
    shutil.copy2(middleware_library, spaced)
    env = dict(os.environ, RMW_INTROSPECT_LIBRARY=str(spaced))
    done = subprocess.run([sys.executable, "-m", "pytest_rmw_introspect", "capture", "--cold-start", "--script",
                           str(TALKER)], capture_output=True, text=True, env=env, timeout=120)
    assert done.returncode == 0, done.stderr
    assert "/talker:" in done.stdout and "/chatter" in done.stdout


@pytest.mark.parametrize(("target", "asked"), [
    # a compiled program (an ELF executable): not told to check rclpy.init()
    ({"command": ["true"]}, "does it call rclcpp::init() (rcl_init in C), create a node and spin"),
    ({"script": "exits.py"}, "does it call rclpy.init(), create a Node and spin"),
    ({"command": ["./exits.sh"]}, "does it initialise ROS 2 (rclpy.init() in Python, rclcpp::init() in C++)"),
])
def test_a_program_that_creates_no_node_is_asked_about_its_own_init(middleware_library, tmp_path, target, asked):
    """Issue 50: a capture of a program that creates no node told a C++ program to check `rclpy.init()`."""
    (tmp_path / "exits.py").write_text("print('no node')\n")
    (tmp_path / "exits.sh").write_text("#!/bin/sh\nexit 0\n")
    (tmp_path / "exits.sh").chmod(0o755)
    spec = TargetSpec.from_mapping({**target, "cwd": str(tmp_path), "timeout": 20, "cold_start": True},
                                   base_dir=tmp_path)
    with pytest.raises(NoNodeCreated) as none:
        runner.run(spec, library=middleware_library)
    assert asked in str(none.value)
    if target == {"command": ["true"]}:
        assert "rclpy" not in str(none.value)
