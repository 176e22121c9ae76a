"""Detected quiescence (issue 24): the rows of the issue's table, each measured twice in the same
run - "before" with the quiet window alone (``RMW_INTROSPECT_IDLE=0``, the rule before issue 24)
and "now" (detection on, the default) - with the ratios the issue's targets name.

    python bench/bench_quiescence.py [--reps 5] [--items 100]

Medians in ms. Targets are the example package's executables (installed by `make bootstrap`),
a 1 kHz timer node and the test suite's rcl C timer node (plain, and polling ``rcl_wait`` with a
zero timeout); captures go through the public API, ``pytest_rmw_introspect.capture(...)``, with
the default options unless a row says otherwise. Floors: ``python -c 'import rclpy'``, and the
talker's code that exits right after creating its node (``bench_time_to_capture``). The last row
runs ``--items`` generated contract items with ``pytest -n 2`` (warm, default) against "import
rclpy ITEMS times on 2 cores". On a machine shared with other work the figures move from run to
run: compare the two columns of one run, not runs. Then bench_cpp_polling.py runs (rclcpp
programs that poll or never block, against a plain rclcpp capture) when the C++ overlay is built.
"""

from __future__ import annotations

import argparse
import concurrent.futures
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench_time_to_capture import NODE_SETUP_ONLY, recording_env, timed
from bench_virtual_time import KILOHERTZ_NODE
from bench_warm_start import executables, pytest_run, write_items

import pytest_rmw_introspect
from pytest_rmw_introspect.run import middleware, ros_env
from pytest_rmw_introspect.run.warm import client as warm

PY = sys.executable
PACKAGE = "rmw_introspect_examples"
BEFORE = {"RMW_INTROSPECT_IDLE": "0"}
C_NODE_DIR = Path(__file__).resolve().parents[1] / "tests" / "middleware" / "c_node"


def c_timer_node() -> Path | None:
    """The suite's compiled rcl timer node (built by its c_node fixture), when there is one."""
    found = sorted(middleware.cache_root().glob("c_node-*/build/rmwi_c_timer_node"), key=lambda p: p.stat().st_mtime)
    return found[-1] if found else None


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--reps", type=int, default=5)
    parser.add_argument("--items", type=int, default=100, help="contract items of the last row (0: skip it)")
    args = parser.parse_args()
    ros = ros_env.detect()
    library = middleware.ensure_library(ros)

    def median(measure) -> float:
        measure()  # warm-up: page cache, bytecode, the warm start server
        return statistics.median(measure() for _ in range(args.reps))

    def captured(before: bool, **options) -> float:
        if before:
            options["env"] = {**options.get("env", {}), **BEFORE}
        t0 = time.monotonic()
        pytest_rmw_introspect.capture(**options)
        return (time.monotonic() - t0) * 1000

    def both(**options) -> tuple[float, float]:
        return median(lambda: captured(True, **options)), median(lambda: captured(False, **options))

    talker = {"package": PACKAGE, "executable": "talker"}
    lifecycle = {"package": PACKAGE, "executable": "lifecycle_talker"}
    with tempfile.TemporaryDirectory() as d:
        quiet = recording_env(library, ros, Path(d) / "unused.json", RMW_INTROSPECT_AUTO_EXPORT="0")
        floor = median(lambda: timed([PY, "-c", "import rclpy"], quiet))
        setup_only = median(lambda: timed([PY, "-c", NODE_SETUP_ONLY], quiet))
        kilohertz = Path(d) / "kilohertz.py"
        kilohertz.write_text(KILOHERTZ_NODE)
        rows: list[tuple[str, tuple[float, float] | float]] = [
            ("floor: python -c 'import rclpy'", floor),
            ("floor: talker code, node set up then exit (no capture)", setup_only),
            ("talker, cold, settle 0.01 s", both(cold_start=True, settle=0.01, **talker)),
            ("talker, cold, default settle 0.1 s", both(cold_start=True, **talker)),
            ("talker, warm, settle 0.01 s", both(settle=0.01, **talker)),
            ("talker, warm, default settle 0.1 s", both(**talker)),
            ("talker, warm, virtual time off (horizon=0)", both(horizon=0, **talker)),
            ("lifecycle_talker driven to active", both(**lifecycle)),
            ("lifecycle_talker left alone (lifecycle: none)", both(lifecycle="none", **lifecycle)),
            ("1 kHz timer node, 10 s horizon", both(script=str(kilohertz))),
        ]
        c_node = c_timer_node()
        if c_node is not None:
            rows += [("rcl C timer node, plain", both(command=[str(c_node)])),
                     ("rcl C timer node polling rcl_wait(0)", both(command=[str(c_node), "poll"]))]
        warm.shutdown()
        if args.items:
            rows += items_rows(args.items, ros)

    def now(name: str) -> float:
        value = dict(rows)[name]
        return value[1] if isinstance(value, tuple) else value

    def before(name: str) -> float:
        value = dict(rows)[name]
        return value[0] if isinstance(value, tuple) else value

    print(f"{'median of %d runs (ms)' % args.reps:<58} {'before':>9} {'now':>9}")
    for name, value in rows:
        old, new = value if isinstance(value, tuple) else ("", value)
        print(f"{name:<58} {old if old == '' else f'{old:9.1f}':>9} {new:9.1f}")
    print("\nratios (target), before -> now:")
    targets = [
        ("warm talker, default / import-rclpy floor", "talker, warm, default settle 0.1 s",
         "floor: python -c 'import rclpy'", 0.4),
        ("cold talker, default / talker code set up then exit", "talker, cold, default settle 0.1 s",
         "floor: talker code, node set up then exit (no capture)", 1.15),
        ("virtual time on / off (warm talker)", "talker, warm, default settle 0.1 s",
         "talker, warm, virtual time off (horizon=0)", 1.1),
        ("lifecycle driven to active / left alone", "lifecycle_talker driven to active",
         "lifecycle_talker left alone (lifecycle: none)", 1.2),
        ("1 kHz timer node, 10 s horizon / warm talker", "1 kHz timer node, 10 s horizon",
         "talker, warm, default settle 0.1 s", 2.0),
    ]
    if c_node is not None:
        targets.append(("rcl C node polling rcl_wait(0) / plain C timer node", "rcl C timer node polling rcl_wait(0)",
                        "rcl C timer node, plain", 2.0))
    if args.items:
        targets.append((f"{args.items} contract items, pytest -n 2, warm / import rclpy {args.items}x on 2 cores",
                        f"{args.items} contract items, pytest -n 2, warm",
                        f"import rclpy {args.items} times on 2 cores", 0.6))
    for label, numerator, denominator, goal in targets:
        old, new = before(numerator) / before(denominator), now(numerator) / now(denominator)
        print(f"  {label:<76} {old:5.2f} -> {new:5.2f}  (target <= {goal}: {'met' if new <= goal else 'NOT met'})")
    # the rclcpp polling programs (issue 24 item 6), when the C++ overlay is built
    print()
    sys.stdout.flush()
    subprocess.run([PY, str(Path(__file__).with_name("bench_cpp_polling.py")), "--reps", str(args.reps)], check=True)
    return 0


def items_rows(count: int, ros: ros_env.RosEnvironment) -> list[tuple[str, tuple[float, float] | float]]:
    """``count`` generated contract items under ``pytest -n 2`` (warm), before and now, and the
    reference: ``import rclpy`` ``count`` times, two processes at a time."""
    def imports() -> float:
        t0 = time.monotonic()
        with concurrent.futures.ThreadPoolExecutor(2) as pool:
            list(pool.map(lambda _: subprocess.run([PY, "-c", "import rclpy"], check=True), range(count)))
        return (time.monotonic() - t0) * 1000

    with tempfile.TemporaryDirectory(prefix="bench_quiescence_") as d:
        directory = Path(d)
        (directory / "pytest.ini").write_text("[pytest]\n")
        write_items(directory, count, executables(ros))
        pytest_run(directory, "--update-golden")  # the goldens: not timed
        os.environ.update(BEFORE)
        try:
            old = pytest_run(directory)[0]
        finally:
            os.environ.pop("RMW_INTROSPECT_IDLE", None)
        new = pytest_run(directory)[0]
    return [(f"import rclpy {count} times on 2 cores", imports()),
            (f"{count} contract items, pytest -n 2, warm", (old, new))]


if __name__ == "__main__":
    sys.exit(main())
