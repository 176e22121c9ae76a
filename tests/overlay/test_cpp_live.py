"""The live check as an independent truth for the rclcpp programs of the overlay tier (issue 52
item 5): every C++ example node runs on Fast DDS over the overlay (RMW_IMPLEMENTATION unset, one
ROS_DOMAIN_ID of its own, localhost discovery), and one `check --live` run compares the graph
with the nodes' contracts, which are the recording middleware's captures. Beyond the notes on what
a live graph cannot show, the one difference is the lifecycle node nobody drives: a capture drives
it to `active`, here it stays `unconfigured`, without the publisher it creates on activation.
The same for the C++ example robot's launch file (a component container, a lifecycle node, an
action server), run by launch_ros as `ros2 launch` runs it. And the tier's timing programs (spin_some
loops, self-cancelling timers, sleep and WallRate loops, parked threads under sim time), each
captured and then checked live: no difference at all. About 7 s each on a shared 2-core machine
(15 s for the timing programs, captured first), the builds aside (shared with the tier)."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from overlay_support import CPP_EXAMPLES, REPO, cmake_build, stop, with_prefix

from pytest_rmw_introspect.live import bringup

PACKAGE = "rmw_introspect_examples_cpp"
CONTRACTS = sorted((CPP_EXAMPLES / "contracts").glob("*.interfaces.yaml"))
#: what the live check finds, by contract (every other contract matches)
EXPECTED = {"lifecycle_talker.interfaces.yaml": {"LIFECYCLE_STATE_CHANGED", "PUB_REMOVED"}}
pytestmark = pytest.mark.timeout(1800)  # the first test of a session may build the C++ examples


def check_running(programs: list[list[str]], contracts: list[Path], env: dict[str, str]) -> tuple[
        subprocess.CompletedProcess, int]:
    """``programs`` run on Fast DDS in a domain of their own (localhost discovery), checked live
    against ``contracts`` in one `check --live --format json` run; every program still running when
    it ended, then stopped. (The check's result, the domain id.)"""
    domain = bringup.reserve_domain()
    live_env = bringup.isolated_env(domain.id, env)
    running = [subprocess.Popen(command, env=live_env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                start_new_session=True) for command in programs]
    try:
        result = subprocess.run([sys.executable, "-m", "pytest_rmw_introspect", "check", "--live", *map(str, contracts),
                                 "--format", "json"], env=live_env, capture_output=True, text=True, timeout=180)
        assert all(p.poll() is None for p in running), [p.args for p in running if p.poll() is not None]
    finally:
        stop(running)
        domain.release()
    return result, domain.id


def test_every_cpp_example_node_runs_on_fast_dds_as_its_capture_says(overlay, cpp_examples):
    programs = [[str(cpp_examples / "lib" / PACKAGE / p.name.removesuffix(".interfaces.yaml"))] for p in CONTRACTS]
    result, domain_id = check_running(programs, CONTRACTS, with_prefix(overlay.env(), cpp_examples))
    assert result.returncode == 1, result.stdout + result.stderr
    found: dict[str, set[str]] = {}
    for item in json.loads(result.stdout):
        found.setdefault(os.path.basename(item["contract"]), set()).add(item["rule"])
    assert found == EXPECTED, (found, result.stderr)
    assert f"joined ROS_DOMAIN_ID {domain_id} on rmw_fastrtps_cpp" in result.stderr, result.stderr


#: launch_ros's own LaunchService runs a launch file as `ros2 launch` does (the overlay has launch_ros)
LAUNCH = """
import sys
from launch import LaunchDescription, LaunchService
from launch.actions import IncludeLaunchDescription
from launch.launch_description_sources import PythonLaunchDescriptionSource
service = LaunchService()
service.include_launch_description(LaunchDescription([IncludeLaunchDescription(
    PythonLaunchDescriptionSource(sys.argv[1]))]))
sys.exit(service.run())
"""


def test_the_cpp_example_robot_with_its_components_runs_on_fast_dds_as_its_system_contract_says(overlay, cpp_examples):
    """launch/robot.launch.py as `ros2 launch` runs it (its container loads the talker and listener
    as components, which the pytest bring-up cannot), checked live against robot.system.yaml."""
    domain = bringup.reserve_domain()
    env = bringup.isolated_env(domain.id, with_prefix(overlay.env(), cpp_examples))
    launch_file = cpp_examples / "share" / PACKAGE / "launch" / "robot.launch.py"
    robot = subprocess.Popen([sys.executable, "-c", LAUNCH, str(launch_file)], env=env, stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, start_new_session=True)
    try:
        result = subprocess.run([sys.executable, "-m", "pytest_rmw_introspect", "check", "--live",
                                 str(CPP_EXAMPLES / "contracts" / "robot.system.yaml"), "--format", "junit"],
                                env=env, capture_output=True, text=True, timeout=180)
        assert robot.poll() is None, robot.communicate()[0].decode(errors="replace")
    finally:
        stop([robot])
        domain.release()
    # (JUnit XML: the findings, failing or not, and the notes of the read in one document)
    [case] = ET.fromstring(result.stdout).iter("testcase")
    lines = [*(case.findtext("failure") or "").splitlines(), *(p.get("value") for p in case.iter("property"))]
    found = sorted({tuple(m.groups()) for line in lines if (m := re.match(r"\[(\w+)\] \w+ (\S+)", line))})
    # what differs is the lifecycle node nobody drives (a capture drives it to active); `ros2 launch`'s
    # own node (launch_ros_<pid>) is left out of the graph and said so
    assert found == [("LIFECYCLE_STATE_CHANGED", "/robot/lifecycle_talker"), ("PUB_REMOVED", "/robot/lifecycle_talker")], \
        result.stdout
    assert any("was in the graph, left out of it: /launch_ros_" in line for line in lines), result.stdout


#: the overlay tier's other rclcpp programs (tests/overlay/cpp_polling and tf2_nodes): fixtures of the
#: capture's settle timing (spin_some loops, self-cancelling timers, sleep_for and WallRate loops,
#: parked threads under sim time) with no contract files of their own
POLLING = ["action_poller", "cancelled_timers", "sleep_loop", "wall_rate_loop"]


def test_the_overlay_timing_programs_run_on_fast_dds_as_their_captures_say(overlay, tmp_path):
    """Each program captured on the recording middleware into a node contract, then all of them run
    on Fast DDS and checked live against those contracts: the warp, the idle proofs and the
    probes change how a capture waits, not what it records."""
    polling = cmake_build(overlay, REPO / "tests" / "overlay" / "cpp_polling", "cpp_polling") / "install"
    programs = [[str(polling / "lib" / "rmwi_cpp_polling" / name)] for name in POLLING]
    env = overlay.env()
    if (overlay.install / "share" / "tf2_ros").is_dir():  # late_starter needs tf2_ros in the overlay
        tf2 = cmake_build(overlay, REPO / "tests" / "overlay" / "tf2_nodes", "tf2_nodes") / "install"
        programs.append([str(tf2 / "lib" / "rmwi_tf2_nodes" / "late_starter"), "--ros-args", "-p", "use_sim_time:=true"])
        env = with_prefix(env, tf2)
    contracts = []
    for command in programs:
        contract = tmp_path / f"{os.path.basename(command[0])}.interfaces.yaml"
        captured = subprocess.run([sys.executable, "-m", "pytest_rmw_introspect", "capture", "-o", str(contract), "--",
                                   *command], env=env, capture_output=True, text=True, timeout=120)
        assert captured.returncode == 0, captured.stderr
        contracts.append(contract)
    result, _ = check_running(programs, contracts, env)
    assert result.returncode == 0 and json.loads(result.stdout) == [], result.stdout + result.stderr
