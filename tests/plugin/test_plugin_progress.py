"""What a user sees while the middleware is built (issue 40, item 2): a forced build (a fresh
RMW_INTROSPECT_CACHE, no prebuilt library in this source checkout) under `pytest -n 2` says once
that it starts, why, where its log is, how far it got and when it ended; a second pytest session
and an `rmw-introspect capture` started meanwhile each say that they wait for it, and when the
wait ended. One real build (45-60 s on a quiet 2-core machine) for all three."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

#: a real build, minutes on a loaded machine: the slow tier (once in .ci/run, not in every tier run)
pytestmark = [pytest.mark.slow, pytest.mark.timeout(1200)]

NODES = Path(__file__).parent / "nodes"

TESTS = f"""
import pytest

@pytest.mark.parametrize("ns", ["/one", "/two"])
def test_capture(ns, rmw_capture):
    assert rmw_capture(script={str(NODES / "talker.py")!r}, namespace=ns).node_names == [ns + "/talker"]
"""


def _start(cmd: list[str], cwd: Path, env: dict[str, str], output: Path) -> subprocess.Popen[bytes]:
    with output.open("wb") as out:
        return subprocess.Popen(cmd, cwd=cwd, env=env, stdout=out, stderr=subprocess.STDOUT)


def _wait_for(pattern: str, where: Path, timeout: float) -> Path:
    deadline = time.monotonic() + timeout
    while not (found := sorted(where.glob(pattern))):
        assert time.monotonic() < deadline, f"no {pattern} in {where} after {timeout} s"
        time.sleep(0.1)
    return found[0]


def test_a_build_and_the_processes_waiting_for_it_say_what_they_do(pytester: pytest.Pytester, tmp_path: Path):
    cache = tmp_path / "fresh-cache"
    env = {k: v for k, v in os.environ.items() if k not in ("RMW_INTROSPECT_LIBRARY", "PYTEST_ADDOPTS", "CI")
           and not k.startswith("PYTEST_XDIST")}
    env["RMW_INTROSPECT_CACHE"] = str(cache)
    pytester.makeini("[pytest]\n")
    pytester.makepyfile(test_progress=TESTS)
    pytest_cmd = [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-p", "no:randomly", "test_progress.py"]
    cli = shutil.which("rmw-introspect", path=str(Path(sys.executable).parent))
    assert cli

    builder = _start([*pytest_cmd, "-n", "2"], pytester.path, env, tmp_path / "xdist.out")
    _wait_for("jazzy-*.lock.pid", cache, timeout=120)  # one of its workers builds
    waiting_session = _start(pytest_cmd, pytester.path, env, tmp_path / "session.out")
    waiting_cli = _start([cli, "capture", "--format", "json", "--script", str(NODES / "talker.py")], pytester.path, env,
                         tmp_path / "cli.out")
    for process in (builder, waiting_session, waiting_cli):
        process.wait(timeout=900)
    xdist, session, capture = ((tmp_path / name).read_text() for name in ("xdist.out", "session.out", "cli.out"))
    (log,) = cache.glob("jazzy-*/build.log")

    # the building session, under xdist: once, though both workers need the library
    assert builder.returncode == 0, xdist
    assert "2 passed" in xdist
    starts = re.findall(r"^rmw-introspect: building the recording middleware for ROS 2 jazzy \((.*)\); once per source "
                        r"version, usually [^;]*; log: (.*)$", xdist, re.M)
    assert len(starts) == 1, xdist
    assert starts[0][0].startswith("no prebuilt middleware in this installation: a source checkout")
    assert starts[0][1] == str(log)
    assert re.search(r"^rmw-introspect: building the middleware: compile \d+%, \d+ s so far$", xdist, re.M), xdist
    assert len(re.findall(r"^rmw-introspect: built the recording middleware in \d+(\.\d)? s$", xdist, re.M)) == 1, xdist
    assert "waiting for another process" not in xdist  # the worker that waited for its sibling said nothing

    # a second pytest session and the command line wait for it, and say so once each
    for output, process, result in ((session, waiting_session, "2 passed"), (capture, waiting_cli, '"/talker"')):
        assert process.returncode == 0, output
        assert result in output
        waits = re.findall(r"^rmw-introspect: waiting for another process \(pid \d+\) that builds the recording "
                           r"middleware for ROS 2 jazzy; its log: (.*)$", output, re.M)
        assert waits == [str(log)], output
        assert len(re.findall(r"^rmw-introspect: the other process's middleware build ended after \d+(\.\d)? s of waiting$",
                              output, re.M)) == 1, output
        assert "building the recording middleware" not in output
