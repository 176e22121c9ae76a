"""The launch reader (launch.reader): XML and YAML launch files, substitutions, includes,
conditions, groups, unsupported constructs, play_launch record.json files and Python launch
files without launch_ros."""

from __future__ import annotations

import importlib.util
import json
import textwrap
from pathlib import Path

import pytest

from pytest_rmw_introspect.errors import LaunchError
from pytest_rmw_introspect.launch import reader as launch_reader
from pytest_rmw_introspect.launch import substitutions as launch_substitutions
from pytest_rmw_introspect.launch.result import LaunchParameter

# ---------------------------------------------------------------------------- helpers


def write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(textwrap.dedent(text).lstrip("\n"), encoding="utf-8")
    return path


@pytest.fixture
def prefix(tmp_path: Path) -> Path:
    """An ament prefix with a package `bringup` (share/bringup/launch/...) and `other`."""
    root = tmp_path / "prefix"
    for package in ("bringup", "other"):
        write(root / "share" / "ament_index" / "resource_index" / "packages" / package, "")
        (root / "share" / package).mkdir(parents=True, exist_ok=True)
    return root


def read(path: Path, arguments=None, prefix: Path | None = None):
    return launch_reader.read(path, arguments, prefixes=[prefix] if prefix else [])


def summary(result) -> list[tuple]:
    """(package, executable, name, namespace, parameters, remappings, arguments, ros_arguments) per node."""
    out = []
    for node in result.nodes:
        params = tuple((p.name, p.value) if p.name else ("file", p.file.name) for p in node.parameters)
        out.append((node.package, node.executable, node.name, node.namespace, params, node.remappings,
                    node.arguments, node.ros_arguments))
    return out


# ---------------------------------------------------------------------------- every tag, XML and YAML

ALL_TAGS_XML = """
<launch>
  <arg name="ns" default="robot" description="namespace of the robot"/>
  <arg name="use_lidar" default="true">
    <choice value="true"/><choice value="false"/>
  </arg>
  <let name="rate" value="5.5"/>
  <set_env name="ROBOT_COLOR" value="red"/>
  <group>
    <push-ros-namespace namespace="$(var ns)"/>
    <node pkg="pkg_a" exec="talker" name="talker" output="screen" respawn="true"
          args="--verbose 'two words'" ros_args="--log-level warn">
      <param name="rate" value="$(var rate)"/>
      <param name="count" value="7"/>
      <param name="enabled" value="true"/>
      <param name="label" value="hello"/>
      <param name="ids" value="1,2,3" value-sep=","/>
      <param name="limits"><param name="max" value="2.0"/><param name="min" value="-1"/></param>
      <param from="params.yaml"/>
      <remap from="chatter" to="chat"/>
      <env name="EXTRA" value="1"/>
    </node>
    <node pkg="pkg_a" exec="laser" namespace="sensors" if="$(var use_lidar)"/>
    <node pkg="pkg_a" exec="camera" unless="$(var use_lidar)"/>
  </group>
  <node pkg="pkg_b" exec="planner" namespace="/absolute"/>
</launch>
"""

ALL_TAGS_YAML = """
launch:
- arg: {name: ns, default: robot, description: namespace of the robot}
- arg:
    name: use_lidar
    default: "true"
    choice: [{value: "true"}, {value: "false"}]
- let: {name: rate, value: "5.5"}
- set_env: {name: ROBOT_COLOR, value: red}
- group:
    children:
    - push_ros_namespace: {namespace: $(var ns)}
    - node:
        pkg: pkg_a
        exec: talker
        name: talker
        output: screen
        respawn: true
        args: --verbose 'two words'
        ros_args: --log-level warn
        param:
        - {name: rate, value: $(var rate)}
        - {name: count, value: 7}
        - {name: enabled, value: true}
        - {name: label, value: hello}
        - {name: ids, value: [1, 2, 3]}
        - name: limits
          param:
          - {name: max, value: 2.0}
          - {name: min, value: -1}
        - {from: params.yaml}
        remap:
        - {from: chatter, to: chat}
        env:
        - {name: EXTRA, value: "1"}
    - node: {pkg: pkg_a, exec: laser, namespace: sensors, if: $(var use_lidar)}
    - node: {pkg: pkg_a, exec: camera, unless: $(var use_lidar)}
- node: {pkg: pkg_b, exec: planner, namespace: /absolute}
"""

EXPECTED_TALKER = (
    "pkg_a", "talker", "talker", "/robot",
    (("rate", 5.5), ("count", 7), ("enabled", True), ("label", "hello"), ("ids", [1, 2, 3]),
     ("limits.max", 2.0), ("limits.min", -1), ("file", "params.yaml")),
    (("chatter", "chat"),), ("--verbose", "two words"), ("--log-level", "warn"),
)


@pytest.mark.parametrize("name,text", [("robot.launch.xml", ALL_TAGS_XML), ("robot.launch.yaml", ALL_TAGS_YAML)])
def test_every_supported_tag(tmp_path, name, text):
    write(tmp_path / "params.yaml", "/**:\n  ros__parameters: {gain: 2}\n")
    path = write(tmp_path / name, text)
    result = read(path)
    assert result.unsupported == []
    assert summary(result) == [
        EXPECTED_TALKER,
        ("pkg_a", "laser", None, "/robot/sensors", (), (), (), ()),
        ("pkg_b", "planner", None, "/absolute", (), (), (), ()),
    ]
    talker = result.nodes[0]
    assert dict(talker.env) == {"ROBOT_COLOR": "red", "EXTRA": "1"}
    assert dict(result.nodes[2].env) == {"ROBOT_COLOR": "red"}
    assert talker.expected_fqn == "/robot/talker"
    assert str(talker.where).endswith(f"{name}:10" if name.endswith(".xml") else f"{name}:12")
    assert [(d.name, d.default, d.choices) for d in result.declared] == [
        ("ns", "robot", ()), ("use_lidar", "true", ("true", "false"))]
    assert result.declared[0].description == "namespace of the robot"
    # the other way round: the camera instead of the lidar
    other = read(path, {"use_lidar": False, "ns": "r2"})
    assert [(n.executable, n.namespace) for n in other.nodes] == [
        ("talker", "/r2"), ("camera", "/r2"), ("planner", "/absolute")]


def test_command_line_follows_launch_ros(tmp_path):
    write(tmp_path / "params.yaml", "{}\n")
    talker = read(write(tmp_path / "a.launch.xml", ALL_TAGS_XML)).nodes[0]
    assert talker.ros_argument_list() == [
        "--ros-args", "-r", "__node:=talker", "-r", "__ns:=/robot",
        "-p", "rate:=5.5", "-p", "count:=7", "-p", "enabled:=true", "-p", "label:=hello", "-p", "ids:=[1, 2, 3]",
        "-p", "limits.max:=2.0", "-p", "limits.min:=-1", "--params-file", str(tmp_path / "params.yaml"),
        "-r", "chatter:=chat", "--log-level", "warn"]
    plain = launch_reader.LaunchedNode(executable="x", package="p", where=talker.where)
    assert plain.ros_argument_list() == []
    assert plain.expected_fqn is None


@pytest.mark.parametrize("value,expected", [
    ("5", 5), ("-3", -3), ("2.5", 2.5), ("1e3", 1000.0), ("true", True), ("False", False), ("hello", "hello"),
    ("", ""), ("'quoted'", "'quoted'"),
])
def test_untyped_values_are_typed_like_launch(value, expected):
    assert launch_reader.guess_type(value) == expected


def test_values_with_substitutions_are_read_as_yaml(tmp_path):
    path = write(tmp_path / "a.launch.xml", """
        <launch>
          <let name="list" value="[1, 2]"/>
          <let name="word" value="text: with colon"/>
          <node pkg="p" exec="e">
            <param name="a" value="$(var list)"/>
            <param name="b" value="$(var word)"/>
            <param name="c" value="x$(var list)"/>
            <param name="d" value="" value-sep=","/>
          </node>
        </launch>""")
    params = read(path).nodes[0].parameters
    assert [(p.name, p.value) for p in params] == [("a", [1, 2]), ("b", "text: with colon"), ("c", "x[1, 2]"), ("d", [])]


# ---------------------------------------------------------------------------- substitutions


def test_substitutions(tmp_path, prefix, monkeypatch):
    monkeypatch.setenv("ROBOT_MODEL", "turtle")
    monkeypatch.delenv("NOT_SET_ANYWHERE", raising=False)
    path = write(tmp_path / "launch" / "subs.launch.xml", """
        <launch>
          <arg name="pkg" default="bringup"/>
          <node pkg="p" exec="e" name="$(anon worker)">
            <param name="var" value="$(var pkg)"/>
            <param name="env" value="$(env ROBOT_MODEL)"/>
            <param name="env_default" value="$(env NOT_SET_ANYWHERE 'fall back')"/>
            <param name="optenv" value="[$(optenv NOT_SET_ANYWHERE)]"/>
            <param name="share" value="$(find-pkg-share $(var pkg))"/>
            <param name="prefix" value="$(find-pkg-prefix other)"/>
            <param name="dirname" value="$(dirname)"/>
            <param name="filename" value="$(filename)"/>
            <param name="again" value="$(anon worker)"/>
            <param name="other" value="$(anon helper)"/>
          </node>
        </launch>""")
    node = read(path, prefix=prefix).nodes[0]
    values = {p.name: p.value for p in node.parameters}
    assert values["var"] == "bringup"
    assert values["env"] == "turtle"
    assert values["env_default"] == "fall back"
    assert values["optenv"] == []
    assert values["share"] == str(prefix / "share" / "bringup")
    assert values["prefix"] == str(prefix)
    assert values["dirname"] == str(tmp_path / "launch")
    assert values["filename"] == str(path)
    # $(anon NAME): one name per NAME within the launch, the same in every run
    assert node.name == values["again"] and node.name.startswith("worker_anon_")
    assert values["other"].startswith("helper_anon_") and values["other"] != node.name
    assert read(path, prefix=prefix).nodes[0].name == node.name


@pytest.mark.parametrize("text,error", [
    ("$(var nope)", "launch configuration 'nope' is not set"),
    ("$(env NOT_SET_ANYWHERE)", "environment variable 'NOT_SET_ANYWHERE' is not set"),
    ("$(find-pkg-share no_such_package)", "package 'no_such_package' is not in the ament index"),
    ("$(var)", "$(var) takes 1 argument(s), got 0"),
    ("$(var a", "unterminated substitution"),
    ("$(var 'a)", "unterminated quote"),
])
def test_substitution_errors_name_the_file_and_line(tmp_path, prefix, text, error, monkeypatch):
    monkeypatch.delenv("NOT_SET_ANYWHERE", raising=False)
    path = write(tmp_path / "bad.launch.xml", f"""
        <launch>

          <node pkg="p" exec="e" name="{text}"/>
        </launch>""")
    with pytest.raises(LaunchError) as info:
        read(path, prefix=prefix)
    assert "bad.launch.xml:3: <node>: " in str(info.value)
    assert error in str(info.value)


def test_substitution_parser():
    parse = launch_substitutions.parse
    Sub = launch_substitutions.Substitution
    assert parse("plain text") == ("plain text",)
    assert parse("a $(var x) b") == ("a ", Sub("var", (("x",),)), " b")
    assert parse("$(find-pkg-share $(var p))/x") == (Sub("find-pkg-share", ((Sub("var", (("p",),)),),)), "/x")
    assert parse("$(env A \"two words\")") == (Sub("env", (("A",), ("two words",))),)
    assert parse("$(dirname)") == (Sub("dirname"),)


# ---------------------------------------------------------------------------- includes


def test_includes_with_arguments_and_scopes(tmp_path, prefix):
    write(prefix / "share" / "bringup" / "launch" / "sensor.launch.yaml", """
        launch:
        - arg: {name: sensor, default: lidar}
        - arg: {name: rate, default: "10"}
        - let: {name: leaked, value: "no"}
        - node:
            pkg: pkg_s
            exec: $(var sensor)
            name: $(var sensor)_driver
            param: [{name: rate, value: $(var rate)}]
        """)
    write(tmp_path / "parts" / "relative.launch.xml", """
        <launch>
          <node pkg="pkg_r" exec="relative" namespace="$(var where)"/>
        </launch>""")
    path = write(tmp_path / "top.launch.xml", """
        <launch>
          <let name="where" value="here"/>
          <group>
            <push-ros-namespace namespace="front"/>
            <include file="$(find-pkg-share bringup)/launch/sensor.launch.yaml">
              <arg name="sensor" value="camera"/>
            </include>
          </group>
          <include file="$(find-pkg-share bringup)/launch/sensor.launch.yaml"/>
          <include file="parts/relative.launch.xml"/>
          <node pkg="p" exec="after" name="$(var leaked none)" if="false"/>
        </launch>""")
    result = read(path, prefix=prefix)
    assert [(n.executable, n.name, n.namespace, [(p.name, p.value) for p in n.parameters]) for n in result.nodes] == [
        ("camera", "camera_driver", "/front", [("rate", 10)]),
        ("lidar", "lidar_driver", None, [("rate", 10)]),
        ("relative", None, "/here", []),
    ]
    assert [p.name for p in result.files] == ["top.launch.xml", "sensor.launch.yaml", "sensor.launch.yaml",
                                              "relative.launch.xml"]
    # a let inside an include does not leak out of it
    leak = write(tmp_path / "leak.launch.xml", """
        <launch>
          <include file="$(find-pkg-share bringup)/launch/sensor.launch.yaml"/>
          <node pkg="p" exec="$(var leaked)"/>
        </launch>""")
    with pytest.raises(LaunchError, match=r"leak.launch.xml:3: <node>: launch configuration 'leaked' is not set"):
        read(leak, prefix=prefix)


def test_include_errors(tmp_path, prefix):
    missing = write(tmp_path / "missing.launch.xml", """
        <launch>
          <include file="nowhere.launch.xml"/>
        </launch>""")
    with pytest.raises(LaunchError, match=r"missing.launch.xml:2: launch file .*nowhere.launch.xml does not exist"):
        read(missing)
    write(tmp_path / "b.launch.xml", '<launch>\n  <include file="a.launch.xml"/>\n</launch>\n')
    cycle = write(tmp_path / "a.launch.xml", '<launch>\n  <include file="b.launch.xml"/>\n</launch>\n')
    with pytest.raises(LaunchError, match=r"b.launch.xml:2: include cycle: .*a.launch.xml -> .*b.launch.xml -> .*a.launch.xml"):
        read(cycle)
    odd = write(tmp_path / "odd.launch.xml", '<launch>\n  <include file="x.launch"/>\n</launch>\n')
    write(tmp_path / "x.launch", "<launch/>")
    with pytest.raises(LaunchError, match=r"unknown launch file type '.launch'"):
        read(odd)


def test_launch_file_of_a_package(prefix):
    write(prefix / "share" / "bringup" / "launch" / "robot.launch.xml", "<launch/>")
    write(prefix / "share" / "bringup" / "launch" / "sub" / "twice.launch.xml", "<launch/>")
    write(prefix / "share" / "bringup" / "config" / "twice.launch.xml", "<launch/>")
    find = launch_reader.launch_file_of_package
    assert find("bringup", "robot.launch.xml", [prefix]) == prefix / "share/bringup/launch/robot.launch.xml"
    assert find("bringup", "launch/sub/twice.launch.xml", [prefix]).is_file()
    with pytest.raises(LaunchError, match="several files named twice.launch.xml"):
        find("bringup", "twice.launch.xml", [prefix])
    with pytest.raises(LaunchError, match="has no launch file named nope.launch.xml"):
        find("bringup", "nope.launch.xml", [prefix])
    with pytest.raises(LaunchError, match="package 'nobody' is not in the ament index"):
        find("nobody", "x.launch.xml", [prefix])


# ---------------------------------------------------------------------------- conditions and groups


@pytest.mark.parametrize("attribute,value,started", [
    ("if", "true", True), ("if", "1", True), ("if", "TRUE", True), ("if", "false", False), ("if", "0", False),
    ("unless", "true", False), ("unless", "0", True),
])
def test_conditions(tmp_path, attribute, value, started):
    path = write(tmp_path / "c.launch.xml", f'<launch>\n  <node pkg="p" exec="e" {attribute}="{value}"/>\n</launch>\n')
    assert len(read(path).nodes) == int(started)


def test_conditions_on_children_and_bad_values(tmp_path):
    path = write(tmp_path / "c.launch.xml", """
        <launch>
          <arg name="debug" default="false"/>
          <node pkg="p" exec="e">
            <param name="a" value="1" if="$(var debug)"/>
            <param name="b" value="2" unless="$(var debug)"/>
            <remap from="x" to="y" if="$(var debug)"/>
          </node>
          <group if="$(var debug)">
            <unknown_tag/>
          </group>
        </launch>""")
    result = read(path)
    assert [(p.name, p.value) for p in result.nodes[0].parameters] == [("b", 2)]
    assert result.nodes[0].remappings == ()
    assert result.unsupported == []  # what a false condition skips is not reported
    bad = write(tmp_path / "bad.launch.xml", '<launch>\n  <node pkg="p" exec="e" if="yes"/>\n</launch>\n')
    with pytest.raises(LaunchError, match=r"bad.launch.xml:2: the condition if='yes' gives 'yes'; a condition must give true, false, 1 or 0"):
        read(bad)


def test_nested_groups_and_scoping(tmp_path):
    path = write(tmp_path / "g.launch.xml", """
        <launch>
          <let name="v" value="top"/>
          <group>
            <push_ros_namespace namespace="a"/>
            <let name="v" value="inner"/>
            <set_env name="E" value="1"/>
            <group>
              <push_ros_namespace namespace="b"/>
              <node pkg="p" exec="ab" name="$(var v)"/>
              <group>
                <push_ros_namespace namespace="/abs"/>
                <node pkg="p" exec="abs" namespace="c"/>
              </group>
            </group>
            <node pkg="p" exec="a"/>
          </group>
          <node pkg="p" exec="top" name="$(var v)"/>
          <group scoped="false">
            <push_ros_namespace namespace="leaky"/>
            <let name="v" value="leaked"/>
            <set_env name="LEAKED_ENV" value="yes"/>
          </group>
          <node pkg="p" exec="after" name="$(var v)"/>
          <group forwarding="false">
            <node pkg="p" exec="fresh" name="$(var v)"/>
          </group>
        </launch>""")
    with pytest.raises(LaunchError, match=r"g.launch.xml:25: <node>: launch configuration 'v' is not set"):
        read(path)
    path.write_text(path.read_text().replace('name="$(var v)"/>\n  </group>', '/>\n  </group>'))
    result = read(path)
    assert [(n.executable, n.name, n.namespace, dict(n.env)) for n in result.nodes] == [
        ("ab", "inner", "/a/b", {"E": "1"}),
        ("abs", None, "/abs/c", {"E": "1"}),
        ("a", None, "/a", {"E": "1"}),
        ("top", "top", None, {}),
        ("after", "leaked", "/leaky", {"LEAKED_ENV": "yes"}),
        ("fresh", None, "/leaky", {"LEAKED_ENV": "yes"}),
    ]


def write_include(tmp_path: Path, rule: str) -> Path:
    """inc.launch.xml: a node `included`, then `rule` (seen by the nodes after the include)."""
    return write(tmp_path / "inc.launch.xml", f"""
        <launch>
          <node pkg="p" exec="included"/>
          {rule}
        </launch>""")


def test_set_remap_applies_to_the_nodes_after_it_in_its_scope(tmp_path):
    write_include(tmp_path, '<set_remap from="inc" to="from_include"/>')
    path = write(tmp_path / "r.launch.xml", """
        <launch>
          <node pkg="p" exec="before"/>
          <set_remap from="/tf" to="tf"/>
          <group>
            <set_remap from="scan" to="lidar/scan"/>
            <node pkg="p" exec="grouped"><remap from="scan" to="own"/></node>
          </group>
          <group scoped="false"><set_remap from="cmd" to="cmd_safe"/></group>
          <group forwarding="false"><node pkg="p" exec="unforwarded"/></group>
          <include file="$(dirname)/inc.launch.xml"/>
          <node pkg="p" exec="after"/>
        </launch>""")
    result = read(path)
    # as launch_ros (jazzy) does, measured: the rules are one list in the launch configurations,
    # which a group copies without copying the list, so a rule set in a group (or an include)
    # stays when the list existed before it; a group without forwarding starts with none
    all_rules = (("/tf", "tf"), ("scan", "lidar/scan"), ("cmd", "cmd_safe"))
    assert [(n.executable, n.scope_remappings, n.remappings) for n in result.nodes] == [
        ("before", (), ()),
        ("grouped", (("/tf", "tf"), ("scan", "lidar/scan")), (("scan", "own"),)),
        ("unforwarded", (), ()),
        ("included", all_rules, ()),
        ("after", (*all_rules, ("inc", "from_include")), ()),
    ]
    # on the command line before the node's own rules (rcl applies the first that matches)
    assert result.nodes[1].ros_argument_list()[-6:] == ["-r", "/tf:=tf", "-r", "scan:=lidar/scan", "-r", "scan:=own"]
    yaml_path = write(tmp_path / "r.launch.yaml", """
        launch:
          - set_remap: {from: scan, to: lidar/scan}
          - node: {pkg: p, exec: e}
        """)
    assert read(yaml_path).nodes[0].scope_remappings == (("scan", "lidar/scan"),)
    assert read(yaml_path).unsupported == []


def test_set_parameter_applies_to_the_nodes_after_it_in_its_scope(tmp_path):
    write(tmp_path / "globals.yaml", "/**:\n  ros__parameters: {frame: map}\n")
    write_include(tmp_path, '<set_parameter name="from_include" value="1"/>')
    path = write(tmp_path / "p.launch.xml", """
        <launch>
          <arg name="rate" default="2.5"/>
          <group><set_parameter name="scoped" value="x"/><node pkg="p" exec="first"/></group>
          <node pkg="p" exec="before"/>
          <set_parameter name="use_sim_time" value="true"/>
          <group>
            <set_parameter name="rate" value="$(var rate)"/>
            <set_parameters_from_file filename="$(dirname)/globals.yaml"/>
            <node pkg="p" exec="grouped"><param name="rate" value="3"/></node>
          </group>
          <group forwarding="false"><node pkg="p" exec="unforwarded"/></group>
          <include file="$(dirname)/inc.launch.xml"/>
          <node pkg="p" exec="after"/>
        </launch>""")
    result = read(path)
    at = {line: launch_reader.Where(path, line) for line in (3, 5, 7, 8)}
    globals_file = tmp_path / "globals.yaml"
    sim_time, rate, from_file = (LaunchParameter("use_sim_time", True, where=at[5]), LaunchParameter("rate", 2.5, where=at[7]),
                                 LaunchParameter(file=globals_file, where=at[8]))
    # launch_ros (jazzy) as measured: a group copies the launch configurations, not the list of
    # global parameters in them, so what a group adds to a list that existed before it stays
    assert [(n.executable, n.parameters) for n in result.nodes] == [
        ("first", (LaunchParameter("scoped", "x", where=at[3]),)),
        ("before", ()),  # the first group made its own list
        ("grouped", (sim_time, rate, from_file, LaunchParameter("rate", 3))),
        ("unforwarded", ()),
        ("included", (sim_time, rate, from_file)),
        ("after", (sim_time, rate, from_file,
                   LaunchParameter("from_include", 1, where=launch_reader.Where(tmp_path / "inc.launch.xml", 3)))),
    ]
    # before the node's own parameters on the command line: the node's own value wins
    assert result.nodes[2].ros_argument_list()[1:] == [
        "-p", "use_sim_time:=true", "-p", "rate:=2.5", "--params-file", str(globals_file), "-p", "rate:=3"]
    assert result.unsupported == []
    yaml_path = write(tmp_path / "p.launch.yaml", """
        launch:
          - set_parameter: {name: gain, value: 0.5}
          - set_parameters_from_file: {filename: globals.yaml}
          - node: {pkg: p, exec: e}
        """)
    yaml_result = read(yaml_path)
    assert yaml_result.nodes[0].parameters == (LaunchParameter("gain", 0.5, where=launch_reader.Where(yaml_path, 2)),
                                               LaunchParameter(file=globals_file, where=launch_reader.Where(yaml_path, 3)))
    assert yaml_result.unsupported == []
    missing = write(tmp_path / "m.launch.xml", """
        <launch><set_parameters_from_file filename="nowhere.yaml"/></launch>""")
    with pytest.raises(LaunchError, match=r"m.launch.xml:1: parameters file .*nowhere.yaml does not exist"):
        read(missing)
    nameless = write(tmp_path / "n.launch.xml", """
        <launch><set_parameter value="1"/></launch>""")
    with pytest.raises(LaunchError, match=r"n.launch.xml:1: <set_parameter> needs the attribute `name`"):
        read(nameless)


def test_components_are_the_load_requests_launch_ros_makes(tmp_path):
    write(tmp_path / "talker.yaml", """
        /**:
          ros__parameters: {frame: map}
        /**/talker:
          ros__parameters: {rate_hz: 9.0}
        robot/talker:
          ros__parameters: {rate_hz: 4.0, limits: {max: 2}}
        """)
    path = write(tmp_path / "c.launch.xml", """
        <launch>
          <push_ros_namespace namespace="robot"/>
          <set_remap from="chatter" to="status"/>
          <set_parameter name="use_sim_time" value="true"/>
          <node_container pkg="rclcpp_components" exec="component_container" name="container">
            <composable_node pkg="demo" plugin="demo::Talker" name="talker">
              <param from="$(dirname)/talker.yaml"/>
              <param name="ids" value="1,2" value-sep=","/>
              <remap from="out" to="talk"/>
              <extra_arg name="use_intra_process_comms" value="true"/>
            </composable_node>
            <composable_node pkg="demo" plugin="demo::Skipped" name="skipped" if="false"/>
          </node_container>
          <load_composable_node target="/robot/container">
            <composable_node pkg="demo" plugin="demo::Listener" name="listener" namespace="/abs"/>
          </load_composable_node>
        </launch>""")
    result = read(path)
    assert result.unsupported == []
    [container] = result.nodes
    assert (container.executable, container.expected_fqn) == ("component_container", "/robot/container")
    talker, listener = container.components
    assert (talker.package, talker.plugin, talker.name, talker.namespace, talker.where.line) == (
        "demo", "demo::Talker", "talker", "/robot", 6)
    assert talker.remap_rules == ("chatter:=status", "out:=talk")
    assert talker.own_remappings == (("out", "talk"),)  # the <set_remap> of the scope is not its own
    # the `/**` and exact-name sections of the file (launch_ros's rule for components), typed
    assert talker.parameters == (("use_sim_time", 1, True), ("frame", 4, "map"), ("rate_hz", 3, 4.0),
                                 ("limits.max", 2, 2), ("ids", 7, (1, 2)))
    assert talker.extra_arguments == (("use_intra_process_comms", 1, True),)
    assert (listener.plugin, listener.namespace, listener.remap_rules, listener.parameters) == (
        "demo::Listener", "/abs", ("chatter:=status",), (("use_sim_time", 1, True),))
    assert listener.own_remappings == ()
    bad = write(tmp_path / "bad.launch.xml", """
        <launch>
          <node_container pkg="rclcpp_components" exec="component_container" name="c">
            <composable_node pkg="demo" plugin="demo::Talker" name="talker">
              <param name="mixed" value="1,a" value-sep=","/>
            </composable_node>
          </node_container>
        </launch>""")
    with pytest.raises(LaunchError, match=r"bad.launch.xml:3: <composable_node name=\"talker\">: parameter `mixed`: "):
        read(bad)


def test_a_required_argument_an_include_does_not_pass_names_the_include(tmp_path):
    write(tmp_path / "driver.launch.xml", """
        <launch>
          <arg name="port"/>
          <node pkg="p" exec="driver"/>
        </launch>""")
    path = write(tmp_path / "robot.launch.xml", """
        <launch>
          <group>
            <include file="$(dirname)/driver.launch.xml">
              <arg name="baud" value="115200"/>
            </include>
          </group>
        </launch>""")
    with pytest.raises(LaunchError) as raised:
        read(path)
    assert str(raised.value).endswith(
        "driver.launch.xml:2: launch argument 'port' is required (it has no default) and the <include> at "
        f"{launch_reader.shown(path)}:3 does not pass it; add <arg name=\"port\" value=\"...\"/> to that <include>")
    path.write_text(path.read_text().replace('<arg name="baud"', '<arg name="port" value="/dev/ttyUSB0"/><arg name="baud"'))
    assert [n.executable for n in read(path).nodes] == ["driver"]


def test_join_namespace():
    join = launch_reader.join_namespace
    assert join(None, None) is None
    assert join(None, "a") == "/a"
    assert join("/a", "b/") == "/a/b"
    assert join("/a", "/b") == "/b"
    assert join("/a", "") == "/a"
    assert join("/a", "/") == "/"


# ---------------------------------------------------------------------------- arguments


def test_argument_errors(tmp_path):
    path = write(tmp_path / "args.launch.xml", """
        <launch>
          <arg name="required"/>
          <arg name="mode" default="fast"><choice value="fast"/><choice value="slow"/></arg>
        </launch>""")
    with pytest.raises(LaunchError, match=r"args.launch.xml:2: launch argument 'required' is required .* was not given"):
        read(path)
    with pytest.raises(LaunchError, match=r"args.launch.xml:3: launch argument 'mode' is 'medium'; it must be one of fast, slow"):
        read(path, {"required": "x", "mode": "medium"})
    with pytest.raises(LaunchError, match=r"launch argument\(s\) requird given but not declared .* \(declared: mode, required\)"):
        read(path, {"required": "x", "requird": "y"})
    assert read(path, {"required": "x", "mode": "slow"}).nodes == []


# ---------------------------------------------------------------------------- unsupported and malformed


def test_unsupported_constructs_are_listed_with_file_and_line(tmp_path):
    path = write(tmp_path / "u.launch.xml", """
        <launch>
          <composable_node pkg="p" plugin="p::C" name="c"/>
          <load_composable_node target="/elsewhere"/>
          <executable cmd="ls"/>
          <node pkg="p" exec="e" launch-prefix="gdb --args">
            <param name="x" value="$(eval '1 + 1')"/>
            <unknown_child/>
          </node>
          <node pkg="p" exec="$(command 'echo hi')"/>
          <timer period="2.0"><node pkg="p" exec="late"/></timer>
          <node pkg="p" exec="ok"/>
        </launch>""")
    result = read(path)
    assert [n.executable for n in result.nodes] == ["ok"]
    listed = [(u.where.line, u.what.split(":")[0]) for u in result.unsupported]
    assert listed == [
        (2, "<composable_node>"), (3, "<load_composable_node>"), (4, "<executable>"),
        (5, "attribute `launch_prefix` of <node> is not supported"), (7, "<unknown_child> inside <node> is not supported"),
        (5, "<node>"), (9, "<node>"), (10, "<timer>"),
    ]
    assert "the substitution $(eval ...) is not supported" in result.unsupported[5].what
    with pytest.raises(LaunchError) as info:
        result.require_supported()
    message = str(info.value)
    assert "u.launch.xml uses what the launch reader does not support" in message
    assert "u.launch.xml:9: <node>: the substitution $(command ...) is not supported" in message
    assert "allow_unsupported: true" in message


@pytest.mark.parametrize("name,text,error", [
    ("a.launch.xml", "<launch>\n  <node pkg='p'\n</launch>\n", r"a.launch.xml:3: not well-formed XML"),
    ("b.launch.xml", "<robot/>\n", r"b.launch.xml:1: the root element is <robot>, not <launch>"),
    ("c.launch.xml", "<launch>\n  <node pkg='p'/>\n</launch>\n", r"c.launch.xml:2: <node> needs the attribute `exec`"),
    ("d.launch.yaml", "nodes: []\n", r"d.launch.yaml:1: a YAML launch file starts with `launch:`"),
    ("e.launch.yaml", "launch:\n- node: {pkg: p, exec: [\n", r"e.launch.yaml:3: YAML syntax error"),
    ("f.launch.yaml", "launch:\n- node: {pkg: p}\n  arg: {name: x}\n", r"f.launch.yaml:2: each entity is a mapping with one key"),
    ("g.launch.xml", "<launch>\n  <node pkg='p' exec='e'><param name='x'/></node>\n</launch>\n",
     r"g.launch.xml:2: <param name=\"x\"> needs `value`, `from` or nested <param> entries"),
    ("h.launch.xml", "<launch>\n  <node pkg='p' exec='e'><param from='none.yaml'/></node>\n</launch>\n",
     r"h.launch.xml:2: parameters file none.yaml does not exist|h.launch.xml:2: parameters file .*none.yaml does not exist"),
])
def test_malformed_launch_files(tmp_path, name, text, error):
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(LaunchError, match=error):
        read(path)


def test_missing_launch_file(tmp_path):
    with pytest.raises(LaunchError, match=r"launch file .*absent.launch.xml does not exist"):
        read(tmp_path / "absent.launch.xml")


# ---------------------------------------------------------------------------- other launch sources


def test_play_launch_record(tmp_path):
    record = {
        "node": [
            {"executable": "talker", "package": "demo", "name": "/robot/talker", "namespace": "/robot",
             "params": [["rate", "5.0"], ["label:=hi", "True"]], "params_files": ["/**:\n  ros__parameters: {a: 1}\n"],
             "remaps": [["chatter", "chat"]], "ros_args": None, "args": ["--x"], "cmd": ["/elsewhere/talker"],
             "env": [["K", "V"]], "respawn": False, "respawn_delay": None, "global_params": []},
            {"executable": "plain", "package": None, "name": None, "namespace": None, "cmd": ["/opt/bin/plain", "--a"]},
        ],
        "container": [{"name": "/c", "namespace": "/"}],
        "load_node": [],
        "lifecycle_node": [],
        "file_data": {},
    }
    path = tmp_path / "record.json"
    path.write_text(json.dumps(record))
    result = read(path)
    talker, plain = result.nodes
    assert (talker.package, talker.executable, talker.name, talker.namespace) == ("demo", "talker", "talker", "/robot")
    assert talker.parameters == (LaunchParameter(file_text="/**:\n  ros__parameters: {a: 1}\n"), LaunchParameter("rate", 5.0),
                                 LaunchParameter("label", "hi"))
    assert talker.remappings == (("chatter", "chat"),)
    assert talker.arguments == ("--x",)
    assert dict(talker.env) == {"K": "V"}
    assert (plain.package, plain.executable, plain.name, plain.namespace) == (None, "/opt/bin/plain", None, None)
    assert [u.what for u in result.unsupported] == [
        "container[0] (/c): composable nodes and their containers are not supported"]
    written = []
    args = talker.ros_argument_list(lambda p: written.append(p.file_text) or tmp_path / "p.yaml")
    assert args[:7] == ["--ros-args", "-r", "__node:=talker", "-r", "__ns:=/robot", "--params-file", str(tmp_path / "p.yaml")]
    assert written == ["/**:\n  ros__parameters: {a: 1}\n"]


@pytest.mark.parametrize("text,error", [
    ("[1, 2", "not valid JSON"), ("{}", "no `node` list"), ('{"node": [{}]}', r"node\[0\] has no `executable`"),
    ('{"node": [{"executable": "x", "params": "a"}]}', r"node\[0\].params is not a list of \[name, value\] pairs"),
])
def test_bad_records(tmp_path, text, error):
    path = tmp_path / "record.json"
    path.write_text(text)
    with pytest.raises(LaunchError, match=error):
        read(path)


def _launch_ros_importable() -> bool:
    try:
        return importlib.util.find_spec("launch_ros") is not None
    except (ImportError, ValueError):
        return False


@pytest.mark.skipif(_launch_ros_importable(), reason="launch_ros is importable here: the error path does not apply")
def test_python_launch_files_need_launch_ros(tmp_path):
    path = write(tmp_path / "robot.launch.py", "from launch import LaunchDescription\n"
                                               "def generate_launch_description():\n    return LaunchDescription([])\n")
    with pytest.raises(LaunchError) as info:
        read(path)
    message = str(info.value)
    assert "robot.launch.py is a Python launch file" in message
    assert "ROS 2 PyPI wheels do not include them" in message
    assert "run `rmw-introspect install-launch` once" in message  # the one command (issue 47, finding 8)
    # also when an XML file includes it, with the line of the include
    top = write(tmp_path / "top.launch.xml", '<launch>\n  <include file="robot.launch.py"/>\n</launch>\n')
    with pytest.raises(LaunchError, match=r"top.launch.xml:2: .*robot.launch.py is a Python launch file"):
        read(top)
