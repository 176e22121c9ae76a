"""TF's node names that change every run (issue 43), on tf2_ros built from ros2/geometry2 in the
overlay: an rclcpp node with a tf2_ros::TransformListener (whose own node is
transform_listener_impl_<address>), tf2_ros's static_transform_publisher
(static_transform_publisher_<16 random characters>) and buffer_server (a listener too). Each is
captured once, then checked ten times in a row with no drift; a real rename still drifts."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
import yaml
from overlay_support import REPO, cmake_build, with_prefix

CLI = [sys.executable, "-m", "pytest_rmw_introspect"]
SOURCES = REPO / "tests" / "overlay" / "tf2_nodes"
CHECKS = 10
LISTENER = "/transform_listener_impl_*"

# the first test of a session may build the program (minutes on 2 cores)
pytestmark = pytest.mark.timeout(1800)


@pytest.fixture(scope="module")
def tf2(overlay):
    """The overlay's environment with tf_reader installed on top (skipped: an overlay without tf2_ros)."""
    if not (overlay.install / "share" / "tf2_ros").is_dir():
        pytest.skip("the overlay has no tf2_ros: rebuild it with the ros2/geometry2 and ros2/message_filters "
                    "checkouts (docs/overlay.md)")
    prefix = cmake_build(overlay, SOURCES, "tf2_nodes") / "install"
    return with_prefix(overlay.env(), prefix), prefix / "lib" / "rmwi_tf2_nodes"


def cli(env: dict[str, str], cwd: Path, *args: object) -> subprocess.CompletedProcess[str]:
    return subprocess.run([*CLI, *map(str, args)], cwd=cwd, env=env, capture_output=True, text=True, timeout=300,
                          check=False)


def capture_then_check(env: dict[str, str], cwd: Path, *target: object) -> dict:
    """Capture ``target`` into ``tf.interfaces.yaml``, check it ten times (no drift), return its nodes."""
    captured = cli(env, cwd, "capture", "-o", "tf.interfaces.yaml", *target)
    assert captured.returncode == 0, captured.stderr
    for attempt in range(CHECKS):
        checked = cli(env, cwd, "check", "tf.interfaces.yaml")
        assert checked.returncode == 0, f"check {attempt + 1} of {CHECKS} drifted:\n{checked.stdout}{checked.stderr}"
    return yaml.safe_load((cwd / "tf.interfaces.yaml").read_text())["nodes"]


def topics(node: dict, kind: str) -> list[str]:
    return sorted(e["name"] for e in node[kind])


def renamed(env: dict[str, str], cwd: Path, name: str) -> str:
    """The report of a check with the node renamed (``--node-name``): it must drift."""
    checked = cli(env, cwd, "check", "tf.interfaces.yaml", "--node-name", name)
    assert checked.returncode == 1, checked.stdout + checked.stderr
    return checked.stdout


def test_an_rclcpp_node_with_a_transform_listener(tf2, tmp_path):
    env, programs = tf2
    nodes = capture_then_check(env, tmp_path, "--", programs / "tf_reader")
    assert sorted(nodes) == sorted([LISTENER, "/tf_reader"])
    assert "TransformListener" in nodes[LISTENER]["unstable_name"]
    assert topics(nodes[LISTENER], "subscriptions") == ["/tf", "/tf_static"]
    # the listener's node keeps its own name: only the reader's is renamed
    report = renamed(env, tmp_path, "other_reader")
    assert "/tf_reader" in report and "/other_reader" in report and LISTENER not in report


def test_two_listeners_in_one_process_are_compared_as_a_set(tf2, tmp_path):
    env, programs = tf2
    nodes = capture_then_check(env, tmp_path, "--", programs / "tf_reader", "--two")
    assert sorted(nodes) == sorted([LISTENER, LISTENER + "#2", "/tf_reader"])


def test_static_transform_publisher(tf2, tmp_path):
    env, _programs = tf2
    nodes = capture_then_check(env, tmp_path, "--package", "tf2_ros", "--executable", "static_transform_publisher",
                               "--arg=--x", "--arg=1.5", "--arg=--frame-id", "--arg=map",
                               "--arg=--child-frame-id", "--arg=base_link")
    [key] = nodes
    assert key == "/static_transform_publisher_*" and "16 random" in nodes[key]["unstable_name"]
    assert topics(nodes[key], "publishers") == ["/tf_static"]
    # named by the command line, it is a node of another name: drift
    report = renamed(env, tmp_path, "map_to_base_link")
    assert "/static_transform_publisher_*" in report and "/map_to_base_link" in report


def test_buffer_server(tf2, tmp_path):
    env, _programs = tf2
    nodes = capture_then_check(env, tmp_path, "--package", "tf2_ros", "--executable", "buffer_server")
    assert sorted(nodes) == sorted([LISTENER, "/tf_buffer"])
    assert [e["name"] for e in nodes["/tf_buffer"]["action_servers"]] == ["/tf2_buffer_server"]
    report = renamed(env, tmp_path, "tf_buffer2")
    assert "/tf_buffer" in report and "/tf_buffer2" in report
