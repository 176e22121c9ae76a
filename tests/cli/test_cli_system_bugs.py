"""One small robot per class of misconfiguration real robots ship with, in a correct and a buggy
version (launch arguments of one launch file), checked end to end with `rmw-introspect`: the
correct robot, its outside world declared under `external:`, passes with no finding at all; each
buggy version fails the default gate (system_fail_on: breaking) with the rule that names the bug,
and no other system finding. The robot: a laser driver and an obstacle detector on lidar/scan,
parameters from a file keyed to the driver's node name, a status talker and its monitor, and a
command listener fed from outside the launch files (an operator console), and a map server that
takes its map by path."""

from __future__ import annotations

import json
import os
import sys

import pytest
from cli_helpers import NODES, Cli


def robot_launch(python: str, talker: str, map_loader: str) -> str:
    return f"""\
<launch>
  <arg name="renamed_node" default="false"/>
  <arg name="undeclared_parameter" default="false"/>
  <arg name="undeclared_global_parameter" default="false"/>
  <arg name="wrong_namespace" default="false"/>
  <arg name="changed_type" default="false"/>
  <arg name="detector_from" default="scan"/>
  <arg name="detector_to" default="lidar/scan"/>
  <arg name="map" default="$(find-pkg-share rmw_introspect_examples)/config/robot_params.yaml"/>
  <let name="params" value="$(dirname)/robot_params.yaml"/>
  <group>
    <push-ros-namespace namespace="robot1"/>
    <group>
      <set_parameter name="frame_idd" value="laser" if="$(var undeclared_global_parameter)"/>
      <node pkg="rmw_introspect_examples" exec="laser_driver" name="lidar" unless="$(var renamed_node)">
        <param from="$(var params)"/>
        <param name="rte" value="5.0" if="$(var undeclared_parameter)"/>
        <remap from="scan" to="lidar/scan"/>
      </node>
      <node pkg="rmw_introspect_examples" exec="laser_driver" name="laser" if="$(var renamed_node)">
        <param from="$(var params)"/>
        <remap from="scan" to="lidar/scan"/>
      </node>
    </group>
    <group unless="$(var wrong_namespace)">
      <node pkg="rmw_introspect_examples" exec="scan_consumer" name="obstacle_detector">
        <remap from="$(var detector_from)" to="$(var detector_to)"/>
      </node>
    </group>
    <node exec="{python}" args="{talker}" name="status_reporter">
      <param name="msg_type" value="Int32" if="$(var changed_type)"/>
      <remap from="chatter" to="status"/>
    </node>
    <node pkg="rmw_introspect_examples" exec="listener" name="status_monitor">
      <remap from="chatter" to="status"/>
    </node>
    <node exec="{python}" args="{map_loader}" name="map_server">
      <param name="map_file" value="$(var map)"/>
    </node>
    <node pkg="rmw_introspect_examples" exec="listener" name="command_listener">
      <remap from="chatter" to="cmd"/>
    </node>
  </group>
  <node pkg="rmw_introspect_examples" exec="scan_consumer" name="obstacle_detector" if="$(var wrong_namespace)">
    <remap from="scan" to="lidar/scan"/>
  </node>
</launch>
"""


#: bug class → (the launch argument that makes the mistake, the system findings that must name it)
BUGS = {
    "a remapping to the wrong name": ("detector_to:=lidar/scna", [("TOPIC_NAME_MISMATCH", "/robot1/lidar/scna")]),
    "a topic in the wrong namespace": ("wrong_namespace:=true", [("TOPIC_NAME_MISMATCH", "/lidar/scan")]),
    "a parameters file keyed to a renamed node": ("renamed_node:=true",
                                                  [("PARAMS_FILE_SECTION_UNMATCHED", "/robot1/lidar")]),
    "a type changed on one side": ("changed_type:=true", [("TYPE_MISMATCH", "/robot1/status")]),
    "a path parameter to a missing map": ("map:=$(find-pkg-share rmw_introspect_examples)/maps/office.yaml",
                                          [("PARAM_PATH_MISSING", "map_file")]),
    "a path parameter to a package that is not installed": ("map:=package://office_maps/office.yaml",
                                                            [("PARAM_PATH_MISSING", "map_file")]),
    "a parameter the node does not declare": ("undeclared_parameter:=true", [("PARAM_NOT_DECLARED", "rte")]),
    # a <set_parameter> reaches the nodes after it in its group only (the driver, not the others)
    "a global parameter the node does not declare": ("undeclared_global_parameter:=true",
                                                     [("PARAM_NOT_DECLARED", "frame_idd")]),
    "a remapping whose from the node does not use": (
        "detector_from:=sacn", [("REMAP_NEAR_MISS", "sacn:=lidar/scan"), ("TOPIC_NAME_MISMATCH", "/robot1/scan")]),
}


def write_robot(cli) -> None:
    cli.write("launch/robot.launch.xml",
              robot_launch(sys.executable, str(NODES / "talker.py"), str(NODES / "map_loader.py")))
    cli.write("launch/robot_params.yaml", "/robot1/lidar:\n  ros__parameters:\n    rate: 20.0\n")


@pytest.fixture(scope="module")
def robot(tmp_path_factory, middleware_library):
    """The correct robot captured into robot.system.yaml, its outside world declared (once for
    the module: every test only checks it)."""
    env = dict(os.environ, RMW_INTROSPECT_LIBRARY=str(middleware_library))
    for name in ("CI", "PYTEST_ADDOPTS"):
        env.pop(name, None)
    cli = Cli(tmp_path_factory.mktemp("robot"), env)
    write_robot(cli)
    created = cli("capture", "--launch", "launch/robot.launch.xml", "-o", "robot.system.yaml", timeout=180)
    assert created.returncode == 0, created
    text = cli.read("robot.system.yaml")
    # the outside input is proposed, commented out, above `processes:`
    proposal = ("# external:\n#   publishers:\n#     /robot1/cmd: WHO    # std_msgs/msg/String, for "
                "/robot1/command_listener\n")
    assert proposal in text and text.index(proposal) < text.index("\nprocesses:")
    # a file of an installed package is recorded with the package's share directory as a token
    assert "default_value: $(find-pkg-share rmw_introspect_examples)/config/robot_params.yaml\n" in text
    # without it declared, the command listener's input fails the check
    undeclared = cli("check", "robot.system.yaml", "--format", "json", timeout=180)
    assert undeclared.returncode == 1, undeclared
    assert [(i["rule"], i["name"]) for i in json.loads(undeclared.stdout)] == [
        ("DANGLING_SUBSCRIPTION", "/robot1/cmd")]
    # adopting the proposal is uncommenting it and naming who provides the input
    cli.write("robot.system.yaml", text.replace(proposal, "external:\n  publishers:\n"
                                                          "    /robot1/cmd: operator console\n"))
    return cli


def test_the_correct_robot_passes_with_no_finding(robot):
    checked = robot("check", "robot.system.yaml", timeout=180)
    assert checked.returncode == 0, checked
    assert checked.stdout.startswith("robot.system.yaml: matches (")
    assert "System check" not in checked.stdout


@pytest.mark.parametrize("bug", list(BUGS))
def test_each_buggy_robot_fails_the_default_gate_naming_its_bug(robot, bug):
    argument, expected = BUGS[bug]
    checked = robot("check", "robot.system.yaml", "--launch-arg", argument, "--format", "json", timeout=180)
    assert checked.returncode == 1, checked
    items = json.loads(checked.stdout)
    system = sorted((i["rule"], i["name"]) for i in items if "requester" in i)
    assert system == sorted(expected), checked
    assert all(i["severity"] == "BREAKING" for i in items if "requester" in i)


def test_a_global_parameter_is_named_where_the_launch_file_sets_it(robot):
    checked = robot("check", "robot.system.yaml", "--launch-arg", "undeclared_global_parameter:=true",
                    "--format", "json", timeout=180)
    [finding] = [i for i in json.loads(checked.stdout) if i.get("rule") == "PARAM_NOT_DECLARED"]
    line = robot.read("launch/robot.launch.xml").splitlines().index(
        '      <set_parameter name="frame_idd" value="laser" if="$(var undeclared_global_parameter)"/>') + 1
    assert f"parameter `frame_idd` is given (launch/robot.launch.xml:{line}) but /robot1/lidar does not declare it" \
        in json.dumps(finding), finding
    assert "did you mean `frame_id`?" in json.dumps(finding)
