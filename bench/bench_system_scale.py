"""Capture and check time of a whole system against its number of processes (issue 42).

    python bench/bench_system_scale.py [--sizes 1,10,50,150,300] [--reps 1] [--plot FILE.png]

For each size N a launch file starts N processes of the example package (talkers and listeners,
each pair in a namespace of its own: tests/support/sample_systems.py). Each repetition runs, as
a user would, ``rmw-introspect capture --launch FILE -o N.system.yaml`` and then
``rmw-introspect check N.system.yaml`` (the contract just written: a check that passes), each in
a process of its own, and measures of each: the wall time, the CPU time of the CLI process and
everything it started (``os.wait4``), the peak RSS of the CLI process itself (its ``VmHWM``,
read while it runs) and the largest of its descendants (``ru_maxrss``). Capture and check of a
size run back to back, so their ratio is taken under the same load.

With ``--pytest`` each repetition also runs the contract as pytest would in CI, ``python -m pytest
N.system.yaml`` once with ``-n 0`` and once with ``-n 2`` (pytest-xdist), and takes the system
item's own duration from its JUnit XML (set-up, call and tear-down: what the item costs, without
pytest's start-up, collection and starting the workers) and the whole pytest process's wall time.

Prints a Markdown table (medians), the check/capture ratios, the cost per process (slope
between the smallest and the largest size) and the CPU per process; ``--plot`` draws the
times against N into a PNG (matplotlib, from the lock's development tools; ``make bench`` draws
docs/system-scale.png). Any run that fails (exit status not 0, or a check that does
not match) stops the benchmark with exit status 1 and the run's output: no timing is asserted.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import threading
import time
import xml.etree.ElementTree as ElementTree
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests" / "support"))
from sample_systems import many_processes  # noqa: E402

CLI = Path(sys.executable).parent / "rmw-introspect"


@dataclass
class Run:
    wall: float  # s
    cpu: float  # s, user + system, the CLI process and its descendants
    rss_cli: float  # MiB, the CLI process's own peak
    rss_max: float  # MiB, the largest process of the run (ru_maxrss)


def _hwm(pid: int) -> float:
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024
    except OSError:
        pass
    return 0.0


def run(args: list[str], cwd: Path, expect: str | None = None, program: list[str] | None = None) -> Run:
    """Run the CLI (or ``program``); exits the benchmark (status 1) when it fails."""
    argv = [*(program or [str(CLI)]), *args]
    started = time.perf_counter()
    proc = subprocess.Popen(argv, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    peak = [0.0]
    done = threading.Event()

    def watch() -> None:  # VmHWM only grows: its last reading is the peak
        while not done.is_set():
            peak[0] = max(peak[0], _hwm(proc.pid))
            done.wait(0.05)

    watcher = threading.Thread(target=watch, daemon=True)
    watcher.start()
    assert proc.stdout is not None and proc.stderr is not None
    # read the pipes in threads, then reap with wait4 to get the run's resource usage
    outs: dict[str, str] = {}
    readers = [threading.Thread(target=lambda k=k, f=f: outs.__setitem__(k, f.read()))
               for k, f in (("out", proc.stdout), ("err", proc.stderr))]
    for reader in readers:
        reader.start()
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - started
    proc.returncode = os.waitstatus_to_exitcode(status)
    done.set()
    for reader in readers:
        reader.join()
    watcher.join()
    stdout, stderr = outs.get("out", ""), outs.get("err", "")
    if proc.returncode != 0 or (expect is not None and expect not in stdout):
        sys.exit(f"bench_system_scale: `{' '.join(argv)}` failed (exit status {proc.returncode})"
                 f"\n--- stdout\n{stdout}\n--- stderr\n{stderr}")
    return Run(wall, usage.ru_utime + usage.ru_stime, peak[0], usage.ru_maxrss / 1024)


@dataclass
class PytestRun:
    wall: float  # s, the whole pytest process
    item: float  # s, the system item's set-up, call and tear-down (JUnit XML)


def run_pytest(n: int, workers: int, cwd: Path) -> PytestRun:
    """``pytest N.system.yaml -n WORKERS``; exits the benchmark when the item does not pass."""
    report = cwd / f"{n}-n{workers}.junit.xml"
    whole = run(["-m", "pytest", f"{n}.system.yaml", "-n", str(workers), "-q", "-p", "no:cacheprovider",
                 f"--junitxml={report}"], cwd, expect="1 passed", program=[sys.executable])
    cases = ElementTree.parse(report).getroot().iter("testcase")
    return PytestRun(whole.wall, sum(float(case.get("time", "0")) for case in cases))


def median(runs: list[Run], key: str) -> float:
    return statistics.median(getattr(r, key) for r in runs)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", default="1,10,50,150,300", help="numbers of processes, comma-separated")
    parser.add_argument("--reps", type=int, default=1)
    parser.add_argument("--pytest", action="store_true",
                        help="also run the contract with pytest, -n 0 and -n 2, and time its item")
    parser.add_argument("--plot", type=Path, metavar="FILE.png", help="draw the times into this PNG (matplotlib)")
    args = parser.parse_args()
    sizes = [int(s) for s in args.sizes.split(",")]
    if args.plot is not None:
        try:
            import matplotlib
        except ImportError:
            sys.exit("bench_system_scale: --plot needs matplotlib (requirements/tools.in): `make bootstrap` "
                     "installs it into the venv")
        matplotlib.use("Agg")
    print(f"{os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f} at the start", flush=True)
    results: dict[int, tuple[list[Run], list[Run]]] = {}
    pytest_results: dict[int, dict[int, list[PytestRun]]] = {}
    with tempfile.TemporaryDirectory(prefix="bench_system_scale_") as d:
        root = Path(d)
        for n in sizes:
            (root / f"{n}.launch.xml").write_text(many_processes(n))
            captures, checks = [], []
            for _ in range(args.reps):
                captures.append(run(["capture", "--launch", f"{n}.launch.xml", "-o", f"{n}.system.yaml"], root))
                checks.append(run(["check", f"{n}.system.yaml"], root, expect=f"{n}.system.yaml: matches ("))
                if args.pytest:
                    for workers in (0, 2):
                        pytest_results.setdefault(n, {}).setdefault(workers, []).append(run_pytest(n, workers, root))
            results[n] = (captures, checks)
            print(f"  {n} processes: capture {median(captures, 'wall'):.2f} s, check {median(checks, 'wall'):.2f} s",
                  flush=True)
    print(f"load average {os.getloadavg()[0]:.1f} at the end; medians of {args.reps}\n")
    print("| processes | capture --launch (s) | check (s) | check / capture | CPU capture (s) | CPU check (s) "
          "| peak RSS of the CLI, check (MiB) | largest process (MiB) |")
    print("|---|---|---|---|---|---|---|---|")
    for n, (captures, checks) in results.items():
        print(f"| {n} | {median(captures, 'wall'):.2f} | {median(checks, 'wall'):.2f} "
              f"| {median(checks, 'wall') / median(captures, 'wall'):.2f} | {median(captures, 'cpu'):.1f} "
              f"| {median(checks, 'cpu'):.1f} | {median(checks, 'rss_cli'):.0f} | {median(checks, 'rss_max'):.0f} |")
    if pytest_results:
        print("\n| processes | capture --launch (s) | pytest -n 0: item (s) | item / capture | whole pytest (s) "
              "| pytest -n 2: item (s) | item / capture | whole pytest (s) |")
        print("|---|---|---|---|---|---|---|---|")
        for n, by_workers in pytest_results.items():
            capture = median(results[n][0], "wall")
            cells = [f"{median(by_workers[w], 'item'):.2f} | {median(by_workers[w], 'item') / capture:.2f} "
                     f"| {median(by_workers[w], 'wall'):.2f}" for w in (0, 2)]
            print(f"| {n} | {capture:.2f} | {cells[0]} | {cells[1]} |")
    if len(sizes) > 1:
        low, high = min(sizes), max(sizes)
        for kind, index in (("capture", 0), ("check", 1)):
            slope = (median(results[high][index], "wall") - median(results[low][index], "wall")) / (high - low)
            cpu = median(results[high][index], "cpu") / high
            print(f"\n{kind}: {slope * 1000:.0f} ms per process (wall, {low} → {high}), {cpu * 1000:.0f} ms CPU per "
                  f"process at {high}", end="")
        rss = median(results[high][1], "rss_cli") / max(median(results[low][1], "rss_cli"), 1e-9)
        print(f"\npeak RSS of the checking CLI, {high} against {low} processes: {rss:.2f}x")
    if args.plot is not None:
        from matplotlib import pyplot

        figure, axes = pyplot.subplots(figsize=(6, 4), dpi=100)
        axes.plot(sizes, [median(results[n][0], "wall") for n in sizes], "o-", label="capture --launch")
        axes.plot(sizes, [median(results[n][1], "wall") for n in sizes], "s-", label="check")
        axes.set_xlabel("processes in the launch file")
        axes.set_ylabel("wall time (s)")
        axes.set_title("A whole system: capture and check time")
        axes.grid(True, alpha=0.3)
        axes.legend()
        figure.tight_layout()
        figure.savefig(args.plot)
        print(f"plot: {args.plot}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
