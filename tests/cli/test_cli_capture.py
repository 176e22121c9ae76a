"""`rmw-introspect capture` on real rclpy nodes: formats, raw vs. filtered endpoints, -o, errors."""

from __future__ import annotations

import json
import shutil
import sys

import yaml
from cli_helpers import NODES
from sample_contracts import talker_nodes

from pytest_rmw_introspect.model import contract as contract_module

TALKER_NODES_YAML = talker_nodes()


def test_capture_yaml_to_a_file_is_a_contract_with_a_relative_target_that_checks(cli):
    shutil.copy(NODES / "talker.py", cli.path / "talker.py")
    result = cli("capture", "--script", "talker.py", "-o", "contracts/talker.interfaces.yaml")
    assert result.returncode == 0, result
    assert result.stdout == ""
    assert "wrote contracts/talker.interfaces.yaml" in result.stderr
    text = cli.read("contracts/talker.interfaces.yaml")
    # the target block names the script relative to the contract file
    assert "target:\n  script: ../talker.py\nnodes:\n" in text
    assert text.endswith(TALKER_NODES_YAML)
    loaded = contract_module.loads(text)
    assert loaded.target == {"script": "../talker.py"}
    assert loaded.options == {}

    # checked from another directory, the script is found relative to the contract
    (cli.path / "elsewhere").mkdir()
    check = cli("check", "../contracts/talker.interfaces.yaml", cwd=cli.path / "elsewhere")
    assert check.returncode == 0, check
    assert "../contracts/talker.interfaces.yaml: matches (/talker)" in check.stdout


def test_capture_prints_yaml_with_the_target_options_used(cli):
    result = cli("capture", "--script", NODES / "talker.py", "--namespace", "robot", "--remap", "chatter:=speech",
                 "--param", "depth:=5", "--param", "reliability:=best_effort", "--env", "RMWI_TEST=1",
                 "--settle", "0.05")
    assert result.returncode == 0, result
    doc = yaml.safe_load(result.stdout)
    assert doc["target"] == {
        "script": str(NODES / "talker.py"),  # far away from the current directory: absolute
        "namespace": "/robot",
        "remappings": {"chatter": "speech"},
        "parameters": {"depth": 5, "reliability": "best_effort"},
        "env": {"RMWI_TEST": "1"},
        "settle": 0.05,
    }
    assert list(doc["nodes"]) == ["/robot/talker"]
    [pub] = doc["nodes"]["/robot/talker"]["publishers"]
    assert pub["name"] == "/robot/speech"
    assert pub["qos"] == {"history": "KEEP_LAST", "depth": 5, "reliability": "BEST_EFFORT", "durability": "VOLATILE"}
    contract_module.loads(result.stdout)  # a valid contract


def test_capture_json_is_the_contract_nodes(cli):
    result = cli("capture", "--format", "json", "--script", NODES / "talker.py")
    assert result.returncode == 0, result
    assert json.loads(result.stdout) == yaml.safe_load(TALKER_NODES_YAML)["nodes"]


def test_capture_of_a_command_after_double_dash(cli):
    result = cli("capture", "--format", "json", "--", sys.executable, NODES / "talker.py")
    assert result.returncode == 0, result
    assert list(json.loads(result.stdout)) == ["/talker"]


def test_capture_nodl_documents(cli):
    result = cli("capture", "--format", "nodl", "--script", NODES / "qos_node.py")
    assert result.returncode == 0, result
    assert "# node: /sensors/qos_node\n" in result.stdout
    [doc] = [d for d in yaml.safe_load_all(result.stdout) if d is not None]
    assert doc["nodl_version"] == 2
    assert set(doc) == {"nodl_version", "publishers", "subscriptions"}  # empty lists are left out
    pubs = {p["name"]: p for p in doc["publishers"]}
    assert pubs["/map"] == {"name": "/map", "type": "std_msgs/msg/String",
                            "qos": {"history": "KEEP_LAST", "depth": 1, "reliability": "RELIABLE",
                                    "durability": "TRANSIENT_LOCAL"}}
    assert pubs["/sensors/scan"]["qos"]["reliability"] == "BEST_EFFORT"
    subs = {s["name"]: s for s in doc["subscriptions"]}
    assert subs["/sensors/commands"]["qos"]["history"] == "KEEP_ALL"
    assert "depth" not in subs["/sensors/commands"]["qos"]
    assert subs["/sensors/commands"]["qos"]["deadline_ns"] == 100_000_000
    for entry in doc["publishers"] + doc["subscriptions"]:  # NoDL v2 topic endpoints: no other keys
        assert set(entry) == {"name", "type", "qos"}
        assert {"history", "reliability"} <= set(entry["qos"])


def test_capture_nodl_groups_actions_and_raw_nodl_does_not(cli):
    grouped = cli("capture", "--format", "nodl", "--script", NODES / "action_node.py")
    assert grouped.returncode == 0, grouped
    [doc] = [d for d in yaml.safe_load_all(grouped.stdout) if d]
    assert doc["action_servers"] == [{"name": "/fibonacci", "type": "test_msgs/action/Fibonacci"}]
    assert doc["action_clients"] == [{"name": "/count", "type": "test_msgs/action/Fibonacci"}]
    assert "service_servers" not in doc and "publishers" not in doc

    raw = cli("capture", "--format", "nodl", "--raw", "--script", NODES / "action_node.py")
    assert raw.returncode == 0, raw
    [doc] = [d for d in yaml.safe_load_all(raw.stdout) if d]
    assert "action_servers" not in doc
    servers = {s["name"]: s["type"] for s in doc["service_servers"]}
    assert servers["/fibonacci/_action/send_goal"] == "test_msgs/action/Fibonacci_SendGoal"
    assert "/fibonacci_server/get_parameters" in servers
    assert "/rosout" in {p["name"] for p in doc["publishers"]}


def test_default_vs_include_ros_infra_vs_raw(cli):
    target = ("--script", NODES / "action_node.py")
    default = cli("capture", "--format", "json", *target)
    infra = cli("capture", "--format", "json", "--include-ros-infra", *target)
    raw = cli("capture", "--format", "json", "--raw", *target)
    for r in (default, infra, raw):
        assert r.returncode == 0, r

    node = json.loads(default.stdout)["/fibonacci_server"]
    assert [a["name"] for a in node["action_servers"]] == ["/fibonacci"]
    assert node["publishers"] == [] and node["service_servers"] == []

    node = json.loads(infra.stdout)["/fibonacci_server"]
    assert [a["name"] for a in node["action_servers"]] == ["/fibonacci"]  # still grouped
    assert {p["name"] for p in node["publishers"]} == {"/rosout", "/parameter_events"}
    services = {s["name"] for s in node["service_servers"]}
    assert "/fibonacci_server/get_parameters" in services
    assert not any("/_action/" in s for s in services)

    doc = json.loads(raw.stdout)
    assert doc["format"] == "rmw_introspect_capture"
    assert [n["fqn"] for n in doc["nodes"]] == ["/fibonacci_server"]
    kinds = {(e["kind"], e["name"]) for e in doc["endpoints"]}
    assert ("service", "/fibonacci/_action/send_goal") in kinds
    assert ("publisher", "/fibonacci/_action/feedback") in kinds
    assert ("client", "/count/_action/get_result") in kinds
    assert ("publisher", "/rosout") in kinds
    assert ("service", "/fibonacci_server/get_parameters") in kinds
    assert all(e["qos"]["history"] in ("KEEP_LAST", "KEEP_ALL") for e in doc["endpoints"])  # raw rmw QoS

    infra_yaml = cli("capture", "--include-ros-infra", *target)
    assert "options:\n  include_infrastructure: true\n" in infra_yaml.stdout


def test_python_dash_m_dispatches_to_the_cli(cli):
    result = cli("--version", module=True)
    assert result.returncode == 0
    assert result.stdout.startswith("rmw-introspect ")


def test_capture_errors_are_messages_with_exit_status_2(cli):
    cases = {
        ("capture",): "no target: give --package P --executable E, --script FILE, --module M, --entry-point MOD:FUNC or -- COMMAND",
        ("capture", "--script", "a.py", "--module", "m"): "give one target, not --script and --module",
        ("capture", "--script", "a.py", "--param", "depth"): "--param 'depth' is not of the form NAME:=VALUE",
        ("capture", "--script", "a.py", "--env", "X"): "--env 'X' is not of the form K=V",
        ("capture", "--script", "missing.py"): "missing.py does not exist",
        ("capture", "--script", "a.py", "--bogus"): "unrecognized arguments: --bogus",
        ("capture", "--format", "xml", "--script", "a.py"): "invalid choice: 'xml'",
        ("capture", "--package", "no_such_pkg", "--executable", "x"): "Package 'no_such_pkg' was not found",
        ("capture", "--script", "a.py", "--"): "`--` must be followed by the command to run",
    }
    for args, message in cases.items():
        result = cli(*args)
        assert result.returncode == 2, (args, str(result))
        assert message in result.stderr, (args, str(result))
        assert "Traceback" not in result.stderr, (args, str(result))
        assert result.stdout == "", (args, str(result))


def test_a_crash_after_the_first_settle_is_a_crash_too(cli):
    # the node spins past the settle window, then raises: not a capture with a one-line note
    script = cli.write("late_crash.py", """\
        import rclpy
        from rclpy.node import Node
        from std_msgs.msg import String

        rclpy.init()
        node = Node("late_crasher")
        node.create_publisher(String, "doomed", 10)
        for _ in range(6):
            rclpy.spin_once(node, timeout_sec=0.1)
        raise RuntimeError("lost the serial port after start-up")
        """)
    result = cli("capture", "--script", script, "--settle", "0.1")
    assert result.returncode == 2, result
    assert "crashed: it exited with status 1 while it was captured" in result.stderr
    assert "RuntimeError: lost the serial port after start-up" in result.stderr
    assert result.stdout == ""


def test_capture_of_a_crashing_target_fails_with_its_stderr(cli):
    result = cli("capture", "--script", NODES / "crashing_node.py")
    assert result.returncode == 2, result
    assert "crashed: it exited with status 1 while it was captured" in result.stderr
    assert "sensor driver failed to open /dev/ttyUSB0" in result.stderr  # the target's own traceback tail
    assert result.stderr.startswith("rmw-introspect: The target script")
    assert result.stdout == ""


def test_capture_to_an_unwritable_output_is_an_error(cli):
    (cli.path / "afile").write_text("x")
    result = cli("capture", "--script", NODES / "talker.py", "-o", "afile/sub/out.yaml")
    assert result.returncode == 2, result
    assert "cannot write afile/sub/out.yaml" in result.stderr
    assert "Traceback" not in result.stderr


def test_a_command_with_relative_paths_records_where_it_ran(cli):
    """`capture -o DIR/x.yaml -- python rel/node.py`: the contract must check from anywhere."""
    (cli.path / "rel").mkdir()
    shutil.copy(NODES / "talker.py", cli.path / "rel" / "node.py")
    result = cli("capture", "-o", "contracts/x.interfaces.yaml", "--", sys.executable, "rel/node.py")
    assert result.returncode == 0, result
    target = contract_module.load(cli.path / "contracts" / "x.interfaces.yaml").target
    assert target["command"][1:] == ["rel/node.py"] and target["cwd"] == ".."
    (cli.path / "elsewhere").mkdir()
    check = cli("check", "../contracts/x.interfaces.yaml", cwd=cli.path / "elsewhere")
    assert check.returncode == 0, check


def test_sigterm_stops_the_target_and_ends_the_cli(cli):
    """A cancelled CI job sends SIGTERM: the CLI ends like on Ctrl-C, and the target with it."""
    import os
    import signal
    import subprocess
    import time

    from cli_helpers import wait_for_file

    pid_file = cli.path / "target.pid"
    script = cli.write("hang.py", f"""\
        import os, time
        open({str(pid_file)!r}, "w").write(str(os.getpid()))
        time.sleep(120)
        """)
    proc = subprocess.Popen([sys.executable, "-m", "pytest_rmw_introspect", "capture", "--script", str(script),
                             "--timeout", "100"],
                            cwd=cli.path, env=cli.env, stderr=subprocess.PIPE, text=True)
    target = wait_for_file(pid_file)
    proc.send_signal(signal.SIGTERM)
    _, stderr = proc.communicate(timeout=20)
    assert proc.returncode == 128 + signal.SIGTERM, stderr
    assert "terminated" in stderr and "Traceback" not in stderr
    deadline = time.monotonic() + 10
    while os.path.exists(f"/proc/{target}") and open(f"/proc/{target}/stat").read().split(") ")[1][0] != "Z":
        assert time.monotonic() < deadline, "the target outlived the CLI"
        time.sleep(0.05)


def test_a_target_that_starts_another_ros_process_is_captured_alone(cli):
    """Both processes run on the middleware and write their own capture: the target's is the
    capture, the child is reported (it used to overwrite the target's capture at random)."""
    cli.write("parent.py", f"""\
        import subprocess, sys
        import rclpy
        child = subprocess.Popen([sys.executable, {str(NODES / "talker.py")!r}])
        rclpy.init()
        node = rclpy.create_node("parent")
        node.create_publisher(__import__("std_msgs.msg", fromlist=["Int32"]).Int32, "count", 1)
        child.wait()          # the child settles (and ends) first, then the parent spins and settles
        rclpy.spin(node)
        """)
    result = cli("capture", "--format", "json", "--script", "parent.py")
    assert result.returncode == 0, result
    assert list(json.loads(result.stdout)) == ["/parent"]
    assert "note: the target started other ROS processes" in result.stderr and "/talker" in result.stderr


def test_an_ament_python_package_installed_with_pip_e_is_checked_through_its_console_script(cli, tmp_path):
    """`pip install -e .` puts an ament_python package's executables in the venv's bin/ as
    console scripts: `--package P --executable E` finds them through the distribution's
    metadata, and `--module` of a module without a __main__ block says what to use instead."""
    import subprocess
    import uuid

    name = f"rmwi_ep_demo_{uuid.uuid4().hex[:8]}"
    pkg = tmp_path / "src" / name
    (pkg / name).mkdir(parents=True)
    (pkg / name / "__init__.py").write_text("")
    (pkg / name / "camera.py").write_text(
        "import rclpy\nfrom std_msgs.msg import String\n\n\n"
        "def main():\n"
        "    rclpy.init()\n"
        "    node = rclpy.create_node('camera')\n"
        "    node.create_publisher(String, 'image_info', 10)\n"
        "    rclpy.spin(node)\n")
    (pkg / "setup.py").write_text(
        "from setuptools import setup\n"
        f"setup(name='{name}', version='0.0.1', packages=['{name}'],\n"
        f"      entry_points={{'console_scripts': ['camera = {name}.camera:main']}})\n")
    pip = [sys.executable, "-m", "pip", "--disable-pip-version-check", "--quiet"]
    # the build backend is the venv's own (from the lock): nothing is downloaded
    subprocess.run([*pip, "install", "--no-deps", "--no-build-isolation", "-e", str(pkg)], check=True,
                   capture_output=True, timeout=300)
    try:
        result = cli("capture", "--format", "json", "--package", name, "--executable", "camera")
        assert result.returncode == 0, result
        assert json.loads(result.stdout)["/camera"]["publishers"][0]["name"] == "/image_info"
        via_entry_point = cli("capture", "--format", "json", "--entry-point", f"{name}.camera:main")
        assert via_entry_point.stdout == result.stdout, via_entry_point
        as_module = cli("capture", "--module", f"{name}.camera")
        assert as_module.returncode == 2, as_module
        assert "created no ROS node" in as_module.stderr
        assert f"`entry_point: {name}.camera:main`" in as_module.stderr
    finally:
        subprocess.run([*pip, "uninstall", "--yes", name], capture_output=True, timeout=300)
