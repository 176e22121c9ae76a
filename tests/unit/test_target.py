"""Target options → argv: ament index lookup, --ros-args, parameter encoding, merging."""

from __future__ import annotations

import os
import re
import sys
from pathlib import Path

import pytest

from pytest_rmw_introspect.errors import (
    ExecutableNotFound,
    TargetConfigError,
    TargetError,
)
from pytest_rmw_introspect.run import executables, failure_hints, target
from pytest_rmw_introspect.run.executables import build_argv
from pytest_rmw_introspect.run.target import (
    TargetSpec,
    merge,
    ros_argument_value,
    ros_arguments,
)


def make_prefix(root: Path, package: str, executables: dict[str, bool] | None = None) -> Path:
    index = root / "share" / "ament_index" / "resource_index" / "packages"
    index.mkdir(parents=True, exist_ok=True)
    (index / package).write_text("")
    lib = root / "lib" / package
    lib.mkdir(parents=True, exist_ok=True)
    for name, executable in (executables or {}).items():
        f = lib / name
        f.write_text("#!/bin/sh\n")
        f.chmod(0o755 if executable else 0o644)
    return root


# ---------------------------------------------------------------------------- ament index


def test_executable_is_found_in_the_prefix_that_provides_the_package(tmp_path):
    a = make_prefix(tmp_path / "a", "other_pkg", {"x": True})
    b = make_prefix(tmp_path / "b", "demo", {"talker": True})
    spec = TargetSpec.from_mapping({"package": "demo", "executable": "talker"})
    assert build_argv(spec, [a, b]) == [str(b / "lib" / "demo" / "talker")]


def test_first_prefix_providing_the_package_wins_like_ros2_run(tmp_path):
    a = make_prefix(tmp_path / "a", "demo", {"talker": True})
    b = make_prefix(tmp_path / "b", "demo", {"talker": True})
    assert executables.find_executable("demo", "talker", [a, b]) == a / "lib" / "demo" / "talker"


def test_missing_package_lists_the_searched_prefixes(tmp_path):
    a = make_prefix(tmp_path / "a", "other", {})
    with pytest.raises(ExecutableNotFound) as info:
        executables.find_executable("demo", "talker", [a])
    msg = str(info.value)
    assert "Package 'demo' was not found in the ament index" in msg
    assert str(a) in msg
    assert info.value.searched == [str(a)]


def test_missing_executable_lists_the_executables_the_package_has(tmp_path):
    a = make_prefix(tmp_path / "a", "demo", {"listener": True, "talker_py": True, "data.txt": False})
    with pytest.raises(ExecutableNotFound) as info:
        executables.find_executable("demo", "talker", [a])
    msg = str(info.value)
    assert "Executable 'talker' not found in package 'demo'" in msg
    assert "listener, talker_py" in msg
    assert "data.txt" not in msg
    assert info.value.found == ["listener", "talker_py"]


def test_shadowed_executable_in_a_later_prefix_is_mentioned(tmp_path):
    a = make_prefix(tmp_path / "a", "demo", {"listener": True})
    b = make_prefix(tmp_path / "b", "demo", {"talker": True})
    with pytest.raises(ExecutableNotFound, match="shadows them"):
        executables.find_executable("demo", "talker", [a, b])


def test_non_executable_file_is_refused(tmp_path):
    a = make_prefix(tmp_path / "a", "demo", {"talker": False})
    with pytest.raises(ExecutableNotFound, match="not executable"):
        executables.find_executable("demo", "talker", [a])


# ---------------------------------------------------------------------------- argv


def test_script_and_module_run_with_the_given_interpreter(tmp_path):
    script = tmp_path / "node.py"
    script.write_text("pass\n")
    spec = TargetSpec.from_mapping({"script": "node.py"}, base_dir=tmp_path)
    assert build_argv(spec, python="/py") == ["/py", str(script)]
    spec = TargetSpec.from_mapping({"module": "pkg.node", "arguments": ["--fast"]})
    assert build_argv(spec, python="/py") == ["/py", "-m", "pkg.node", "--fast"]


def test_default_interpreter_is_sys_executable(tmp_path):
    spec = TargetSpec.from_mapping({"module": "x"})
    assert build_argv(spec)[0] == sys.executable


def test_missing_script_is_executable_not_found(tmp_path):
    spec = TargetSpec.from_mapping({"script": "nope.py"}, base_dir=tmp_path)
    with pytest.raises(ExecutableNotFound, match=r"nope\.py does not exist"):
        build_argv(spec)


def test_command_is_looked_up_on_path_and_relative_to_the_base_dir(tmp_path):
    spec = TargetSpec.from_mapping({"command": ["sh", "-c", "true"]})
    argv = build_argv(spec)
    assert os.path.basename(argv[0]) == "sh" and argv[1:] == ["-c", "true"]
    tool = tmp_path / "bin" / "node"
    tool.parent.mkdir()
    tool.write_text("#!/bin/sh\n")
    tool.chmod(0o755)
    spec = TargetSpec.from_mapping({"command": "bin/node --x"}, base_dir=tmp_path)
    assert build_argv(spec) == [str(tool), "--x"]


def test_unknown_command_is_executable_not_found():
    spec = TargetSpec.from_mapping({"command": ["definitely-not-a-command-xyz"]})
    with pytest.raises(ExecutableNotFound, match="not found on PATH"):
        build_argv(spec)


def test_ros_args_namespace_name_remappings_parameters_params_file(tmp_path):
    params = tmp_path / "p.yaml"
    params.write_text("{}\n")
    spec = TargetSpec.from_mapping(
        {
            "module": "m",
            "arguments": ["a1"],
            "namespace": "robot1",
            "node_name": "talker2",
            "remappings": {"chatter": "/talk", "/x": "/y"},
            "parameters": {"rate": 2.0, "name": "true", "count": 3, "on": True, "ids": [1, 2], "nested": {"a": "b c"}},
            "params_file": "p.yaml",
        },
        base_dir=tmp_path,
    )
    argv = build_argv(spec, python="py")
    assert argv == [
        "py", "-m", "m", "a1",
        "--ros-args",
        "-r", "__ns:=/robot1",
        "-r", "__node:=talker2",
        "-r", "chatter:=/talk",
        "-r", "/x:=/y",
        "-p", "rate:=2.0",
        "-p", "name:='true'",
        "-p", "count:=3",
        "-p", "on:=true",
        "-p", "ids:=[1, 2]",
        "-p", "nested.a:=b c",
        "--params-file", str(params),
    ]


def test_no_ros_args_when_nothing_to_pass():
    assert ros_arguments(TargetSpec.from_mapping({"module": "m"})) == []


def test_remappings_accept_a_list_of_rules():
    spec = TargetSpec.from_mapping({"module": "m", "remappings": ["a:=b", ["c", "d"]]})
    assert spec.remappings == (("a", "b"), ("c", "d"))


def test_missing_params_file_is_a_config_error(tmp_path):
    spec = TargetSpec.from_mapping({"module": "m", "params_file": "nope.yaml"}, base_dir=tmp_path)
    with pytest.raises(TargetConfigError, match="nope.yaml does not exist"):
        build_argv(spec)


@pytest.mark.parametrize(
    "value, encoded",
    [
        (True, "true"),
        (False, "false"),
        (0, "0"),
        (-7, "-7"),
        (1.0, "1.0"),
        (2.5, "2.5"),
        (1e-5, "1.0e-05"),
        (1e20, "1.0e+20"),
        ("hello", "hello"),
        ("", "''"),
        ("true", "'true'"),
        ("1", "'1'"),
        ("1.5", "'1.5'"),
        ("x: y", "'x: y'"),
        ("a,b", "'a,b'"),
        ("/ns/topic", "/ns/topic"),
        ([1, 2], "[1, 2]"),
        ([1.0, 2.5], "[1.0, 2.5]"),
        (["a", "true"], "[a, 'true']"),
        ([True, False], "[true, false]"),
        ([], "[]"),
    ],
)
def test_parameter_values_are_yaml_encoded(value, encoded):
    assert ros_argument_value(value) == encoded


def test_parameter_values_round_trip_through_yaml():
    import yaml

    for value in [True, 3, 2.0, 1e-9, "str", "true", "", "null", "~", "0x10", [1, 2], ["a", "b"]]:
        assert yaml.safe_load(ros_argument_value(value)) == value


def test_unsupported_parameter_value_is_refused():
    with pytest.raises(TargetConfigError, match="cannot hold"):
        ros_argument_value(object())


# ---------------------------------------------------------------------------- validation & merging


def test_no_target_is_a_config_error():
    with pytest.raises(TargetConfigError, match="No target to run"):
        TargetSpec().validate()


def test_incomplete_package_executable():
    with pytest.raises(TargetConfigError, match="`executable` is missing"):
        TargetSpec.from_mapping({"package": "demo"}).validate()


def test_two_targets_in_one_layer_is_ambiguous():
    with pytest.raises(TargetConfigError, match="Ambiguous target"):
        TargetSpec.from_mapping({"module": "m", "script": "x.py"}).validate()


def test_a_package_without_executable_lists_the_executables_it_has(tmp_path, monkeypatch):
    (tmp_path / "share" / "ament_index" / "resource_index" / "packages").mkdir(parents=True)
    (tmp_path / "share" / "ament_index" / "resource_index" / "packages" / "cam_pkg").write_text("")
    (tmp_path / "lib" / "cam_pkg").mkdir(parents=True)
    for name in ("camera_node", "lidar_node"):
        (tmp_path / "lib" / "cam_pkg" / name).write_text("#!/bin/sh\n")
        (tmp_path / "lib" / "cam_pkg" / name).chmod(0o755)
    monkeypatch.setenv("AMENT_PREFIX_PATH", str(tmp_path))
    with pytest.raises(TargetConfigError) as info:
        TargetSpec.from_mapping({"package": "cam_pkg"}).validate()
    message = str(info.value)
    assert message == ("Target package/executable is incomplete: `executable` is missing for package 'cam_pkg'. "
                       "The package has these executables: camera_node, lidar_node; choose one with `executable` "
                       "(--executable on the command line).")
    assert "None" not in message
    with pytest.raises(TargetConfigError, match="`package` is missing \\(executable 'camera_node' was given\\)"):
        TargetSpec.from_mapping({"executable": "camera_node"}).validate()


def test_a_timeout_set_after_loading_is_checked_with_the_same_words():
    spec = TargetSpec.from_mapping({"module": "m"})
    from dataclasses import replace

    with pytest.raises(TargetConfigError, match="`timeout` must be a number of seconds more than 0 and at most 86400, got 0"):
        replace(spec, timeout=0.0).validate()


def test_unknown_key_is_reported_with_the_source():
    with pytest.raises(TargetConfigError) as info:
        TargetSpec.from_mapping({"pakage": "x"}, source="contracts/a.yaml: target")
    assert "contracts/a.yaml: target" in str(info.value)
    assert "'pakage'" in str(info.value)
    assert isinstance(info.value, TargetError)


@pytest.mark.parametrize(
    "options, message",
    [
        ({"timeout": "soon"}, "`timeout` must be a number of seconds"),
        ({"settle": True}, "`settle` must be a number of seconds"),
        ({"settle": float("inf")}, "`settle` must be a number of seconds, got inf"),
        ({"timeout": float("nan")}, "`timeout` must be a number of seconds, got nan"),
        ({"settle": 90_000}, "`settle` must be a number of seconds from 0 to 86400"),
        ({"horizon": -1}, "`horizon` must be a number of seconds from 0 to 86400"),
        # -1 and 0 are refused with the same words: the range a timeout takes
        ({"timeout": -1}, "`timeout` must be a number of seconds more than 0 and at most 86400, got -1"),
        ({"timeout": 0}, "`timeout` must be a number of seconds more than 0 and at most 86400, got 0"),
        ({"horizon": "10s"}, "`horizon` must be a number of seconds"),
        ({"remappings": 3}, "`remappings` must be"),
        ({"parameters": ["a"]}, "`parameters` must be a mapping"),
        ({"command": {"a": 1}}, "`command` must be a list of strings"),
        ({"package": ""}, "`package` must be a non-empty string"),
        ({"lifecycle": "configured"}, "`lifecycle` must be one of active, inactive, unconfigured, none, got 'configured'"),
        ({"lifecycle": True}, "`lifecycle` must be one of active"),
        ({"read_parameters": "maybe"}, "`read_parameters` must be true or false, got 'maybe'"),
        ({"parameters": False}, "`read_parameters: false` stops reading the node's parameters"),
    ],
)
def test_bad_option_values(options, message):
    with pytest.raises(TargetConfigError, match=message):
        TargetSpec.from_mapping(options)


def test_later_layer_wins_and_a_new_kind_replaces_the_old_one(tmp_path):
    contract_dir = tmp_path / "contracts"
    test_dir = tmp_path / "tests"
    spec = merge(
        ({"package": "demo", "executable": "talker", "namespace": "/a", "timeout": 5}, contract_dir, "contract"),
        ({"script": "nodes/t.py", "namespace": "/b"}, test_dir, "marker"),
    )
    spec.validate()
    assert spec.kind == "script"
    assert spec.package is None and spec.executable is None
    assert spec.script == test_dir / "nodes" / "t.py"
    assert spec.namespace == "/b"
    assert spec.timeout == 5.0


def test_layer_without_kind_keeps_the_inherited_target(tmp_path):
    spec = merge(
        ({"package": "demo", "executable": "talker"}, None, "contract"),
        ({"node_name": "renamed", "env": {"A": 1, "B": True}}, None, "marker"),
    )
    assert spec.describe() == "demo/talker"
    assert spec.node_name == "renamed"
    assert spec.env == {"A": "1", "B": "1"}


def test_defaults_and_describe():
    spec = TargetSpec.from_mapping({"command": ["ros2", "run", "a b"]})
    assert spec.effective_timeout() == target.DEFAULT_TIMEOUT
    assert spec.effective_settle() == target.DEFAULT_SETTLE
    assert spec.effective_horizon() == target.DEFAULT_HORIZON == 10.0
    assert TargetSpec.from_mapping({"module": "m", "horizon": 0}).effective_horizon() == 0.0
    assert spec.describe() == "`ros2 run 'a b'`"
    assert TargetSpec.from_mapping({"module": "x.y"}).describe() == "module x.y"


def test_stimuli_are_fully_resolved_names_once_each_in_order():
    spec = TargetSpec.from_mapping({"module": "m", "stimuli": ["/camera_info", "/reset", "/camera_info"]})
    assert spec.stimuli == ("/camera_info", "/reset")
    # One string: names separated by commas or spaces (the CLI, an ini-like contract value).
    assert TargetSpec.from_mapping({"module": "m", "stimuli": "/a, /b/_action/send_goal /c"}).stimuli == (
        "/a", "/b/_action/send_goal", "/c")
    assert TargetSpec.from_mapping({"module": "m"}).stimuli == ()
    # A stronger layer replaces the list, an empty one turns them off.
    layered = merge(({"module": "m", "stimuli": ["/a"]}, None, "contract"), ({"stimuli": []}, None, "marker"))
    assert layered.stimuli == ()
    assert TargetSpec.from_mapping({"module": "m", "stimuli": ["/a"]}).to_mapping() == {"module": "m", "stimuli": ["/a"]}


@pytest.mark.parametrize("value, message", [
    (["camera_info"], "`stimuli`: 'camera_info' is not a fully resolved topic or service name"),
    (["~/reset"], "'~/reset' is not a fully resolved"),
    (["/9lives"], "'/9lives' is not a fully resolved"),
    (["/a/"], "'/a/' is not a fully resolved"),
    ("/a,,/b//c", "'/b//c' is not a fully resolved"),
    ([1], "`stimuli` must be a list of topic or service names"),
    ({"/a": 1}, "`stimuli` must be a list of topic or service names"),
])
def test_bad_stimuli_are_refused_with_the_name(value, message):
    with pytest.raises(TargetConfigError, match=re.escape(message)) as info:
        TargetSpec.from_mapping({"module": "m", "stimuli": value}, source="contract c.yaml: target")
    assert str(info.value).startswith("contract c.yaml: target: ")


def test_to_mapping_round_trips():
    options = {"module": "m", "remappings": {"a": "b"}, "parameters": {"p": 1}, "timeout": 3.0}
    assert TargetSpec.from_mapping(options).to_mapping() == options


# ---------------------------------------------------------------------------- entry points, console scripts


def test_an_entry_point_target_calls_the_function_like_its_console_script(tmp_path):
    spec = TargetSpec.from_mapping({"entry_point": "my_pkg.camera:main", "arguments": ["--x"], "namespace": "/a"})
    assert spec.kind == "entry_point" and spec.describe() == "entry point my_pkg.camera:main"
    argv = executables.build_argv(spec, python="/py")
    assert argv[:2] == ["/py", "-c"] and argv[3:] == ["my_pkg.camera:main", "main", "--x", "--ros-args", "-r", "__ns:=/a"]
    module = tmp_path / "ep_demo_mod.py"
    module.write_text("import sys\ndef main():\n    print(sys.argv)\n    return 3\n")
    import subprocess

    run = subprocess.run([sys.executable, *argv[1:3], "ep_demo_mod:main", "camera", "--flag"], cwd=tmp_path,
                         capture_output=True, text=True, env={**os.environ, "PYTHONPATH": str(tmp_path)})
    assert run.returncode == 3 and run.stdout.strip() == "['camera', '--flag']", run


@pytest.mark.parametrize("value", ["my_pkg.camera", "my_pkg:", ":main", "my pkg:main", "a:b:c", 3])
def test_a_malformed_entry_point_is_refused(value):
    with pytest.raises(TargetConfigError, match="`entry_point` must be a function as `package.module:function`"):
        TargetSpec.from_mapping({"entry_point": value})


def test_an_entry_point_replaces_another_kind_of_target():
    spec = TargetSpec.from_mapping({"script": "a.py"}).merged({"entry_point": "m:f"})
    assert spec.kind == "entry_point" and spec.script is None


def _fake_distribution(site, name, scripts):
    info = site / f"{name.replace('-', '_')}-1.0.dist-info"
    info.mkdir(parents=True)
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {name}\nVersion: 1.0\n")
    lines = "".join(f"{k} = {v}\n" for k, v in scripts.items())
    (info / "entry_points.txt").write_text(f"[console_scripts]\n{lines}")


def test_a_package_executable_falls_back_to_a_console_script(tmp_path):
    site = tmp_path / "site"
    _fake_distribution(site, "my-camera_pkg", {"camera": "my_camera_pkg.camera:main"})
    assert executables.console_scripts("my_camera_pkg", [str(site)]) == {"camera": "my_camera_pkg.camera:main"}
    assert executables.console_scripts("My-Camera-Pkg", [str(site)]) == {"camera": "my_camera_pkg.camera:main"}
    assert executables.console_scripts("no_such_pkg", [str(site)]) is None  # no such distribution
    spec = TargetSpec.from_mapping({"package": "my_camera_pkg", "executable": "camera",
                                    "env": {"PYTHONPATH": str(site)}})
    argv = executables.build_argv(spec, prefixes=[], python="/py")
    assert argv[3:5] == ["my_camera_pkg.camera:main", "camera"]
    with pytest.raises(ExecutableNotFound) as info:
        executables.build_argv(TargetSpec.from_mapping({"package": "my_camera_pkg", "executable": "lidar",
                                                   "env": {"PYTHONPATH": str(site)}}), prefixes=[])
    assert str(info.value) == ("Executable 'lidar' not found in package 'my_camera_pkg': the package is installed as "
                               "a Python distribution (pip), not in the ament index, and its console scripts are: camera.")


def test_a_mistyped_console_script_lists_the_packages_scripts_and_suggests_the_closest(tmp_path):
    # `pip install -e .` of an ament_python package: no ament index entry, console scripts only
    site = tmp_path / "site"
    _fake_distribution(site, "sensor_relay", {"relay": "sensor_relay.relay:main", "monitor": "sensor_relay.mon:main"})
    spec = TargetSpec.from_mapping({"package": "sensor_relay", "executable": "rleay", "env": {"PYTHONPATH": str(site)}})
    with pytest.raises(ExecutableNotFound) as info:
        executables.build_argv(spec, prefixes=[tmp_path / "empty_prefix"])
    message = str(info.value)
    assert message.startswith("Executable 'rleay' not found in package 'sensor_relay': the package is installed "
                              "as a Python distribution (pip), not in the ament index"), message
    assert "its console scripts are: monitor, relay. Did you mean 'relay'?" in message
    assert "was not found in the ament index" not in message
    assert info.value.found == ["monitor", "relay"]


def test_a_distribution_without_console_scripts_says_how_to_declare_them(tmp_path):
    site = tmp_path / "site"
    _fake_distribution(site, "sensor_relay", {})
    spec = TargetSpec.from_mapping({"package": "sensor_relay", "executable": "relay", "env": {"PYTHONPATH": str(site)}})
    with pytest.raises(ExecutableNotFound, match=r"it has no console scripts \(declare them under `entry_points="):
        executables.build_argv(spec, prefixes=[])


def test_a_package_in_neither_place_says_both_were_searched(tmp_path):
    spec = TargetSpec.from_mapping({"package": "no_such_pkg", "executable": "x", "env": {"PYTHONPATH": str(tmp_path)}})
    with pytest.raises(ExecutableNotFound) as info:
        executables.build_argv(spec, prefixes=[tmp_path])
    message = str(info.value)
    assert message.startswith("Package 'no_such_pkg' was not found in the ament index.")
    assert "No Python distribution named 'no_such_pkg' is installed either" in message


def test_a_mistyped_executable_of_an_ament_package_gets_the_closest_suggested(tmp_path):
    (tmp_path / "share" / "ament_index" / "resource_index" / "packages").mkdir(parents=True)
    (tmp_path / "share" / "ament_index" / "resource_index" / "packages" / "cam_pkg").write_text("")
    (tmp_path / "lib" / "cam_pkg").mkdir(parents=True)
    for name in ("camera_node", "lidar_node"):
        exe = tmp_path / "lib" / "cam_pkg" / name
        exe.write_text("#!/bin/sh\n")
        exe.chmod(0o755)
    spec = TargetSpec.from_mapping({"package": "cam_pkg", "executable": "camera_nod", "env": {"PYTHONPATH": str(tmp_path)}})
    with pytest.raises(ExecutableNotFound) as info:
        executables.build_argv(spec, prefixes=[tmp_path])
    assert str(info.value).endswith("The package has these executables: camera_node, lidar_node. "
                                    "Did you mean 'camera_node'?"), str(info.value)


def test_messages_show_a_console_script_as_the_users_command_shell_quoted(tmp_path):
    site = tmp_path / "site"
    _fake_distribution(site, "sensor_relay", {"relay": "sensor_relay.relay:main"})
    bin_dir = tmp_path / "venv" / "bin"
    bin_dir.mkdir(parents=True)
    python = bin_dir / "python"
    spec = TargetSpec.from_mapping({"package": "sensor_relay", "executable": "relay", "env": {"PYTHONPATH": str(site)},
                                    "parameters": {"label": "a b"}})
    argv = executables.build_argv(spec, prefixes=[], python=str(python))
    assert argv[1] == "-c"  # started through our launcher ...
    assert executables.command_as_typed(argv) == ["relay", "--ros-args", "-p", "label:=a b"]  # ... shown as the script
    (bin_dir / "relay").write_text("#!/bin/sh\n")
    shown = executables.command_as_typed(argv)
    assert shown[0] == str(bin_dir / "relay")
    from pytest_rmw_introspect.errors import TargetExited

    message = str(TargetExited("sensor_relay/relay", 1, "boom", argv=shown))
    assert f"Command: {bin_dir / 'relay'} --ros-args -p 'label:=a b'" in message
    assert "importlib" not in message
    assert executables.command_as_typed(["/usr/bin/env", "x"]) == ["/usr/bin/env", "x"]  # anything else as it is


def test_a_module_with_main_but_no_main_block_gets_a_hint(tmp_path):
    (tmp_path / "pkg_a").mkdir()
    (tmp_path / "pkg_a" / "__init__.py").write_text("")
    (tmp_path / "pkg_a" / "camera.py").write_text("def main():\n    pass\n")
    (tmp_path / "pkg_a" / "runs.py").write_text("def main():\n    pass\n\nif __name__ == '__main__':\n    main()\n")
    hint = failure_hints.module_main_hint("pkg_a.camera", tmp_path / "pkg_a" / "camera.py")
    assert hint is not None and "defines main() but has no `if __name__ == \"__main__\":` block" in hint
    assert "`entry_point: pkg_a.camera:main`" in hint
    assert failure_hints.module_main_hint("pkg_a.runs", tmp_path / "pkg_a" / "runs.py") is None
    assert failure_hints.module_main_hint("pkg_a.missing", tmp_path / "pkg_a" / "missing.py") is None
    assert failure_hints.module_main_hint("pkg_a.missing", None) is None


def test_lifecycle_and_read_parameters_defaults_and_layers():
    spec = TargetSpec.from_mapping({"module": "m"})
    assert spec.effective_lifecycle() == "active" and spec.effective_read_parameters() is True
    spec = merge(({"lifecycle": "inactive", "read_parameters": "false"}, None, "ini file"),
                 ({"module": "m", "lifecycle": "NONE"}, None, "contract"))
    assert (spec.lifecycle, spec.read_parameters) == ("none", False)
    assert spec.to_mapping() == {"module": "m", "lifecycle": "none", "read_parameters": False}


def test_env_entries_the_runner_owns_are_refused_with_the_option_to_use():
    with pytest.raises(TargetConfigError) as info:
        TargetSpec.from_mapping({"script": "node.py", "env": {"RMW_INTROSPECT_SETTLE_MS": "500", "MY_VAR": "1",
                                                              "RMW_INTROSPECT_OUTPUT": "/tmp/x.json"}},
                                source="contract contracts/node.interfaces.yaml")
    message = str(info.value)
    assert message.startswith("contract contracts/node.interfaces.yaml: `env` sets middleware variables the runner owns")
    assert "RMW_INTROSPECT_SETTLE_MS: set the target option `settle (seconds)` instead" in message
    assert "RMW_INTROSPECT_OUTPUT: the runner sets it for every capture" in message
    assert "MY_VAR" not in message


def test_other_middleware_variables_pass_through_env():
    spec = TargetSpec.from_mapping({"script": "node.py", "env": {"RMW_INTROSPECT_VERBOSE": "1",
                                                                 "RMW_INTROSPECT_DELIVERY": True}})
    assert spec.env == {"RMW_INTROSPECT_VERBOSE": "1", "RMW_INTROSPECT_DELIVERY": "1"}

