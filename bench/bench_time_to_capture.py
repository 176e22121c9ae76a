"""Time to capture, measured against Fast DDS in the same run.

    python bench/bench_time_to_capture.py [--reps 7]

Targets: the example package's Python `talker` and compiled rcl `c_talker` (installed into the
venv by `make bootstrap`), run exactly as the plugin runs them (``target.environment``: the
middleware preloaded, the wheels' interpreter re-exec skipped, RMW_INTROSPECT_EXIT=1).

Rows (medians, ms):
- recording: spawn -> process exited with its capture written (the plugin's default settle
  is *not* used: the middleware's own default, 10 ms, applies, as for `RMW_INTROSPECT_*` users);
- Fast DDS: spawn -> a second, already running rclpy process sees the node's /chatter
  publisher through get_publisher_names_and_types_by_node (the usual way to learn a node's
  interfaces without this tool); the ratio is Fast DDS time / recording time;
- floors, to show what the middleware itself costs: `python -c 'import rclpy'`; the same
  talker code that exits right after creating its node and publisher (imports + node set-up,
  on the recording middleware with nothing written); and a C program that links librcl and
  returns at once (the dynamic loader's share of every C node).
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import sysconfig
import tempfile
import time
from pathlib import Path

from pytest_rmw_introspect.run import middleware, ros_env, target

PY = sys.executable
PACKAGE = "rmw_introspect_examples"

OBSERVER = r"""
import sys, time
import rclpy
from rclpy.node import Node
rclpy.init()
n = Node("bench_observer")
print("ready", flush=True)
target, ns, topic = sys.argv[1], sys.argv[2], sys.argv[3]
sys.stdin.readline()
while True:
    try:
        if any(t.endswith(topic) for t, _ in n.get_publisher_names_and_types_by_node(target, ns)):
            break
    except Exception:
        pass
    time.sleep(0.002)
print("found", flush=True)
"""

NODE_SETUP_ONLY = r"""
import os
import rclpy
from rclpy.node import Node
from std_msgs.msg import String
rclpy.init()
node = Node("talker")
node.create_publisher(String, "chatter", 10)
node.create_timer(0.5, lambda: None)
os._exit(0)  # the way the middleware ends a settled process: no interpreter finalization
"""

LINK_ONLY_C = "int main(void) { return 0; }\n"


def recording_env(library: Path, ros: ros_env.RosEnvironment, output: Path, **extra: str) -> dict[str, str]:
    spec = target.TargetSpec(command=("true",))
    env = target.environment(spec, library, ros, output)
    env["RMW_INTROSPECT_SETTLE_MS"] = extra.pop("settle_ms", "10")
    env.update(extra)
    return env


def timed(argv: list[str], env: dict[str, str]) -> float:
    t0 = time.monotonic()
    subprocess.run(argv, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    return (time.monotonic() - t0) * 1000


def run_recording(argv: list[str], library: Path, ros: ros_env.RosEnvironment) -> float:
    with tempfile.TemporaryDirectory() as d:
        out = Path(d) / "capture.json"
        ms = timed(argv, recording_env(library, ros, out))
        if not out.exists():
            raise RuntimeError(f"{argv[0]} wrote no capture")
        return ms


def run_fastdds(argv: list[str], node_name: str, ros: ros_env.RosEnvironment, topic: str = "chatter") -> float:
    """Spawn -> a second, already running rclpy process sees the node's `topic` publisher (ms)."""
    env = dict(os.environ)
    env["LD_LIBRARY_PATH"] = ros.library_path(env.get("LD_LIBRARY_PATH"))
    env["_ROS_WHEELS_BOOTSTRAP_COMPLETE"] = "1"
    env["ROS_DOMAIN_ID"] = "91"
    for key in ("LD_PRELOAD", "RMW_IMPLEMENTATION"):
        env.pop(key, None)
    observer = subprocess.Popen([PY, "-c", OBSERVER, node_name, "/", topic], env=env, stdin=subprocess.PIPE,
                                stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    try:
        if observer.stdout.readline().strip() != "ready":
            raise RuntimeError("the observer did not start")
        observer.stdin.write("go\n")
        observer.stdin.flush()
        t0 = time.monotonic()
        node = subprocess.Popen(argv, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        line = observer.stdout.readline()
        ms = (time.monotonic() - t0) * 1000
        node.kill()
        node.wait()
    finally:
        observer.kill()
        observer.wait()
    if line.strip() != "found":
        raise RuntimeError(f"the observer never saw {node_name}")
    return ms


def build_link_only_c(ros: ros_env.RosEnvironment, workdir: Path) -> Path:
    """A C program that links librcl like a C node does and returns at once."""
    src, exe = workdir / "link_only.c", workdir / "link_only"
    src.write_text(LINK_ONLY_C)
    rpaths = [f"-Wl,-rpath,{d}" for d in ros.library_dirs]
    pylib = sysconfig.get_config_var("LIBDIR")
    subprocess.run(
        ["cc", str(src), "-o", str(exe), f"-L{ros.prefix / 'lib'}", "-Wl,--no-as-needed", "-lrcl",
         "-Wl,--allow-shlib-undefined", *rpaths, f"-L{pylib}", f"-Wl,-rpath,{pylib}",
         f"-lpython{sysconfig.get_config_var('LDVERSION')}"],
        check=True,
    )
    return exe


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--reps", type=int, default=7)
    args = parser.parse_args()

    ros = ros_env.detect()
    library = middleware.ensure_library(ros)
    prefixes = ros_env.ament_prefixes(ros.ament_prefixes)
    talker = str(target.find_executable(PACKAGE, "talker", prefixes))
    c_talker = str(target.find_executable(PACKAGE, "c_talker", prefixes))

    def median(measure) -> float:
        measure()  # warm-up: page cache, Python bytecode
        return statistics.median(measure() for _ in range(args.reps))

    with tempfile.TemporaryDirectory() as d:
        quiet = recording_env(library, ros, Path(d) / "unused.json", RMW_INTROSPECT_AUTO_EXPORT="0")
        link_only = build_link_only_c(ros, Path(d))
        floor_import = median(lambda: timed([PY, "-c", "import rclpy"], quiet))
        floor_node = median(lambda: timed([PY, "-c", NODE_SETUP_ONLY], quiet))
        floor_c = median(lambda: timed([str(link_only)], quiet))
    py_rec = median(lambda: run_recording([talker], library, ros))
    py_dds = median(lambda: run_fastdds([talker], "talker", ros))
    c_rec = median(lambda: run_recording([c_talker], library, ros))
    c_dds = median(lambda: run_fastdds([c_talker], "c_talker", ros))

    rows = [
        ("floor: python -c 'import rclpy'", floor_import, ""),
        ("floor: talker code, node set up then exit (no capture)", floor_node, ""),
        ("floor: C program linking librcl, returns at once", floor_c, ""),
        ("Python talker, recording (spawn -> exit, capture written)", py_rec, ""),
        ("Python talker, Fast DDS (spawn -> seen by another process)", py_dds, f"{py_dds / py_rec:.2f}x"),
        ("C talker, recording (spawn -> exit, capture written)", c_rec, ""),
        ("C talker, Fast DDS (spawn -> seen by another process)", c_dds, f"{c_dds / c_rec:.2f}x"),
    ]
    print(f"{'median of %d runs' % args.reps:<62} {'ms':>8} {'Fast DDS / recording':>21}")
    for name, ms, ratio in rows:
        print(f"{name:<62} {ms:8.1f} {ratio:>21}")
    print()
    print(f"Python talker above the import-rclpy floor:        {py_rec - floor_import:6.1f} ms")
    print(f"Python talker above its own set-up (middleware):   {py_rec - floor_node:6.1f} ms")
    print(f"C talker above the librcl load floor (middleware): {c_rec - floor_c:6.1f} ms")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
