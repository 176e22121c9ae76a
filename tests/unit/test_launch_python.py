"""Python launch files walked through ROS 2's own launch and launch_ros (run.launch_python).

These run only where launch_ros can be imported (a standard ROS 2 install); the ROS 2 PyPI
wheels have no launch_ros, and there the error path is tested instead
(test_launch_reader.py::test_python_launch_files_need_launch_ros)."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

from pytest_rmw_introspect.run import launch_reader

pytest.importorskip("launch_ros.actions", reason="launch_ros is not importable here (the ROS 2 PyPI wheels lack it)")


@pytest.fixture
def prefix(tmp_path: Path) -> Path:
    """An ament prefix with a package `demo` and its executables talker, laser, listener."""
    root = tmp_path / "prefix"
    (root / "share" / "ament_index" / "resource_index" / "packages").mkdir(parents=True)
    (root / "share" / "ament_index" / "resource_index" / "packages" / "demo").write_text("")
    (root / "share" / "demo").mkdir(parents=True)
    (root / "lib" / "demo").mkdir(parents=True)
    for name in ("talker", "laser", "listener"):
        exe = root / "lib" / "demo" / name
        exe.write_text("#!/bin/sh\n")
        exe.chmod(0o755)
    return root


LAUNCH = """
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, GroupAction, SetEnvironmentVariable
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import ComposableNodeContainer, Node, PushRosNamespace


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('use_lidar', default_value='true'),
        SetEnvironmentVariable('ROBOT_COLOR', 'red'),
        GroupAction([
            PushRosNamespace('robot1'),
            Node(package='demo', executable='talker', name='status_reporter',
                 remappings=[('chatter', 'status')], parameters=[{'rate': 5.0}]),
            Node(package='demo', executable='laser', name='lidar', parameters=[PARAMS],
                 condition=IfCondition(LaunchConfiguration('use_lidar'))),
        ]),
        Node(package='demo', executable='listener'),
        ComposableNodeContainer(name='c', namespace='', package='rclcpp_components',
                                executable='component_container', composable_node_descriptions=[]),
    ])
"""


def test_a_python_launch_file(tmp_path, prefix):
    params = tmp_path / "params.yaml"
    params.write_text("/**:\n  ros__parameters: {rate: 20.0}\n")
    path = tmp_path / "robot.launch.py"
    path.write_text(textwrap.dedent(LAUNCH).replace("PARAMS", repr(str(params))))
    result = launch_reader.read(path, {"use_lidar": "true"}, prefixes=[prefix])
    talker, laser, listener = result.nodes
    assert (talker.package, talker.executable, talker.name, talker.namespace) == ("demo", "talker", "status_reporter",
                                                                                 "/robot1")
    assert talker.command is not None and talker.command[0] == str(prefix / "lib" / "demo" / "talker")
    assert talker.command[1:6] == ("--ros-args", "-r", "__node:=status_reporter", "-r", "__ns:=/robot1")
    assert talker.command[-2:] == ("-r", "chatter:=status")
    assert "--params-file" in talker.command  # launch_ros writes dict parameters to a file
    assert laser.command[-2:] == ("--params-file", str(params))
    assert (listener.name, listener.namespace, listener.command[1:]) == (None, None, ("--ros-args",))
    assert dict(talker.env) == {"ROBOT_COLOR": "red"}
    assert [u.what.split(":")[0] for u in result.unsupported] == ["ComposableNodeContainer"]
    without = launch_reader.read(path, {"use_lidar": "false"}, prefixes=[prefix])
    assert [n.executable for n in without.nodes] == ["talker", "listener"]
