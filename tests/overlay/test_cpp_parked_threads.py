"""Threads parked in rmw_wait do not make a busy thread look idle (issue 50 item 1), on rclcpp
built in the overlay: late_starter (tests/overlay/tf2_nodes) runs with use_sim_time:=true, so
rclcpp's clock thread waits in rmw_wait from the start, beside a TransformListener's spin thread
and a MultiThreadedExecutor spinning another node; its main thread then sleeps in
rclcpp::Rate(2).sleep() (a timed wait on the real clock) before it declares its parameters and
creates a publisher, as diagnostic_updater's example does. Before, the capture settled at ~20 ms
with the main thread counted idle, and the parameters could not be read ("no executor serves
/late_starter/list_parameters"), and nothing said that virtual time stopped far short of its
horizon."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
from overlay_support import REPO, cmake_build, with_prefix

CLI = [sys.executable, "-m", "pytest_rmw_introspect"]
SOURCES = REPO / "tests" / "overlay" / "tf2_nodes"

# the first test of a session may build the program (minutes on 2 cores)
pytestmark = pytest.mark.timeout(1800)


def test_a_sim_time_node_with_parked_threads_gets_its_parameters_with_default_settings(overlay):
    if not (overlay.install / "share" / "tf2_ros").is_dir():
        pytest.skip("the overlay has no tf2_ros: rebuild it with the ros2/geometry2 and ros2/message_filters "
                    "checkouts (docs/overlay.md)")
    prefix = cmake_build(overlay, SOURCES, "tf2_nodes") / "install"
    program = prefix / "lib" / "rmwi_tf2_nodes" / "late_starter"
    out = subprocess.run([*CLI, "capture", "--raw", "--format", "json", "--", str(program),
                          "--ros-args", "-p", "use_sim_time:=true"],
                         env=with_prefix(overlay.env(), prefix), capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)
    nodes = {n["fqn"]: n for n in doc["nodes"]}
    late = nodes["/late_starter"]
    assert late["parameters_error"] is None, late["parameters_error"]
    parameters = {p["name"]: p["value"] for p in late["parameters"]}
    assert parameters["use_sim_time"] is True
    assert {"min_freq", "max_freq"} <= set(parameters), sorted(parameters)
    publishers = {e["name"] for e in doc["endpoints"] if e["kind"] == "publisher" and e["node"] == "/late_starter"}
    assert {"/topic1", "/after_rate"} <= publishers, sorted(publishers)
    assert doc["time_to_settle_ms"] >= 450  # after the main thread's Rate(2).sleep(), not at ~20 ms
    assert doc["probe"]["unanswered"] == 0, doc["probe"]
    # Its loop sleeps in Rate(2).sleep(), which virtual time does not step: the idle proof ends the
    # warp far short of the horizon, and a note says so and why.
    assert doc["time"]["warp_real_waits"] is True and not doc["time"]["horizon_reached"], doc["time"]
    (note,) = [line for line in out.stderr.splitlines() if line.startswith("note: virtual time stopped")]
    assert "the idle proof ended it while a thread of the program waited on the real clock" in note, note
