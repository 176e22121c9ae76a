"""The rclcpp talker's time to capture, against its own set-up floor and against Fast DDS.

    python bench/bench_cpp_talker.py [--reps 7]      (also run by `make bench`)

Needs the C++ and launch overlay (`make overlay`, docs/overlay.md); without
one it says so and exits 0. It re-runs itself in the overlay's environment, where the plugin
activates the middleware as on a standard install (RMW_IMPLEMENTATION plus the preload), and
builds the C++ example package over the overlay (once, cached).

Rows (medians, ms):
- floor: the talker constructs its node (parameters, publisher, timer) and ends at once without
  teardown (`--exit-after-setup`: `_Exit`, as the middleware ends a settled process), on the
  recording middleware with nothing written: what the program itself costs, loader and rclcpp
  included;
- recording: spawn -> process exited with its capture written (as the plugin runs it, with the
  middleware's default 10 ms settle); the ratio to the floor is the middleware's overhead
  (target <= 1.2x);
- Fast DDS: spawn -> a second, already running rclpy process sees the talker's /chatter
  publisher (bench_time_to_capture.py's observer); the ratio is Fast DDS time / recording time.
"""

from __future__ import annotations

import statistics
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(REPO / "tests" / "overlay"), str(REPO / "tests" / "support")]

import overlay_support  # noqa: E402
from bench_time_to_capture import recording_env, run_fastdds, run_recording, timed  # noqa: E402

from pytest_rmw_introspect.run import middleware, ros_env  # noqa: E402


def main() -> int:
    started = overlay_support.start_bench("bench_cpp_talker", __doc__, reps=7)
    if started is None:
        return 0
    args, _, examples = started

    ros = ros_env.detect()
    library = middleware.ensure_library(ros)
    talker = str(examples / "lib" / "rmw_introspect_examples_cpp" / "talker")

    def median(measure) -> float:
        measure()  # warm-up: page cache
        return statistics.median(measure() for _ in range(args.reps))

    with tempfile.TemporaryDirectory() as d:
        quiet = recording_env(library, ros, Path(d) / "unused.json", RMW_INTROSPECT_AUTO_EXPORT="0")
        floor = median(lambda: timed([talker, "--exit-after-setup"], quiet))
    recording = median(lambda: run_recording([talker], library, ros))
    fastdds = median(lambda: run_fastdds([talker], "talker", ros))
    print(f"{'median of %d runs (%s install over the wheels)' % (args.reps, ros.kind):<62} {'ms':>8} {'ratio':>21}")
    print(f"{'floor: rclcpp talker, node set up then exit (no capture)':<62} {floor:8.1f} {'':>21}")
    print(f"{'rclcpp talker, recording (spawn -> exit, capture written)':<62} {recording:8.1f} "
          f"{f'{recording / floor:.2f}x the floor':>21}")
    print(f"{'rclcpp talker, Fast DDS (spawn -> seen by another process)':<62} {fastdds:8.1f} "
          f"{f'{fastdds / recording:.2f}x recording':>21}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
