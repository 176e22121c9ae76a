"""Component containers in Python launch files (issue 25 item 3), and the Python launch-file
walker itself (event handlers, SetRemap, SetParameter: tests/unit/test_launch_python.py), on the
C++ and launch overlay: real launch_ros, a real rclcpp_components container, the example
package's real components."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

# the first test of a session may build the middleware and the C++ examples over the overlay
pytestmark = pytest.mark.timeout(1800)

ROBOT = """
from launch import LaunchDescription
from launch.actions import GroupAction
from launch_ros.actions import ComposableNodeContainer, LoadComposableNodes, PushRosNamespace, SetParameter, SetRemap
from launch_ros.descriptions import ComposableNode


def generate_launch_description():
    container = ComposableNodeContainer(
        name='container', namespace='robot', package='rclcpp_components', executable='component_container',
        composable_node_descriptions=[
            ComposableNode(package='rmw_introspect_examples_cpp', plugin='rmw_introspect_examples_cpp::Talker',
                           name='talker', namespace='robot', parameters=[{'rate_hz': 5.0}],
                           remappings=[('chatter', 'status')]),
        ])
    return LaunchDescription([
        container,
        GroupAction([
            PushRosNamespace('robot'),
            SetRemap(src='chatter', dst='status'),
            SetParameter(name='log_every', value=3),
            LoadComposableNodes(target_container='/robot/container', composable_node_descriptions=[
                ComposableNode(package='rmw_introspect_examples_cpp', plugin='PLUGIN', name='monitor'),
            ]),
        ]),
    ])
"""


#: the same robot as an XML launch file (read by this project's own reader)
ROBOT_XML = """
<launch>
  <node_container pkg="rclcpp_components" exec="component_container" name="container" namespace="robot">
    <composable_node pkg="rmw_introspect_examples_cpp" plugin="rmw_introspect_examples_cpp::Talker" name="talker"
                     namespace="robot">
      <param name="rate_hz" value="5.0"/>
      <remap from="chatter" to="status"/>
    </composable_node>
  </node_container>
  <group>
    <push_ros_namespace namespace="robot"/>
    <set_remap from="chatter" to="status"/>
    <set_parameter name="log_every" value="3"/>
    <load_composable_node target="/robot/container">
      <composable_node pkg="rmw_introspect_examples_cpp" plugin="PLUGIN" name="monitor"/>
    </load_composable_node>
  </group>
</launch>
"""
FORMS = {"robot.launch.py": ROBOT, "robot.launch.xml": ROBOT_XML}


@pytest.fixture
def env(overlay, cpp_examples, rmw_introspect_library) -> dict[str, str]:
    """A process over the overlay that also finds the example package's components."""
    base = overlay.env({"RMW_INTROSPECT_LIBRARY": str(rmw_introspect_library)})
    for name, path in (("AMENT_PREFIX_PATH", cpp_examples), ("LD_LIBRARY_PATH", cpp_examples / "lib")):
        base[name] = os.pathsep.join([str(path), *filter(None, base.get(name, "").split(os.pathsep))])
    return base


def rmw_introspect(env: dict[str, str], cwd: Path, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "pytest_rmw_introspect", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=300, check=False)


@pytest.mark.parametrize("launch_file", list(FORMS))
def test_the_components_a_launch_file_loads_are_nodes_of_their_container(tmp_path, env, launch_file):
    (tmp_path / launch_file).write_text(
        textwrap.dedent(FORMS[launch_file]).replace("PLUGIN", "rmw_introspect_examples_cpp::Listener"))
    captured = rmw_introspect(env, tmp_path, "capture", "--launch", launch_file, "-o", "robot.system.yaml")
    assert captured.returncode == 0, captured
    text = (tmp_path / "robot.system.yaml").read_text()
    # one process, the container, with the components as its nodes
    assert ("  - package: rclcpp_components\n    executable: component_container\n    name: /robot/container\n"
            "    nodes: [/robot/container, /robot/monitor, /robot/talker]\n") in text
    checked = rmw_introspect(env, tmp_path, "check", "robot.system.yaml", "--format", "json")
    assert checked.returncode == 0, checked
    assert json.loads(checked.stdout) == []  # wired: /robot/talker publishes what /robot/monitor takes
    contract = text[text.index("\nnodes:"):]
    # each component with its own parameters and remappings, and those of its scope
    assert "  /robot/talker:\n    publishers:\n      - name: /robot/status\n" in contract
    assert "      - name: rate_hz\n        type: double\n        default_value: 5.0\n" in contract
    assert "  /robot/monitor:\n    publishers: []\n    subscriptions:\n      - name: /robot/status\n" in contract
    assert "      - name: log_every\n        type: integer\n        default_value: 3\n" in contract


def one_finding(tmp_path: Path, env: dict[str, str], launch_text: str, rule: str, marker: str) -> tuple[dict, int]:
    """Capture ``launch_text`` as robot.launch.py, check it: the one finding of ``rule``, and the
    line of the launch file that holds ``marker``."""
    (tmp_path / "robot.launch.py").write_text(textwrap.dedent(launch_text))
    captured = rmw_introspect(env, tmp_path, "capture", "--launch", "robot.launch.py", "-o", "robot.system.yaml")
    assert captured.returncode == 0, captured
    checked = rmw_introspect(env, tmp_path, "check", "robot.system.yaml", "--format", "json")
    assert checked.returncode == 1, checked
    [finding] = [i for i in json.loads(checked.stdout) if i["rule"] == rule]
    lines = (tmp_path / "robot.launch.py").read_text().splitlines()
    return finding, [n for n, text in enumerate(lines, 1) if marker in text][0]


def test_a_component_the_container_cannot_load_is_a_node_not_created(tmp_path, env):
    unloaded, line = one_finding(tmp_path, env, ROBOT.replace("PLUGIN", "rmw_introspect_examples_cpp::Listner"),
                                 "LAUNCHED_NODE_NOT_CREATED", "plugin='rmw_introspect_examples_cpp::Listner'")
    assert unloaded["name"] == "/robot/monitor"
    assert (f"the launch file loads component rmw_introspect_examples_cpp::Listner as /robot/monitor "
            f"(robot.launch.py:{line}) into /robot/container, but no node came of it: the container refused it: "
            "Failed to find class with the requested plugin name.") in json.dumps(unloaded)


def test_a_component_s_remapping_that_changes_none_of_its_names_is_found(tmp_path, env):
    # the talker component's own rule misspells its topic; the scope's SetRemap (chatter:=status,
    # used by the monitor only) is not the talker's to use
    robot = ROBOT.replace("PLUGIN", "rmw_introspect_examples_cpp::Listener").replace(
        "remappings=[('chatter', 'status')]", "remappings=[('chater', 'status')]")
    unused, line = one_finding(tmp_path, env, robot, "REMAP_NEAR_MISS", "plugin='rmw_introspect_examples_cpp::Talker'")
    assert (unused["name"], unused["severity"]) == ("chater:=status", "BREAKING"), unused
    assert "/robot/talker" in json.dumps(unused)
    assert f"the remapping chater -> status (at robot.launch.py:{line}) changed none of the names of /robot/talker:" \
        in unused["message"], unused


def test_the_python_launch_walker_runs_on_real_launch_ros(overlay):
    """tests/unit/test_launch_python.py, skipped where launch_ros cannot be imported, runs here."""
    ran = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-rs",
                          str(REPO / "tests" / "unit" / "test_launch_python.py")],
                         cwd=REPO, env=overlay.env(), capture_output=True, text=True, timeout=300, check=False)
    assert ran.returncode == 0, ran.stdout + ran.stderr
    assert " passed" in ran.stdout and "skipped" not in ran.stdout, ran.stdout


CPP_ROBOT = REPO / "examples" / "rmw_introspect_examples_cpp" / "contracts" / "robot.system.yaml"


def test_the_cpp_example_robot_matches_its_system_contract(tmp_path, env):
    """launch/robot.launch.py of rmw_introspect_examples_cpp: an include with arguments, launch
    arguments and conditions, GroupAction + PushRosNamespace, SetRemap, SetParameter, a Node with
    a parameters file, an OpaqueFunction, a container with LoadComposableNodes, a LifecycleNode,
    an OnProcessExit -> Shutdown handler."""
    checked = rmw_introspect(env, tmp_path, "check", str(CPP_ROBOT), "--format", "json")
    assert checked.returncode == 0, checked
    assert json.loads(checked.stdout) == []
    # the same robot without components: the talker and listener are processes of their own,
    # with the same interfaces and parameters; only the container is gone
    separate = rmw_introspect(env, tmp_path, "check", str(CPP_ROBOT), "--launch-arg", "use_components:=false",
                              "--format", "json")
    assert separate.returncode == 1, separate
    assert sorted({(i["rule"], i["node"]) for i in json.loads(separate.stdout)}) == [
        ("NODE_REMOVED", "/robot/components"), ("SERVICE_SERVER_REMOVED", "/robot/components")]


def test_a_container_started_alone_shows_itself_and_no_component(tmp_path, env, overlay):
    """docs/system-contracts.md, "Component containers": components loaded later by `ros2 component load` come from
    another process, which never reaches a capture."""
    container = overlay.install / "lib" / "rclcpp_components" / "component_container"
    captured = rmw_introspect(env, tmp_path, "capture", "-o", "alone.interfaces.yaml", "--", str(container))
    assert captured.returncode == 0, captured
    text = (tmp_path / "alone.interfaces.yaml").read_text()
    nodes = text[text.index("\nnodes:"):]
    assert [line.strip() for line in nodes.splitlines() if line.startswith("  /")] == ["/ComponentManager:"]
    assert [line.split("name: ")[1] for line in nodes.splitlines() if "- name: /ComponentManager/" in line] == [
        "/ComponentManager/_container/list_nodes", "/ComponentManager/_container/load_node",
        "/ComponentManager/_container/unload_node"]


def test_a_parameter_a_component_does_not_declare_is_named_where_it_is_loaded(tmp_path, env):
    launch_text = (ROBOT.replace("PLUGIN", "rmw_introspect_examples_cpp::Listener")
                   .replace("'rate_hz': 5.0", "'rate_hz': 5.0, 'rate_hzz': 6.0"))
    undeclared, line = one_finding(tmp_path, env, launch_text, "PARAM_NOT_DECLARED",
                                   "plugin='rmw_introspect_examples_cpp::Talker'")
    assert undeclared["name"] == "rate_hzz"
    assert (f"parameter `rate_hzz` is given (robot.launch.py:{line}) but /robot/talker does not declare it: ROS 2 "
            "ignores it without a word; did you mean `rate_hz`?") in json.dumps(undeclared)
