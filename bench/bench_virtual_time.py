"""Virtual time: what a node creates in its first seconds, captured in milliseconds.

    python bench/bench_virtual_time.py [--reps 5]

Every figure is measured in this run, on this machine (medians, ms). Targets are the example
package's executables (installed into the venv by `make bootstrap`) plus a 1 kHz timer node
written by the benchmark; recording runs go through the public API,
``pytest_rmw_introspect.capture(...)``, exactly as the plugin and the CLI run a target.

Rows:
- `talker` with the default options (settle 0.1 s, virtual-time horizon 10 s): the reference;
- `talker` with virtual time off (``horizon=0``): what the warp itself costs a plain node;
- `battery_monitor` (creates its publisher from a timer 3 s after start) three ways: with
  virtual time (default options), with a real ``settle`` long enough to catch the publisher
  (``horizon=0, settle=3.5``), and under Fast DDS (spawn -> a second, already running rclpy
  process sees its ``battery_state`` publisher);
- a node with a 1 kHz periodic timer, with and without virtual time (10 s of virtual life =
  10,000 timer callbacks, bounded by the middleware's warp budget).
The issue's target: `battery_monitor` with virtual time in less than twice the plain talker.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

import pytest_rmw_introspect
from bench_time_to_capture import run_fastdds
from pytest_rmw_introspect import ros_env, target

PACKAGE = "rmw_introspect_examples"

KILOHERTZ_NODE = r"""
import rclpy
from rclpy.node import Node
from std_msgs.msg import String

rclpy.init()
node = Node("kilohertz")
publisher = node.create_publisher(String, "fast", 10)
node.create_timer(0.001, lambda: publisher.publish(String(data="tick")))
rclpy.spin(node)
"""


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--reps", type=int, default=5)
    args = parser.parse_args()

    def median(measure) -> float:
        measure()  # warm-up: page cache, Python bytecode, the middleware build
        return statistics.median(measure() for _ in range(args.reps))

    def captured(expect: str | None = None, **target) -> float:
        t0 = time.monotonic()
        cap = pytest_rmw_introspect.capture(**target)
        ms = (time.monotonic() - t0) * 1000
        if expect is not None and not any(p.name == expect for node in cap for p in node.publishers):
            raise RuntimeError(f"{target}: the capture lacks the publisher {expect}")
        return ms

    talker = {"package": PACKAGE, "executable": "talker"}
    battery = {"package": PACKAGE, "executable": "battery_monitor"}
    ros = ros_env.detect()
    battery_argv = [str(target.find_executable(PACKAGE, "battery_monitor", ros_env.ament_prefixes(ros.ament_prefixes)))]

    with tempfile.TemporaryDirectory() as d:
        kilohertz = Path(d) / "kilohertz.py"
        kilohertz.write_text(KILOHERTZ_NODE)
        rows = [
            ("talker, default options (virtual time on)", median(lambda: captured("/chatter", **talker))),
            ("talker, virtual time off (horizon=0)", median(lambda: captured("/chatter", horizon=0, **talker))),
            ("battery_monitor (3 s timer), virtual time", median(lambda: captured("/battery_state", **battery))),
            ("battery_monitor, real settle 3.5 s (horizon=0)",
             median(lambda: captured("/battery_state", horizon=0, settle=3.5, **battery))),
            ("battery_monitor, Fast DDS (seen by another process)",
             median(lambda: run_fastdds(battery_argv, "battery_monitor", ros, topic="battery_state"))),
            ("1 kHz timer node, virtual time (10 s horizon)", median(lambda: captured("/fast", script=str(kilohertz)))),
            ("1 kHz timer node, virtual time off", median(lambda: captured("/fast", script=str(kilohertz), horizon=0))),
        ]
    print(f"{'median of %d runs' % args.reps:<56} {'ms':>9} {'/ talker':>9}")
    reference = rows[0][1]
    for name, ms in rows:
        print(f"{name:<56} {ms:9.1f} {ms / reference:8.2f}x")
    ratio = rows[2][1] / reference
    print()
    print(f"battery_monitor with virtual time / plain talker: {ratio:.2f}x (target: below 2x: {'met' if ratio < 2 else 'NOT met'})")
    print(f"battery_monitor: virtual time is {rows[3][1] / rows[2][1]:.1f}x faster than a real settle, "
          f"{rows[4][1] / rows[2][1]:.1f}x faster than Fast DDS discovery")
    return 0


if __name__ == "__main__":
    sys.exit(main())
