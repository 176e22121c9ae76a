"""Where a cold capture of the example talker spends its time (issue 24 item 3): the target is run
as the runner runs it (its environment, the parent-death wrapper) with ``RMW_INTROSPECT_VERBOSE=1``,
and the middleware's stderr lines are timestamped as they arrive; the floors of
bench_quiescence.py ("talker code, node set up then exit", ``import rclpy``) are measured in turn
with each repetition.

    python bench/bench_cold_capture.py [--reps 9] [--settle 0.1]

Medians in ms. The stages: the process until the middleware creates the node (Python, the
imports, ``rclpy.init``), rclpy's ``Node`` set-up until the ``/chatter`` publisher, the first
settle (detected idle), the parameter probe, the warp until the first timer callback's log line
(rclpy's caller lookup, paid once per cold process), the rest of the warp and the final settle,
and the settled capture's write and the process's end as the runner sees it.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench_time_to_capture import NODE_SETUP_ONLY, recording_env, timed

from pytest_rmw_introspect.run import middleware, process, ros_env, target

PY = sys.executable
#: (mark, text of the first stderr line that sets it)
MARKS = [("node", "] node "), ("chatter", "/chatter"), ("idle", "idle"), ("warp", "wrote warping"),
         ("log0", "Hello World: 0"), ("settled", "exiting")]
STAGES = [
    ("spawn -> node created (Python, imports, rclpy.init)", None, "node"),
    ("node -> /chatter created (rclpy's Node set-up)", "node", "chatter"),
    ("/chatter -> idle detected (executor starts, first settle)", "chatter", "idle"),
    ("idle -> warp starts (parameter probe)", "idle", "warp"),
    ("warp -> first timer callback's log line", "warp", "log0"),
    ("first log line -> settled (18 callbacks, final settle)", "log0", "settled"),
    ("settled -> end seen (write, _exit, teardown)", "settled", "exit"),
]


def timeline(spec: target.TargetSpec, library: Path, ros: ros_env.RosEnvironment) -> dict[str, float]:
    argv = target.build_argv(spec, ros_env.ament_prefixes(tuple(ros.ament_prefixes)))
    with tempfile.TemporaryDirectory(prefix="bench_cold_capture_") as d:
        env = target.environment(spec, library, ros, Path(d) / "capture.<pid>.json")
        env["RMW_INTROSPECT_VERBOSE"] = "1"
        marks: dict[str, float] = {}
        t0 = time.monotonic()
        proc = subprocess.Popen([*(process.death_signal_wrapper() or ()), *argv], env=env, text=True,
                                stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        assert proc.stderr is not None
        for line in proc.stderr:
            for mark, text in MARKS:
                if text in line and mark not in marks:
                    marks[mark] = (time.monotonic() - t0) * 1000
                    break
        proc.wait()
        marks["exit"] = (time.monotonic() - t0) * 1000
    missing = [mark for mark, _ in MARKS if mark not in marks]
    if missing:
        raise SystemExit(f"the talker's stderr had no line for {missing}: is the example package installed?")
    return marks


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--reps", type=int, default=9)
    parser.add_argument("--settle", type=float, default=None, help="the target's settle (default: the default)")
    args = parser.parse_args()
    ros = ros_env.detect()
    library = middleware.ensure_library(ros)
    options = {"package": "rmw_introspect_examples", "executable": "talker"}
    spec = target.TargetSpec.from_mapping({**options, **({"settle": args.settle} if args.settle is not None else {})})
    rows = []
    with tempfile.TemporaryDirectory() as d:
        quiet = recording_env(library, ros, Path(d) / "unused.json", RMW_INTROSPECT_AUTO_EXPORT="0")
        timeline(spec, library, ros)  # warm-up: page cache, bytecode
        for _ in range(args.reps):
            marks = timeline(spec, library, ros)
            marks["floor"] = timed([PY, "-c", NODE_SETUP_ONLY], quiet)
            marks["import"] = timed([PY, "-c", "import rclpy"], quiet)
            rows.append(marks)
    print(f"cold talker capture, medians of {args.reps} (ms)")
    for label, start, end in STAGES:
        print(f"  {label:<62} {statistics.median(r[end] - (r[start] if start else 0.0) for r in rows):7.1f}")
    print(f"  {'the whole target, spawn -> end seen':<62} {statistics.median(r['exit'] for r in rows):7.1f}")
    print(f"  {'floor: talker code, node set up then exit (no capture)':<62} {statistics.median(r['floor'] for r in rows):7.1f}")
    print(f"  {'floor: python -c import rclpy':<62} {statistics.median(r['import'] for r in rows):7.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
