"""How long `check --live` takes on a 50-node system, against reading the same graph by hand
(issue 52 item 6).

Fifty rclpy nodes (ten processes of five, each node with a publisher, a subscription of its
neighbour's topic and a service) run on Fast DDS in a ROS_DOMAIN_ID of their own. The contract is
written once from them (`capture --live`). Then, in the same run, alternating so that both see the
same machine:

- **live**: `rmw-introspect check --live robot.system.yaml` from its start to its report (it joins
  the graph, waits until it is stable, reads every node, endpoint, QoS, parameter and lifecycle
  state, and compares);
- **by hand**: what a developer types to see the same endpoints: `ros2 node list`, then `ros2
  topic info -v TOPIC` for every topic. ros2cli has no wheel here, so each command is played by a
  process that does what it does with the daemon off: a new rclpy node joins the graph, waits for
  discovery, asks, prints and leaves. It waits until it sees all 50 nodes and the graph has not
  changed for 0.5 s (at most 20 s): a best case for the manual way, whose commands answer after
  their spin time (0.5 s by default) with whatever part of the graph they found by then. (With the
  ros2 daemon running each command skips discovery; the by-hand column is then an upper bound.)

    python bench/bench_live_check.py [--rounds 3]

Prints the median seconds of each and their ratio (by hand / live).
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import textwrap
import time
from pathlib import Path

from pytest_rmw_introspect.live import bringup
from pytest_rmw_introspect.run.target import TargetSpec

PROCESSES, NODES_PER_PROCESS = 10, 5

NODES = textwrap.dedent('''
    import sys
    import rclpy
    from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
    from std_msgs.msg import String
    from std_srvs.srv import Trigger

    process, per_process, total = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3])
    rclpy.init()
    executor, keep = SingleThreadedExecutor(), []
    for i in range(process * per_process, (process + 1) * per_process):
        node = rclpy.create_node(f"bench_{i:02d}")
        keep += [node.create_publisher(String, f"/bench/t{i:02d}", 10),
                 node.create_subscription(String, f"/bench/t{(i + 1) % total:02d}", lambda _m: None, 10),
                 node.create_service(Trigger, f"/bench/s{i:02d}", lambda _q, r: r)]
        executor.add_node(node)
    try:
        executor.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
''')

BY_HAND = textwrap.dedent('''
    import sys, time
    import rclpy
    rclpy.init()
    node = rclpy.create_node("_bench_cli")
    expected = int(sys.argv[-1])
    seen, stable_since, started = None, time.monotonic(), time.monotonic()
    while time.monotonic() - started < 20.0:
        rclpy.spin_once(node, timeout_sec=0.05)
        now = (tuple(sorted(node.get_node_names_and_namespaces())), tuple(sorted(node.get_topic_names_and_types())))
        if now != seen:
            seen, stable_since = now, time.monotonic()
        elif time.monotonic() - stable_since >= 0.5 and len(now[0]) > expected:
            break
    if sys.argv[1] == "nodes":
        for name, namespace in node.get_node_names_and_namespaces():
            print(namespace.rstrip("/") + "/" + name)
    else:
        topic = sys.argv[2]
        for info in node.get_publishers_info_by_topic(topic) + node.get_subscriptions_info_by_topic(topic):
            print(info.node_name, info.topic_type, info.qos_profile.reliability, info.qos_profile.durability)
    node.destroy_node()
    rclpy.shutdown()
''')


def cli(*args: str, env: dict[str, str], cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "pytest_rmw_introspect", *args], env=env, cwd=cwd,
                          capture_output=True, text=True, timeout=300)


def by_hand(script: Path, env: dict[str, str]) -> float:
    began = time.monotonic()
    expected = str(PROCESSES * NODES_PER_PROCESS)
    listed = subprocess.run([sys.executable, str(script), "nodes", expected], env=env, capture_output=True, text=True,
                            check=True)
    assert len(listed.stdout.split()) >= PROCESSES * NODES_PER_PROCESS, listed.stdout
    topics = [f"/bench/t{i:02d}" for i in range(PROCESSES * NODES_PER_PROCESS)] + ["/rosout", "/parameter_events"]
    for topic in topics:
        subprocess.run([sys.executable, str(script), "topic", topic, expected], env=env, capture_output=True,
                       check=True)
    return time.monotonic() - began


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    work = Path(tempfile.mkdtemp(prefix="bench_live_"))
    (work / "nodes.py").write_text(NODES)
    (work / "by_hand.py").write_text(BY_HAND)
    (work / "robot.launch.xml").write_text("<launch/>\n")  # named by the contract, never run here
    total = PROCESSES * NODES_PER_PROCESS
    system = bringup.start([TargetSpec.from_mapping({"script": str(work / "nodes.py"),
                                                     "arguments": [str(p), str(NODES_PER_PROCESS), str(total)]})
                            for p in range(PROCESSES)])
    try:
        system.wait_until_up(timeout=120, nodes=[f"/bench_{i:02d}" for i in range(total)])
        # the contract from a graph read with a long settle (discovery of 10 processes comes in bursts)
        made = cli("capture", "--live", "--settle", "5", "--launch", "robot.launch.xml", "-o", "robot.system.yaml",
                   env=system.env, cwd=work)
        assert made.returncode == 0, made.stderr
        written = (work / "robot.system.yaml").read_text()
        assert all(f"/bench_{i:02d}:" in written for i in range(total)), "capture --live missed nodes"
        live, hand = [], []
        for _ in range(args.rounds):
            began = time.monotonic()
            checked = cli("check", "--live", "robot.system.yaml", env=system.env, cwd=work)
            live.append(time.monotonic() - began)
            assert checked.returncode == 0, checked.stdout + checked.stderr
            hand.append(by_hand(work / "by_hand.py", system.env))
        print(f"{total} nodes in {PROCESSES} processes, ROS_DOMAIN_ID {system.domain_id}, {args.rounds} rounds")
        print(f"check --live (everything, compared):        {statistics.median(live):6.1f} s  {[round(s, 1) for s in live]}")
        print(f"by hand (node list + topic info -v per topic): {statistics.median(hand):6.1f} s  "
              f"{[round(s, 1) for s in hand]}")
        print(f"ratio by hand / live: {statistics.median(hand) / statistics.median(live):.1f}x")
    finally:
        system.stop()


if __name__ == "__main__":
    main()
