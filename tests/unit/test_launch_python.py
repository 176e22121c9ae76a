"""Python launch files walked through ROS 2's own launch and launch_ros (launch.python_file).

These run only where launch_ros can be imported (a standard ROS 2 install, the overlay, or a venv
with the ROS 2 PyPI wheels after `rmw-introspect install-launch`: tests/cli/test_install_launch.py
runs them so); elsewhere the error path is tested instead
(test_launch_reader.py::test_python_launch_files_need_launch_ros)."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

from pytest_rmw_introspect.launch import python_file
from pytest_rmw_introspect.launch import reader as launch_reader

try:
    python_file.modules()
except ImportError as exc:
    pytest.skip(f"launch/launch_ros cannot be imported here ({exc}): `rmw-introspect install-launch` installs them",
                allow_module_level=True)


@pytest.fixture
def prefix(tmp_path: Path) -> Path:
    """An ament prefix with a package `demo` and its executables talker, laser, listener, and
    rclcpp_components' component_container (a stand-in where rclcpp is not built: the wheels)."""
    root = tmp_path / "prefix"
    (root / "share" / "ament_index" / "resource_index" / "packages").mkdir(parents=True)
    for package, names in (("demo", ("talker", "laser", "listener")), ("rclcpp_components", ("component_container",))):
        (root / "share" / "ament_index" / "resource_index" / "packages" / package).write_text("")
        (root / "share" / package).mkdir(parents=True)
        (root / "lib" / package).mkdir(parents=True)
        for name in names:
            exe = root / "lib" / package / name
            exe.write_text("#!/bin/sh\n")
            exe.chmod(0o755)
    return root


LAUNCH = """
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, GroupAction, SetEnvironmentVariable, TimerAction
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
        TimerAction(period=2.0, actions=[Node(package='demo', executable='talker')]),
    ])
"""


def test_a_python_launch_file(tmp_path, prefix):
    params = tmp_path / "params.yaml"
    params.write_text("/**:\n  ros__parameters: {rate: 20.0}\n")
    path = tmp_path / "robot.launch.py"
    path.write_text(textwrap.dedent(LAUNCH).replace("PARAMS", repr(str(params))))
    result = launch_reader.read(path, {"use_lidar": "true"}, prefixes=[prefix])
    talker, laser, listener, container = result.nodes
    assert (talker.package, talker.executable, talker.name, talker.namespace) == ("demo", "talker", "status_reporter",
                                                                                 "/robot1")
    assert talker.command is not None and talker.command[0] == str(prefix / "lib" / "demo" / "talker")
    assert talker.command[1:6] == ("--ros-args", "-r", "__node:=status_reporter", "-r", "__ns:=/robot1")
    assert talker.command[-2:] == ("-r", "chatter:=status")
    assert "--params-file" in talker.command  # launch_ros writes dict parameters to a file
    assert laser.command[-2:] == ("--params-file", str(params))
    assert (listener.name, listener.namespace, listener.command[1:]) == (None, None, ("--ros-args",))
    assert dict(talker.env) == {"ROBOT_COLOR": "red"}
    assert (container.executable, container.expected_fqn, container.components) == ("component_container", "/c", ())
    assert [u.what.split(":")[0] for u in result.unsupported] == ["TimerAction"]
    without = launch_reader.read(path, {"use_lidar": "false"}, prefixes=[prefix])
    assert [n.executable for n in without.nodes] == ["talker", "listener", "component_container"]


def line_of(path: Path, text: str) -> int:
    """The line of ``path`` that contains ``text`` (once)."""
    [line] = [n for n, line in enumerate(path.read_text().splitlines(), 1) if text in line]
    return line


SETTINGS = """
from launch import LaunchDescription
from launch.actions import GroupAction
from launch_ros.actions import Node, SetParameter, SetRemap


def generate_launch_description():
    return LaunchDescription([
        SetParameter(name='use_sim_time', value=True),
        GroupAction([
            SetRemap(src='scan', dst='lidar/scan'),
            SetParameter(name='rate', value=2.5),
            Node(package='demo', executable='laser', name='lidar', remappings=[('odom', 'wheel/odom')],
                 parameters=[{'frame': 'laser'}]),
        ]),
        Node(package='demo', executable='listener', name='after'),
    ])
"""


def test_set_remap_and_set_parameter_in_a_python_launch_file(tmp_path, prefix):
    from pytest_rmw_introspect.check import launch_settings

    path = tmp_path / "settings.launch.py"
    path.write_text(textwrap.dedent(SETTINGS))
    laser, after = launch_reader.read(path, prefixes=[prefix]).nodes
    # launch_ros put them on the command line (global parameters first, the node's own after)
    assert laser.command is not None
    words = list(laser.command)
    assert words[words.index("-p"):words.index("-p") + 4] == ["-p", "use_sim_time:=True", "-p", "rate:=2.5"]
    assert laser.command[-4:] == ("-r", "scan:=lidar/scan", "-r", "odom:=wheel/odom")
    # and the walker read them back, each SetParameter with its own line
    sim_time = launch_reader.Where(path, line_of(path, "SetParameter(name='use_sim_time'"))
    rate = launch_reader.Where(path, line_of(path, "SetParameter(name='rate'"))
    assert [(p.name, p.value, p.where) for p in laser.parameters if p.name] == [
        ("use_sim_time", True, sim_time), ("rate", 2.5, rate)]
    assert [p.file is not None for p in laser.parameters] == [False, False, True]  # the node's own dict
    # SetRemap's rules as in XML: in force for the node (before its own), not its own remappings
    assert (laser.scope_remappings, laser.remappings) == ((("scan", "lidar/scan"),), (("odom", "wheel/odom"),))
    assert laser.where == launch_reader.Where(path, line_of(path, "executable='laser'"))
    # launch_ros's scoping, as in XML: the group's SetRemap ends with it (no remapping was set
    # before the group), its SetParameter does not (the list of global parameters existed)
    assert after.remappings == after.scope_remappings == ()
    assert [(p.name, p.where) for p in after.parameters] == [("use_sim_time", sim_time), ("rate", rate)]
    given = launch_settings.given(laser)
    assert [(p.name, p.source) for p in given.parameters] == [
        ("use_sim_time", str(sim_time)), ("rate", str(rate))]
    assert [f.sections for f in given.files] == [(("/**", ("frame",)),)]


HANDLERS = """
from launch import LaunchDescription
from launch.actions import EmitEvent, LogInfo, RegisterEventHandler, Shutdown
from launch.conditions import IfCondition
from launch.event_handlers import OnProcessExit, OnProcessIO, OnProcessStart, OnShutdown
from launch.events import Shutdown as ShutdownEvent
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    talker = Node(package='demo', executable='talker', name='talker', on_exit=Shutdown(),
                  condition=IfCondition(LaunchConfiguration('talk', default='true')))
    return LaunchDescription([
        talker,
        RegisterEventHandler(OnProcessExit(target_action=talker, on_exit=[LogInfo(msg='done'), EmitEvent(event=ShutdownEvent())])),
        RegisterEventHandler(OnProcessStart(target_action=talker, on_start=[LogInfo(msg='up'), Node(package='demo', executable='listener', name='follower')])),
        RegisterEventHandler(OnShutdown(on_shutdown=[LogInfo(msg='bye')])),
        BAD
    ])
"""
#: handlers a capture cannot honour: (the code, what the report says of it)
BAD_HANDLERS = {
    "RegisterEventHandler(OnProcessExit(target_action=talker, on_exit=[Node(package='demo', executable='laser')])),":
        "RegisterEventHandler: OnProcessExit: Node would run only after the process exits, which a capture does not "
        "wait for (it stops every process itself); only Shutdown, EmitEvent(Shutdown) and LogInfo are accepted there",
    "RegisterEventHandler(OnProcessExit(target_action=talker, on_exit=lambda event, context: None)),":
        "RegisterEventHandler: OnProcessExit: its actions are given as a function, run after the process exits; a "
        "capture cannot run it (it has no such event): give a list of actions",
    "RegisterEventHandler(OnShutdown(on_shutdown=lambda event, context: [LogInfo(msg='x')])),":
        "RegisterEventHandler: OnShutdown: its actions are given as a function, run when the launch shuts down;",
    "RegisterEventHandler(OnProcessStart(target_action=talker, on_start=lambda event, context: None)),":
        "RegisterEventHandler: OnProcessStart: its actions are given as a function of the start event",
    "RegisterEventHandler(OnProcessIO(target_action=talker, on_stdout=lambda event: None)),":
        "RegisterEventHandler: OnProcessIO: this event handler is not supported",
    "Node(package='demo', executable='laser', on_exit=[Node(package='demo', executable='listener')]),":
        "Node: on_exit: Node would run only after the process exits",
}


def test_event_handlers_get_the_meaning_a_capture_can_give_them(tmp_path, prefix):
    path = tmp_path / "handlers.launch.py"
    path.write_text(textwrap.dedent(HANDLERS).replace("BAD", ""))
    result = launch_reader.read(path, prefixes=[prefix])
    # OnProcessStart: what follows the talker's start is started too; the ending handlers are accepted
    assert [(n.executable, n.name) for n in result.nodes] == [("talker", "talker"), ("listener", "follower")]
    assert result.unsupported == []
    assert result.nodes[1].where == launch_reader.Where(path, line_of(path, "name='follower'"))
    # its target not started: nothing follows
    assert [n.name for n in launch_reader.read(path, {"talk": "false"}, prefixes=[prefix]).nodes] == []
    for code, what in BAD_HANDLERS.items():
        path.write_text(textwrap.dedent(HANDLERS).replace("BAD", code))
        [unsupported] = launch_reader.read(path, prefixes=[prefix]).unsupported
        assert unsupported.what.startswith(what), (code, unsupported.what)
        assert unsupported.where == launch_reader.Where(path, line_of(path, code)), code


def test_unsupported_python_actions_name_their_file_and_line(tmp_path, prefix):
    params = tmp_path / "params.yaml"
    params.write_text("/**:\n  ros__parameters: {rate: 20.0}\n")
    path = tmp_path / "robot.launch.py"
    path.write_text(textwrap.dedent(LAUNCH).replace("PARAMS", repr(str(params))))
    [unsupported] = launch_reader.read(path, {"use_lidar": "true"}, prefixes=[prefix]).unsupported
    assert unsupported.where == launch_reader.Where(path, line_of(path, "TimerAction(period="))
    assert str(unsupported.where).endswith(f"robot.launch.py:{unsupported.where.line}")


#: XML scoping the project's own reader implements: groups, scoped="false", <include>, and the
#: <set_remap>/<set_parameter> rules at every level
SCOPED_XML = """
<launch>
  <set_remap from="/tf" to="tf"/>
  <set_parameter name="use_sim_time" value="true"/>
  <group>
    <push_ros_namespace namespace="robot1"/>
    <set_remap from="scan" to="lidar/scan"/>
    <set_parameter name="rate" value="2.5"/>
    <node pkg="demo" exec="laser" name="lidar"><remap from="odom" to="wheel/odom"/></node>
    <include file="$(dirname)/inner.launch.xml"/>
    <node pkg="demo" exec="listener" name="after_include"/>
  </group>
  <group scoped="false">
    <set_remap from="cmd" to="cmd_vel"/>
    <set_parameter name="unscoped" value="7"/>
  </group>
  <node pkg="demo" exec="listener" name="after_groups"/>
  <include file="$(dirname)/inner.launch.xml"/>
  <node pkg="demo" exec="talker" name="last"/>
</launch>
"""
INNER_XML = """
<launch>
  <set_remap from="inner" to="from_inner"/>
  <set_parameter name="inner_param" value="1"/>
  <node pkg="demo" exec="talker" name="t"/>
</launch>
"""


@pytest.mark.parametrize("top_level", [True, False], ids=["rules-set-before-the-groups", "no-rule-before-the-groups"])
def test_xml_scoping_of_the_reader_equals_launch_ros(tmp_path, prefix, top_level):
    """The XML reader's scopes (what each node is given) against launch_ros's own, which walks the
    same file included from a Python launch file: the same nodes, remapping rules in the same
    order, and the same named parameters. launch_ros's scoping depends on whether a rule was set
    before a group (the group then adds to the same list, and its rules outlive it), so both."""
    xml = textwrap.dedent(SCOPED_XML)
    if not top_level:
        xml = xml.replace('<set_remap from="/tf" to="tf"/>\n', "").replace('<set_parameter name="use_sim_time" value="true"/>\n', "")
    assert ('"/tf"' in xml and "use_sim_time" in xml) == top_level
    (tmp_path / "robot.launch.xml").write_text(xml)
    (tmp_path / "inner.launch.xml").write_text(textwrap.dedent(INNER_XML))
    (tmp_path / "wrapper.launch.py").write_text(textwrap.dedent(f"""
        from launch import LaunchDescription
        from launch.actions import IncludeLaunchDescription
        from launch.launch_description_sources import AnyLaunchDescriptionSource


        def generate_launch_description():
            return LaunchDescription([IncludeLaunchDescription(AnyLaunchDescriptionSource('{tmp_path / "robot.launch.xml"}'))])
        """))

    def given(path: Path) -> list[tuple[str | None, tuple[tuple[str, str], ...], list[tuple[str, object]]]]:
        return [(node.expected_fqn, (*node.scope_remappings, *node.remappings),
                 [(p.name, p.value) for p in node.parameters if p.name])
                for node in launch_reader.read(path, prefixes=[prefix]).nodes]

    ours, theirs = given(tmp_path / "robot.launch.xml"), given(tmp_path / "wrapper.launch.py")
    assert [fqn for fqn, _, _ in theirs] == ["/robot1/lidar", "/robot1/t", "/robot1/after_include", "/after_groups",
                                             "/t", "/last"]
    assert ours == theirs


def test_anon_names_of_a_python_launch_file_are_those_of_xml_and_stable_across_runs(tmp_path, prefix):
    path = tmp_path / "anon.launch.py"
    path.write_text(textwrap.dedent("""
        from launch import LaunchDescription
        from launch.substitutions import AnonName
        from launch_ros.actions import Node


        def generate_launch_description():
            return LaunchDescription([Node(package='demo', executable='talker', name=AnonName('worker'))])
    """))
    xml = tmp_path / "anon.launch.xml"
    xml.write_text('<launch><node pkg="demo" exec="talker" name="$(anon worker)"/></launch>')
    names = {launch_reader.read(path, prefixes=[prefix]).nodes[0].name for _ in range(3)}
    assert names == {launch_reader.read(xml, prefixes=[prefix]).nodes[0].name}
    assert next(iter(names)).startswith("worker_anon_")
    # launch's own AnonName is itself again after reading
    from launch.substitutions import AnonName
    assert "worker_anon_" not in AnonName("worker").compute_name("worker")


COMPONENTS = """
from launch import LaunchDescription
from launch.actions import GroupAction
from launch_ros.actions import ComposableNodeContainer, PushRosNamespace, SetRemap
from launch_ros.descriptions import ComposableNode


def generate_launch_description():
    return LaunchDescription([GroupAction([
        PushRosNamespace('robot'),
        SetRemap(src='scan', dst='lidar/scan'),
        ComposableNodeContainer(name='container', namespace='', package='rclcpp_components',
                                executable='component_container', composable_node_descriptions=[
            ComposableNode(package='demo', plugin='demo::Talker', name='talker',
                           remappings=[('chatter', 'status')], parameters=[{'rate': 2.5, 'ids': [1, 2]}],
                           extra_arguments=[{'use_intra_process_comms': True}]),
        ]),
    ])])
"""


def test_a_component_is_the_load_node_request_launch_ros_builds(tmp_path, prefix):
    """With or without a real composition_interfaces (the wheels have none: launch_ros then builds
    the request on launch.composition_stand_in's LoadNode), the request holds what launch_ros put in."""
    path = tmp_path / "components.launch.py"
    path.write_text(textwrap.dedent(COMPONENTS))
    [container] = launch_reader.read(path, prefixes=[prefix]).nodes
    [component] = container.components
    assert (component.package, component.plugin, component.name, component.namespace) == (
        "demo", "demo::Talker", "talker", "/robot")
    assert component.remap_rules == ("scan:=lidar/scan", "chatter:=status")
    assert component.parameters == (("rate", 3, 2.5), ("ids", 7, (1, 2)))
    assert component.extra_arguments == (("use_intra_process_comms", 1, True),)
