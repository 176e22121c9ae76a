"""rclcpp programs that poll or never block (issue 24 item 6) against a plain rclcpp capture.

    python bench/bench_cpp_polling.py [--reps 5]      (run by bench_quiescence.py, so `make bench`)

Needs the C++ and launch overlay (`make overlay`, docs/overlay.md); without one it
says so and exits 0. Like bench_cpp_talker.py it re-runs itself in the overlay's environment and
builds what it runs over the overlay (once, cached): the C++ example talker (the plain capture)
and tests/overlay/cpp_polling (the programs of tests/overlay/test_cpp_polling.py).

Rows: medians in ms of `pytest_rmw_introspect.capture(command=[...])` with the default options
(10 s horizon), "before" with the quiet window alone (RMW_INTROSPECT_IDLE=0) and "now". Target
(issue 24 item 6): the spin_some action client and the node whose timers cancel themselves end
within 2x the plain talker's capture. The sleep_for and WallRate loops are shown for what they
cost; they sleep on the real clock, which no rule can shorten below two of their periods.
"""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(REPO / "tests" / "overlay"), str(REPO / "tests" / "support")]

import overlay_support  # noqa: E402

import pytest_rmw_introspect  # noqa: E402

BEFORE = {"RMW_INTROSPECT_IDLE": "0"}


def main() -> int:
    started = overlay_support.start_bench("bench_cpp_polling", __doc__, reps=5)
    if started is None:
        return 0
    args, overlay, examples = started
    programs = overlay_support.cmake_build(overlay, REPO / "tests" / "overlay" / "cpp_polling", "cpp_polling")
    lib = programs / "install" / "lib" / "rmwi_cpp_polling"

    def captured(command: list[str], before: bool) -> float:
        t0 = time.monotonic()
        pytest_rmw_introspect.capture(command=command, env=dict(BEFORE) if before else {})
        return (time.monotonic() - t0) * 1000

    def both(command: list[str]) -> tuple[float, float]:
        def median(before: bool) -> float:
            captured(command, before)  # warm-up: page cache
            return statistics.median(captured(command, before) for _ in range(args.reps))
        return median(True), median(False)

    rows = [
        ("rclcpp talker (plain capture)", both([str(examples / "lib" / "rmw_introspect_examples_cpp" / "talker")])),
        ("action client, while (!done) spin_some(node)", both([str(lib / "action_poller")])),
        ("timers that cancel themselves, rclcpp::spin", both([str(lib / "cancelled_timers")])),
        ("timers that cancel themselves, MultiThreadedExecutor", both([str(lib / "cancelled_timers"), "multi"])),
        ("publish; sleep_for(10ms); spin_some", both([str(lib / "sleep_loop")])),
        ("2 Hz WallRate loop", both([str(lib / "wall_rate_loop")])),
    ]
    print(f"{'median of %d runs (ms)' % args.reps:<58} {'before':>9} {'now':>9} {'now / plain':>12}")
    plain = rows[0][1][1]
    for name, (old, new) in rows:
        print(f"{name:<58} {old:9.1f} {new:9.1f} {new / plain:12.2f}")
    for name, (_, new) in rows[1:4]:
        print(f"  {name} / plain: {new / plain:.2f} (target <= 2: {'met' if new <= 2 * plain else 'NOT met'})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
