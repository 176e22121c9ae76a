"""The system rules judge by evidence, end to end through `rmw-introspect check` with real rclpy
nodes (issue 37): a camera driver whose launch file gives it a serial device, a network link, a
calibration file of an installed package inside a `file://` URL, a data file in the home
directory, an output file, an identity remapping and a remapping for an interface the node
creates only in some configurations (not here). On a machine without the device or the data file, the
correct system passes the default gate (the device, the data file and the remapping are notes,
level NOTE); a missing installed calibration file and a comment that lost its `#` fail it. And the
correct system checked against its own golden on another machine (another home directory,
another install prefix, no devices) shows no drift and no finding."""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

import pytest
from cli_helpers import NODES, Cli


def camera_launch() -> str:
    return f"""\
<launch>
  <arg name="calibration" default="cal.yaml"/>
  <arg name="params" default="camera.yaml"/>
  <arg name="imu_remap" default="true"/>
  <group>
    <push-ros-namespace namespace="robot1"/>
    <node exec="{sys.executable}" args="{NODES / 'configured_node.py'}" name="camera">
      <param name="port" value="/dev/ttyFAKE37:57600"/>
      <param name="fcu_url" value="udp://:14540@127.0.0.1:14557"/>
      <param name="camera_info_url" value="file://$(find-pkg-share robot_config)/config/$(var calibration)"/>
      <param name="route_file" value="$(env HOME)/.autoware/data/route.csv"/>
      <param name="output_file" value="$(env HOME)/out/lane_waypoint.csv"/>
      <param from="$(dirname)/$(var params)"/>
      <remap from="~/status" to="~/status"/>
      <remap from="imu" to="imu/data" if="$(var imu_remap)"/>
    </node>
  </group>
</launch>
"""


CAMERA_PARAMS = "/robot1/camera:\n  ros__parameters:\n    exposure: 10\n"
# a parameters file whose comment lost its `#`: the comment became a parameter name
LOST_HASH = CAMERA_PARAMS + "    (see exposure description) (bool, default: false)\n"


def machine(root: Path, *, data_file: bool) -> dict[str, str]:
    """A machine: its own home directory (with the robot's data file, or without) and its own
    install prefix holding the package robot_config and its calibration file."""
    home, prefix = root / "home" / "user", root / "install"
    (home / ".autoware" / "data").mkdir(parents=True)
    if data_file:
        (home / ".autoware" / "data" / "route.csv").write_text("0,0\n")
    index = prefix / "share" / "ament_index" / "resource_index" / "packages"
    index.mkdir(parents=True)
    (index / "robot_config").write_text("")
    (prefix / "share" / "robot_config" / "config").mkdir(parents=True)
    (prefix / "share" / "robot_config" / "config" / "cal.yaml").write_text("camera_name: front\n")
    prefixes = [str(prefix), *filter(None, os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep))]
    return {"HOME": str(home), "AMENT_PREFIX_PATH": os.pathsep.join(prefixes)}


@pytest.fixture
def camera(cli: Cli) -> Cli:
    cli.write("launch/camera.launch.xml", camera_launch())
    cli.write("launch/camera.yaml", CAMERA_PARAMS)
    cli.write("launch/camera_lost_hash.yaml", LOST_HASH)
    return cli


def system_findings(result) -> list[tuple[str, str, str]]:
    return sorted((i["rule"], i["name"], i["severity"]) for i in json.loads(result.stdout) if "requester" in i)


def test_the_rules_judge_by_evidence(camera, tmp_path):
    here = machine(tmp_path / "ci", data_file=False)
    captured = camera("capture", "--launch", "launch/camera.launch.xml", "-o", "camera.system.yaml", env=here,
                      timeout=180)
    assert captured.returncode == 0, captured
    checked = camera("check", "camera.system.yaml", "--format", "json", env=here, timeout=180)
    assert checked.returncode == 0, checked
    # no device, udp link, installed calibration in file://, output file or identity remapping is a finding
    assert system_findings(checked) == [("PARAM_PATH_MACHINE_LOCAL", "route_file", "NOTE"),
                                        ("REMAP_UNUSED_UNCONNECTED", "imu:=imu/data", "NOTE")]
    # the device is a note
    assert ("note: camera.system.yaml: /robot1/camera: parameter `port` is '/dev/ttyFAKE37:57600': the device "
            "/dev/ttyFAKE37, which this machine does not have (not judged: the robot has it)\n") in checked.stderr

    # the project's rule levels apply to the system rules (issue 49): a dead remapping made to fail,
    # the machine-local file turned off
    strict = camera("check", "camera.system.yaml", "--rule", "REMAP_UNUSED*=breaking", "--rule",
                    "PARAM_PATH_MACHINE_LOCAL=off", "--format", "json", env=here, timeout=180)
    assert strict.returncode == 1, strict
    assert [(i["rule"], i["severity"], i.get("level_set_by")) for i in json.loads(strict.stdout)] == [
        ("REMAP_UNUSED_UNCONNECTED", "BREAKING", "set by rules `REMAP_UNUSED*`: in command line")]

    missing_calibration = camera("check", "camera.system.yaml", "--launch-arg", "calibration:=front.yaml",
                                 "--format", "json", env=here, timeout=180)
    assert missing_calibration.returncode == 1, missing_calibration
    assert ("PARAM_PATH_MISSING", "camera_info_url", "BREAKING") in system_findings(missing_calibration)

    lost_hash = camera("check", "camera.system.yaml", "--launch-arg", "params:=camera_lost_hash.yaml",
                       "--format", "json", env=here, timeout=180)
    assert lost_hash.returncode == 1, lost_hash
    findings = system_findings(lost_hash)
    assert ("PARAM_NAME_INVALID", "(see exposure description) (bool, default", "BREAKING") in findings
    assert not [f for f in findings if f[0] == "PARAM_NOT_DECLARED"]


def test_a_correct_system_checked_on_another_machine_shows_no_drift_and_no_finding(camera, tmp_path):
    robot = machine(tmp_path / "robot", data_file=True)
    # correct and complete: no remapping for an interface this configuration lacks
    captured = camera("capture", "--launch", "launch/camera.launch.xml", "--launch-arg", "imu_remap:=false",
                      "-o", "camera.system.yaml", env=robot, timeout=180)
    assert captured.returncode == 0, captured
    text = camera.read("camera.system.yaml")
    # recorded portably: no home directory, no install prefix of the machine that captured
    assert "default_value: $(env HOME)/.autoware/data/route.csv\n" in text
    assert "default_value: file://$(find-pkg-share robot_config)/config/cal.yaml\n" in text
    assert str(tmp_path) not in text

    elsewhere = machine(tmp_path / "ci", data_file=True)
    assert elsewhere["HOME"] != robot["HOME"]
    checked = camera("check", "camera.system.yaml", env=elsewhere, timeout=180)
    assert checked.returncode == 0, checked
    assert checked.stdout == "camera.system.yaml: matches (1 node in 1 process)\n", checked
    as_json = camera("check", "camera.system.yaml", "--format", "json", "--fail-on", "any",
                     "--system-fail-on", "any", env=elsewhere, timeout=180)
    assert as_json.returncode == 0, as_json
    assert json.loads(as_json.stdout) == []
