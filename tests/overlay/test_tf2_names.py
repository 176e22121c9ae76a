"""TF's node names that change every run (issue 43), on tf2_ros built from ros2/geometry2 in the
overlay: an rclcpp node with a tf2_ros::TransformListener (whose own node is
transform_listener_impl_<address>), tf2_ros's static_transform_publisher
(static_transform_publisher_<16 random characters>) and buffer_server (a listener too). Each is
captured once, then checked ten times in a row with no drift; a real rename still drifts. All
three, running on Fast DDS, also check live against their captures (the patterns match)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
import yaml
from overlay_support import REPO, cmake_build, stop, with_prefix

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



def test_the_tf_programs_run_on_fast_dds_as_their_captures_say(tf2, overlay, tmp_path):
    """The live check as an independent truth for these rclcpp programs (issue 52 item 5): each is
    captured on the recording middleware, then all run together on Fast DDS (a domain of their own)
    and one `check --live` compares the graph with the captures: the names that change every run
    (``/transform_listener_impl_*``, ``/static_transform_publisher_*``) are matched by the contracts'
    patterns, and nothing differs."""
    import json

    from pytest_rmw_introspect.live import bringup

    env, programs = tf2
    tf2_ros = overlay.install / "lib" / "tf2_ros"
    static = ["--x", "1.5", "--frame-id", "map", "--child-frame-id", "base_link"]
    targets = {"reader": ([programs / "tf_reader"], ["--", programs / "tf_reader"]),
               "static": ([tf2_ros / "static_transform_publisher", *static],
                          ["--package", "tf2_ros", "--executable", "static_transform_publisher",
                           *(f"--arg={a}" for a in static)]),
               "buffer": ([tf2_ros / "buffer_server"], ["--package", "tf2_ros", "--executable", "buffer_server"])}
    for name, (_argv, target) in targets.items():
        captured = cli(env, tmp_path, "capture", "-o", f"{name}.interfaces.yaml", *target)
        assert captured.returncode == 0, captured.stderr
    domain = bringup.reserve_domain()
    live_env = bringup.isolated_env(domain.id, env)
    running = [subprocess.Popen([str(a) for a in argv], env=live_env, stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL, start_new_session=True) for argv, _ in targets.values()]
    try:
        checked = subprocess.run([*CLI, "check", "--live", *(f"{name}.interfaces.yaml" for name in targets),
                                  "--format", "json"], cwd=tmp_path, env=live_env, capture_output=True, text=True,
                                 timeout=180, check=False)
        assert all(process.poll() is None for process in running), [p.args for p in running if p.poll() is not None]
    finally:
        stop(running)
        domain.release()
    assert (checked.returncode, json.loads(checked.stdout or "null")) == (0, []), checked.stdout + checked.stderr
