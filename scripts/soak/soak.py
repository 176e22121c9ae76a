#!/usr/bin/env python3
"""`make soak`: the example package's contracts checked again and again, as a CI would run them.

    .venv/bin/python scripts/soak/soak.py [--runs 1000] [--workers 2]

Each run is one pytest session over the example package's node contracts
(``examples/rmw_introspect_examples/contracts/*.interfaces.yaml``, bare contract items) with
``-n WORKERS``; even runs start their Python targets warm (the default), odd runs cold
(``--rmw-introspect-cold-start``). Every run must give the same outcome for every item as the
first run of its kind (warm or cold) and as each other; every outcome is counted.

Counted after the last session ended (shared memory: before the first and after the last) and
reported as leaks:

* processes that carry the soak's mark (``RMWI_SOAK_MARK``, inherited by every process of every
  session: pytest, its workers, targets, warm start servers) after the last session ended;
* shared memory segments of this user in /dev/shm;
* what is left in the sessions' own temporary directory (``TMPDIR``: a directory of the soak's),
  but for pytest's base directories and the golden-write lock directory;
* file descriptors of each pytest worker: ``fd_probe`` (a pytest plugin given to every session)
  counts a worker's open descriptors after its first item and at its end; growth over a
  session is a runner leaking one per capture.

Stopping early: ``--minutes M`` ends the soak after the run during which M minutes passed, and
SIGTERM after the run in progress; either way everything above is still counted and reported, with
the number of runs done ("stopped after 412 of 1000 runs").

Exit status 0 when every run had the same outcomes and nothing leaked, 1 otherwise.
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
import uuid
import xml.etree.ElementTree as ET
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples" / "rmw_introspect_examples"
HERE = Path(__file__).resolve().parent
#: a session's descriptors may grow this much after its first item (lazily opened files: the
#: capture model's imports, a warm start server's sockets) before it counts as a leak
FD_GROWTH_ALLOWED = 8
#: seconds one pytest session may take (17 contracts on two workers take ~20-60 s)
SESSION_TIMEOUT = 900


#: the variable every process of the soak inherits (pytest, its workers, targets, warm start
#: servers): what carries it is the soak's, whatever else runs on the machine
MARK = "RMWI_SOAK_MARK"
#: entries the sessions leave in their temporary directory on purpose: pytest's own base
#: directories (it keeps the last three) and the golden-write lock directory
KEPT_TEMPORARY = ("pytest-of-", "pytest-rmw-introspect-locks-")


def marked_processes(mark: str) -> dict[int, str]:
    """Processes whose environment carries ``MARK=mark``: pid → command line."""
    found: dict[int, str] = {}
    needle = f"{MARK}={mark}".encode()
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            if needle not in (entry / "environ").read_bytes():
                continue
            cmdline = (entry / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace").strip()
        except OSError:
            continue
        found[int(entry.name)] = cmdline
    return found


def shared_memory() -> set[str]:
    """This user's entries in /dev/shm (the machine's: other programs of the user may add some)."""
    try:
        return {p.name for p in Path("/dev/shm").iterdir() if p.stat().st_uid == os.getuid()}
    except OSError:
        return set()


def temporary_entries(tmpdir: Path) -> set[str]:
    """What is in the sessions' own temporary directory, but for what is kept there on purpose."""
    return {p.name for p in tmpdir.iterdir() if not p.name.startswith(KEPT_TEMPORARY)}


def outcomes(junit: Path) -> dict[str, str]:
    """Item → passed / failed / error / skipped, from a JUnit XML report."""
    result: dict[str, str] = {}
    for case in ET.parse(junit).getroot().iter("testcase"):
        name = f"{case.get('classname', '')}::{case.get('name', '')}"
        kinds = [child.tag for child in case if child.tag in ("failure", "error", "skipped")]
        result[name] = kinds[0] if kinds else "passed"
    return result


def one_session(run: int, workers: int, python: Path, work: Path, mark: str,
                tmpdir: Path) -> tuple[dict[str, str], float, list[dict]]:
    cold = run % 2 == 1
    junit = work / f"run{run}.xml"
    fds = work / f"fds{run}"
    fds.mkdir()
    cmd = [str(python), "-m", "pytest", "-p", "no:cacheprovider", "-p", "fd_probe", "-q", "-n", str(workers),
           f"--junitxml={junit}", *sorted(str(p) for p in (EXAMPLES / "contracts").glob("*.interfaces.yaml"))]
    if cold:
        cmd.append("--rmw-introspect-cold-start")
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in (str(HERE), os.environ.get("PYTHONPATH")) if p),
           "SOAK_FD_DIR": str(fds), MARK: mark, "TMPDIR": str(tmpdir)}
    started = time.monotonic()
    proc = subprocess.run(cmd, cwd=EXAMPLES, env=env, capture_output=True, text=True, timeout=SESSION_TIMEOUT)
    wall = time.monotonic() - started
    if not junit.exists():
        raise SystemExit(f"soak: run {run} wrote no report (status {proc.returncode}):\n{proc.stdout[-3000:]}"
                         f"\n{proc.stderr[-3000:]}")
    counts = [json.loads(p.read_text()) for p in sorted(fds.glob("*.json"))]
    return outcomes(junit), wall, counts


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=1000)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--python", type=Path, default=Path(sys.executable))
    parser.add_argument("--settle", type=float, default=5.0,
                        help="seconds to wait after the last run before counting what is left")
    parser.add_argument("--minutes", type=float, default=None,
                        help="stop after the run during which this many minutes passed (a partial soak, "
                             "reported as such); SIGTERM stops after the run in progress")
    args = parser.parse_args(argv)
    stop: list[str] = []  # why the soak stopped before --runs, once it must
    signal.signal(signal.SIGTERM, lambda *_: stop.append("SIGTERM"))
    deadline = None if args.minutes is None else time.monotonic() + 60 * args.minutes

    mark = uuid.uuid4().hex
    shm_before = shared_memory()
    reference: dict[str, str] | None = None
    differing: list[tuple[int, dict[str, tuple[str | None, str | None]]]] = []
    tally: collections.Counter[str] = collections.Counter()
    walls: list[float] = []
    fd_leaks: list[str] = []
    with tempfile.TemporaryDirectory(prefix="soak-") as tmp:
        work, tmpdir = Path(tmp) / "work", Path(tmp) / "tmp"
        work.mkdir()
        tmpdir.mkdir()
        for run in range(args.runs):
            if deadline is not None and time.monotonic() > deadline:
                stop.append(f"--minutes {args.minutes:g}")
            if stop:
                break
            got, wall, fd_counts = one_session(run, args.workers, args.python, work, mark, tmpdir)
            walls.append(wall)
            tally.update(got.values())
            if reference is None:
                reference = got
            elif got != reference:
                diff = {k: (reference.get(k), got.get(k)) for k in sorted(set(reference) | set(got))
                        if reference.get(k) != got.get(k)}
                differing.append((run, diff))
            for count in fd_counts:
                if count["end"] - count["first"] > FD_GROWTH_ALLOWED:
                    fd_leaks.append(f"run {run} worker {count['worker']}: {count['first']} -> {count['end']} fds")
            print(f"soak: run {run + 1}/{args.runs} ({'cold' if run % 2 else 'warm'}) {wall:.1f} s: "
                  + ", ".join(f"{k} {v}" for k, v in sorted(collections.Counter(got.values()).items())), flush=True)
        time.sleep(args.settle)
        leaked_processes = marked_processes(mark)
        leaked_shm = sorted(shared_memory() - shm_before)
        leaked_tmp = sorted(temporary_entries(tmpdir))
    items = len(reference or {})
    done = len(walls)
    if done < args.runs:
        print(f"\nsoak: stopped after {done} of {args.runs} runs ({stop[0]})")
    print(f"\nsoak: {done} runs of {items} contract items (-n {args.workers}, warm and cold alternating), "
          f"{sum(walls):.0f} s in all, {min(walls, default=0):.1f}-{max(walls, default=0):.1f} s a run")
    print("soak: outcomes: " + ", ".join(f"{k} {v}" for k, v in sorted(tally.items())))
    print(f"soak: runs identical to the first: {done - len(differing)} of {done}")
    for run, diff in differing[:5]:
        print(f"soak: run {run} differed: " + "; ".join(f"{k}: {a} -> {b}" for k, a, b in
                                                       ((k, *v) for k, v in list(diff.items())[:5])))
    print(f"soak: processes left running: {len(leaked_processes)}"
          + "".join(f"\n    {pid}: {cmd[:160]}" for pid, cmd in sorted(leaked_processes.items())))
    print(f"soak: shared memory segments left: {len(leaked_shm)} {leaked_shm[:10]}")
    print(f"soak: temporary entries left in the sessions' TMPDIR: {len(leaked_tmp)} {leaked_tmp[:10]}")
    print(f"soak: workers whose descriptors grew over {FD_GROWTH_ALLOWED}: {len(fd_leaks)}"
          + "".join(f"\n    {line}" for line in fd_leaks[:10]))
    bad = differing or leaked_processes or leaked_shm or leaked_tmp or fd_leaks or not done
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
