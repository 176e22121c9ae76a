"""Captures back to back (issue 39): 200 `rmw-introspect capture` runs of the example talker,
interleaved with launch captures of the example robot and with runs killed (SIGKILL) at random
moments, as a CI that runs the tool all day would. None may take longer than its timeout plus
5 s, and nothing may be left running or holding a lock afterwards.

About two minutes on a quiet 2-core machine; RMWI_STRESS_CAPTURES sets the count (default 200),
RMWI_STRESS_SEED the random moments."""

from __future__ import annotations

import os
import random
import signal
import subprocess
import time
import uuid
from pathlib import Path

import pytest
from cli_helpers import console_script
from rmwi_processes import wait_gone

CAPTURES = int(os.environ.get("RMWI_STRESS_CAPTURES", "200"))
TIMEOUT_S = 20.0
MARGIN_S = 5.0
#: every KILL_EVERY-th capture is started and killed with SIGKILL at a random moment, every
#: LAUNCH_EVERY-th is followed by a launch capture
KILL_EVERY = 10
LAUNCH_EVERY = 25


def _marked_processes(mark: str) -> list[int]:
    """Processes of this user whose environment carries ``mark`` (every process of this test)."""
    pids = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            if mark.encode() in (entry / "environ").read_bytes():
                pids.append(int(entry.name))
        except OSError:
            continue
    return pids


def _lock_holders() -> set[int]:
    """The pids holding a file lock (flock, POSIX or OFD), from /proc/locks."""
    holders = set()
    for line in Path("/proc/locks").read_text().splitlines():
        fields = line.split()
        if len(fields) > 4 and fields[4].isdigit():
            holders.add(int(fields[4]))
    return holders


@pytest.mark.timeout(max(300, CAPTURES * 6))
def test_captures_back_to_back_with_launches_and_killed_runs(cli, tmp_path):
    mark = f"RMWI_STRESS_MARK={uuid.uuid4().hex}"
    env = {**cli.env, mark.split("=")[0]: mark.split("=")[1]}
    rng = random.Random(int(os.environ.get("RMWI_STRESS_SEED", "39")))
    talker = [console_script(), "capture", "--package", "rmw_introspect_examples", "--executable", "talker",
              "--timeout", f"{TIMEOUT_S:g}"]
    robot = [console_script(), "capture", "--launch-package", "rmw_introspect_examples",
             "--launch-file", "robot.launch.xml", "--timeout", f"{TIMEOUT_S:g}", "--format", "json"]
    slowest: tuple[float, str] = (0.0, "")
    killed = launches = 0
    seen: set[int] = set()
    for i in range(CAPTURES):
        if i % KILL_EVERY == KILL_EVERY - 1:
            proc = subprocess.Popen(talker, cwd=tmp_path, env=env, stdout=subprocess.DEVNULL,
                                    stderr=subprocess.DEVNULL)
            time.sleep(rng.uniform(0.0, 1.5))  # before, during or after its target's start
            seen.update(_marked_processes(mark))
            proc.send_signal(signal.SIGKILL)
            proc.wait(10)
            killed += 1
            continue
        runs = [("talker", talker)] + ([("robot launch", robot)] if i % LAUNCH_EVERY == LAUNCH_EVERY - 1 else [])
        for name, argv in runs:
            started = time.monotonic()
            result = subprocess.run(argv, cwd=tmp_path, env=env, capture_output=True, text=True,
                                    timeout=TIMEOUT_S + 60)
            took = time.monotonic() - started
            assert result.returncode == 0, f"capture {i} ({name}): exit {result.returncode}\n{result.stderr[-3000:]}"
            assert took < TIMEOUT_S + MARGIN_S, f"capture {i} ({name}) took {took:.1f} s"
            slowest = max(slowest, (took, f"capture {i} ({name})"))
            launches += name == "robot launch"
    print(f"{CAPTURES - killed} captures, {launches} launch captures, {killed} killed runs; "
          f"slowest {slowest[0]:.1f} s ({slowest[1]})")
    # nothing left running: every target of a killed runner died with it (parent-death signal)
    left = wait_gone([p for p in {*seen, *_marked_processes(mark)} if p != os.getpid()], 10.0)
    assert left == [], {p: Path(f"/proc/{p}/cmdline").read_bytes() for p in left if Path(f"/proc/{p}").exists()}
    # ... and nothing of theirs holds a lock (the build and golden-write locks are flocks)
    assert not (_lock_holders() & seen)
