"""Time to capture: a node on the recording middleware (spawn -> exited with the capture
written) versus the same node on Fast DDS found by a second rclpy process polling
get_publisher_names_and_types_by_node; plus the `python -c 'import rclpy'` floor.

    python bench/bench_time_to_capture.py [--reps 5] [--library PATH] [--c-node PATH]

Prints a table of medians (ms) and ratios.
"""
from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests" / "middleware"))
import rmwi_helpers as h  # noqa: E402

PY = sys.executable
TALKER = REPO / "tests" / "middleware" / "nodes" / "talker.py"

OBSERVER = r"""
import sys, time
import rclpy
from rclpy.node import Node
rclpy.init()
n = Node("bench_observer")
print("ready", flush=True)
target, ns = sys.argv[1], sys.argv[2]
sys.stdin.readline()
t0 = time.monotonic()
while True:
    try:
        names = [t for t, _ in n.get_publisher_names_and_types_by_node(target, ns)]
        if any(x.endswith("chatter") for x in names):
            break
    except Exception:
        pass
    time.sleep(0.002)
print(f"found {time.monotonic() - t0:.6f}", flush=True)
"""


def run_recording(argv, library):
    with tempfile.TemporaryDirectory() as d:
        out = Path(d) / "c.json"
        env = h.ros_environment({"LD_PRELOAD": str(library), "RMW_INTROSPECT_EXIT": "1",
                                 "RMW_INTROSPECT_OUTPUT": str(out)})
        t0 = time.monotonic()
        subprocess.run(argv, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
        wall = time.monotonic() - t0
        assert out.exists()
        return wall * 1000


def run_fastdds(argv, node_name, namespace="/"):
    env = h.ros_environment({"ROS_DOMAIN_ID": "91"})
    obs = subprocess.Popen([PY, "-c", OBSERVER, node_name, namespace], env=env, stdin=subprocess.PIPE,
                           stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    assert obs.stdout.readline().strip() == "ready"
    obs.stdin.write("go\n")
    obs.stdin.flush()
    t0 = time.monotonic()
    target = subprocess.Popen(argv, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    line = obs.stdout.readline()
    wall = time.monotonic() - t0
    target.kill()
    target.wait()
    obs.kill()
    obs.wait()
    assert line.startswith("found"), line
    return wall * 1000


def floor():
    env = h.ros_environment()
    t0 = time.monotonic()
    subprocess.run([PY, "-c", "import rclpy"], env=env, check=True)
    return (time.monotonic() - t0) * 1000


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--library", type=Path)
    ap.add_argument("--c-node", type=Path)
    args = ap.parse_args()
    library = args.library
    if library is None:
        from pytest_rmw_introspect.middleware import ensure_library
        library = ensure_library()
    rows = []
    med = lambda f: statistics.median(f() for _ in range(args.reps))  # noqa: E731
    t_floor = med(floor)
    rows.append(("python -c 'import rclpy' (floor)", t_floor, None))
    t_py = med(lambda: run_recording([PY, str(TALKER)], library))
    t_py_dds = med(lambda: run_fastdds([PY, str(TALKER)], "talker"))
    rows.append(("Python talker, recording (spawn->exit+capture)", t_py, None))
    rows.append(("Python talker, Fast DDS (spawn->discovered)", t_py_dds, t_py_dds / t_py))
    if args.c_node:
        t_c = med(lambda: run_recording([str(args.c_node)], library))
        rows.append(("C node, recording (spawn->exit+capture)", t_c, None))
        t_c_dds = med(lambda: run_fastdds([str(args.c_node)], "c_talker", "/c"))
        rows.append(("C node, Fast DDS (spawn->discovered)", t_c_dds, t_c_dds / t_c))
    print(f"{'measurement (median of %d)' % args.reps:<52} {'ms':>8} {'Fast DDS / recording':>22}")
    for name, ms, ratio in rows:
        print(f"{name:<52} {ms:8.1f} {('%.2fx' % ratio) if ratio else '':>22}")
    print(f"Python talker above the import-rclpy floor: {t_py - t_floor:.1f} ms")


if __name__ == "__main__":
    main()
