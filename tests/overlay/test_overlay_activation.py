"""The standard activation path in the overlay: RMW_IMPLEMENTATION selects the middleware through
rmw_implementation for rclpy, rclcpp and C (rcl) nodes, as on /opt/ros/jazzy, and the plugin's
detection (run/ros_env.py) sees the overlay as a standard install over the wheels."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from overlay_support import Overlay

from pytest_rmw_introspect.run import middleware

# the first test of a session may build the middleware and the C++ examples over the overlay
pytestmark = pytest.mark.timeout(1800)

IDENTIFIER = ("import rclpy; from rclpy.utilities import get_rmw_implementation_identifier as i; "
              "rclpy.init(); print(i()); rclpy.shutdown()")


@pytest.fixture(scope="module")
def library(overlay: Overlay) -> Path:
    """The middleware built for the overlay (the plugin's own build, run in the overlay's environment)."""
    out = subprocess.run([sys.executable, "-m", "pytest_rmw_introspect.run.middleware"], env=overlay.env(),
                         capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    return Path(out.stdout.strip().splitlines()[-1])


def selected(overlay: Overlay, library: Path, extra: dict[str, str] | None = None) -> dict[str, str]:
    """The overlay's environment selecting the middleware by name alone, no LD_PRELOAD: its
    install prefix sourced like a workspace's (rmw_implementation dlopens librmw_<name>.so by name)."""
    env = overlay.env(extra)
    env["RMW_IMPLEMENTATION"] = "rmw_introspect_cpp"
    env["AMENT_PREFIX_PATH"] = f"{library.parent.parent}:{env['AMENT_PREFIX_PATH']}"
    env["LD_LIBRARY_PATH"] = f"{library.parent}:{env['LD_LIBRARY_PATH']}"
    return env


def capture_by_name(overlay: Overlay, library: Path, command: list[str], tmp_path: Path) -> dict:
    """Run ``command`` with the middleware selected by RMW_IMPLEMENTATION only; its capture."""
    output = tmp_path / "capture.json"
    env = selected(overlay, library, {"RMW_INTROSPECT_OUTPUT": str(output), "RMW_INTROSPECT_FORMAT": "json",
                                      "RMW_INTROSPECT_EXIT": "1", "RMW_INTROSPECT_AUTO_EXPORT": "1",
                                      "RMW_INTROSPECT_SETTLE_MS": "200", "RMW_INTROSPECT_HORIZON_MS": "0",
                                      "ROS_LOG_DIR": str(tmp_path / "log")})
    run = subprocess.run(command, env=env, capture_output=True, text=True, timeout=60)
    assert output.exists(), f"no capture from {command} (exit {run.returncode}):\n{run.stderr[-3000:]}"
    return json.loads(output.read_text())


def publishers(capture: dict, node: str) -> list[str]:
    """The topics ``node`` (a fully qualified name) publishes in a raw capture."""
    return sorted(e["name"] for e in capture["endpoints"] if e["kind"] == "publisher" and e["node"] == node)


def test_rclpy_in_the_overlay_runs_on_whatever_rmw_implementation_names(overlay, library):
    # the overlay's rclpy (the wheels' copy, relinked) asks rmw_implementation, like /opt/ros/jazzy's
    default = subprocess.run([sys.executable, "-c", IDENTIFIER], env=overlay.env(), capture_output=True, text=True)
    assert default.stdout.split() == ["rmw_fastrtps_cpp"], default.stderr
    ours = subprocess.run([sys.executable, "-c", IDENTIFIER], env=selected(overlay, library),
                          capture_output=True, text=True)
    assert ours.stdout.split() == ["rmw_introspect_cpp"], ours.stderr


def test_the_venv_without_the_overlay_still_binds_fast_dds(overlay, library):
    # the wheels themselves are unchanged: there only the preload can select the middleware
    env = {k: v for k, v in selected(overlay, library).items() if k not in {"PYTHONPATH", "LD_LIBRARY_PATH"}}
    env.pop("_ROS_WHEELS_BOOTSTRAP_COMPLETE")
    plain = subprocess.run([sys.executable, "-c", IDENTIFIER], env=env, capture_output=True, text=True)
    assert "rmw_introspect_cpp" not in plain.stdout


def test_an_rclpy_node_is_captured_through_rmw_implementation(overlay, library, tmp_path):
    capture = capture_by_name(overlay, library, [str(Path(sys.prefix) / "lib" / "rmw_introspect_examples" / "talker")],
                              tmp_path)
    assert "/chatter" in publishers(capture, "/talker")


def test_a_c_node_is_captured_through_rmw_implementation(overlay, library, c_node, tmp_path):
    capture = capture_by_name(overlay, library, [str(c_node)], tmp_path)
    assert capture["rmw_implementation"] == "rmw_introspect_cpp"
    assert capture["nodes"], capture


def test_an_rclcpp_node_is_captured_through_rmw_implementation(overlay, library, cpp_examples, tmp_path):
    capture = capture_by_name(overlay, library, [str(cpp_examples / "lib" / "rmw_introspect_examples_cpp" / "talker")],
                              tmp_path)
    assert "/chatter" in publishers(capture, "/talker")


def test_the_plugin_detects_the_overlay_as_a_standard_install_over_the_wheels(overlay):
    code = ("from pytest_rmw_introspect.run import ros_env; r = ros_env.detect(); "
            "print(r.kind, r.prefix, r.wheels_underlay, r.library_dirs[0])")
    out = subprocess.run([sys.executable, "-c", code], env=overlay.env(), capture_output=True, text=True)
    assert out.stdout.split() == ["system", str(overlay.install), "True", str(overlay.install / "lib")], out.stderr
    plain = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                           env={k: v for k, v in overlay.env().items() if k != "AMENT_PREFIX_PATH"})
    assert plain.stdout.split()[0] == "wheels", plain.stderr


def test_the_middleware_library_of_the_overlay_is_its_own_build(overlay, library):
    # built against the overlay's prefix, cached apart from the wheels' build
    assert library.is_file()
    assert library.parent.parent.parent.parent == middleware.cache_root()


def test_the_overlays_console_scripts_run_from_any_venv_of_the_lock(overlay: Overlay):
    """The overlay is shared by every venv made from the same lock, so its console scripts (colcon)
    must not name the interpreter of the venv it happened to be built with: that venv may be gone."""
    named = {script.name: script.read_bytes().split(b"\n", 1)[0].decode(errors="replace")
             for script in (overlay.install / "bin").iterdir()
             if script.is_file() and script.read_bytes().startswith(b"#!")}
    assert "colcon" in named
    pinned = {name: line for name, line in named.items() if not line.startswith("#!/usr/bin/env ") and not line.startswith("#!/bin/")}
    assert pinned == {}
    usage = subprocess.run(["colcon", "build", "--help"], env=overlay.env(), capture_output=True, text=True, timeout=60)
    assert usage.returncode == 0, usage.stderr
