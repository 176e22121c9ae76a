"""System contracts end to end: `rmw-introspect capture --launch` captures every process of a launch
file (the example package's robot.launch.xml, and launch files written here that start the
example package's nodes), `check` compares and runs the system rules, `--update` writes, and
`compat`, `diff` and `graph` read system contracts."""

from __future__ import annotations

import importlib.util
import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from cli_helpers import NODES, wait_for_file

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "rmw_introspect_examples"

BROKEN = """\
<launch>
  <arg name="mistakes" default="true"/>
  <group>
    <push-ros-namespace namespace="robot1"/>
    <node pkg="rmw_introspect_examples" exec="map_server"/>
    <node pkg="rmw_introspect_examples" exec="listener" name="map_listener">
      <remap from="chatter" to="map" if="$(var mistakes)"/>
    </node>
    <node pkg="rmw_introspect_examples" exec="talker" name="reporter"/>
    <node pkg="rmw_introspect_examples" exec="talker" name="reporter" if="$(var mistakes)"/>
  </group>
</launch>
"""


def test_capture_of_the_example_robot(cli):
    result = cli("capture", "--launch-package", "rmw_introspect_examples", "--launch-file", "robot.launch.xml",
                 "--format", "json", timeout=120)
    assert result.returncode == 0, result
    data = json.loads(result.stdout)
    processes = {p["executable"]: p for p in data["processes"]}
    assert list(processes) == ["talker", "listener", "laser_driver", "scan_consumer", "map_server",
                               "motor_enable_server", "motor_enable_client"]
    assert processes["talker"]["nodes"] == ["/robot1/status_reporter"]
    assert processes["map_server"]["name"] is None and processes["map_server"]["nodes"] == ["/robot1/map_server"]
    # the command line as the launch file gives it: name, namespace, parameters file, remappings
    lidar = processes["laser_driver"]["command"]
    assert lidar[0].endswith("lib/rmw_introspect_examples/laser_driver")
    assert lidar[1:5] == ["--ros-args", "-r", "__node:=lidar", "-r"] and lidar[5] == "__ns:=/robot1"
    assert lidar[6] == "--params-file" and lidar[7].endswith("share/rmw_introspect_examples/config/robot_params.yaml")
    assert lidar[8:] == ["-r", "scan:=lidar/scan"]
    assert processes["motor_enable_client"]["command"][-2:] == ["-p", "enable:=true"]
    assert processes["laser_driver"]["launched_at"].endswith("robot.launch.xml:23")
    nodes = data["nodes"]
    assert nodes["/robot1/lidar"]["publishers"][0]["name"] == "/robot1/lidar/scan"
    assert nodes["/robot1/obstacle_detector"]["subscriptions"][0]["name"] == "/robot1/lidar/scan"
    assert nodes["/robot1/status_monitor"]["subscriptions"][0]["name"] == "/robot1/status"
    assert nodes["/robot1/motor_enabler"]["service_clients"][0]["name"] == "/robot1/enable_motors"
    # launch arguments
    without = cli("capture", "--launch-package", "rmw_introspect_examples", "--launch-file", "robot.launch.xml",
                  "--launch-arg", "use_lidar:=false", "--launch-arg", "robot:=r2", "--format", "json", timeout=120)
    assert without.returncode == 0, without
    assert sorted(json.loads(without.stdout)["nodes"]) == [
        "/r2/map_server", "/r2/motor_enabler", "/r2/motors", "/r2/status_monitor", "/r2/status_reporter"]


def test_the_example_system_contract_matches(cli):
    result = cli("check", "contracts/robot.system.yaml", cwd=EXAMPLES, timeout=120)
    assert result.returncode == 0, result
    assert result.stdout.startswith("contracts/robot.system.yaml: matches (7 nodes in 7 processes)")
    named = cli("check", "-v", "contracts/robot.system.yaml", cwd=EXAMPLES, timeout=120)
    assert named.stdout.startswith("contracts/robot.system.yaml: matches (7 nodes in 7 processes: /robot1/lidar, "), named


def test_capture_check_update_of_a_system(cli):
    cli.write("launch/broken.launch.xml", BROKEN)
    created = cli("capture", "--launch", "launch/broken.launch.xml", "--timeout", "30", "-o", "robot.system.yaml",
                  timeout=120)
    assert created.returncode == 0, created
    text = cli.read("robot.system.yaml")
    assert "launch:\n  path: launch/broken.launch.xml\ntarget:\n  timeout: 30.0\n" in text
    # the capture is the golden, so there is no drift, but the system does not fit together
    checked = cli("check", "robot.system.yaml", timeout=120)
    assert checked.returncode == 1, checked
    out = checked.stdout
    assert "System check of robot.system.yaml: 2 problems in 2 processes (2 breaking, 0 risky, 0 safe)" in out
    assert "[TYPE_MISMATCH] 1 finding in 1 process\n" in out and "[DUPLICATE_NODE_NAME] 1 finding in 1 process\n" in out
    assert "publisher of /robot1/map_server (rmw_introspect_examples/map_server) -> subscription " \
           "of /robot1/map_listener (rmw_introspect_examples/listener)" in out
    assert "node of /robot1/reporter (rmw_introspect_examples/talker) and node of " \
           "/robot1/reporter (rmw_introspect_examples/talker #2)" in out
    assert "To accept" not in out  # nothing to accept: the contract matches
    as_json = cli("check", "robot.system.yaml", "--format", "json", timeout=120)
    assert sorted(item["rule"] for item in json.loads(as_json.stdout)) == ["DUPLICATE_NODE_NAME", "TYPE_MISMATCH"]
    # a header comment survives an update; with the mistakes fixed (a launch argument) the nodes drift
    cli.write("robot.system.yaml", "# kept\n" + text.replace("launch:\n  path: launch/broken.launch.xml\n",
                                                              "launch:\n  path: launch/broken.launch.xml\n"
                                                              "  arguments: {mistakes: 'false'}\n"))
    drifted = cli("check", "robot.system.yaml", timeout=120)
    assert drifted.returncode == 1, drifted
    # one subscription of the same type removed and one added in the node: read as a rename
    assert "[SUB_RENAMED] subscription /robot1/map looks renamed to /robot1/chatter" in drifted.stdout
    assert "rmw-introspect check --update robot.system.yaml" in drifted.stdout
    updated = cli("check", "--update", "robot.system.yaml", timeout=120)
    assert updated.returncode == 0, updated
    assert "updated robot.system.yaml" in updated.stderr
    new_text = cli.read("robot.system.yaml")
    assert new_text.startswith("# kept\n") and "arguments: {mistakes: 'false'}" in new_text
    assert new_text.count("executable: talker") == 1
    assert cli("check", "robot.system.yaml", "--jobs", "1", timeout=120).returncode == 0
    # launch arguments on the command line go on top of the contract's
    again = cli("check", "robot.system.yaml", "--launch-arg", "mistakes:=true", "--format", "json", timeout=120)
    assert again.returncode == 1, again
    assert {"SUB_RENAMED", "TYPE_MISMATCH", "DUPLICATE_NODE_NAME"} <= {i["rule"] for i in json.loads(again.stdout)}
    # diff and compat of system contracts
    cli.write("old.system.yaml", text)
    diff = cli("diff", "old.system.yaml", "robot.system.yaml")
    assert diff.returncode == 1 and "[SUB_RENAMED]" in diff.stdout, diff
    compat = cli("compat", "old.system.yaml")
    assert compat.returncode == 1 and "[DUPLICATE_NODE_NAME]" in compat.stdout, compat
    assert cli("compat", "robot.system.yaml").returncode == 0


def test_check_creates_a_missing_system_contract(cli):
    cli.write("launch/one.launch.yaml", """\
        launch:
        - node: {pkg: rmw_introspect_examples, exec: talker, name: speaker, namespace: ns}
        """)
    result = cli("check", "--update", "--launch", "launch/one.launch.yaml", "one.system.yaml", timeout=120)
    assert result.returncode == 0, result
    assert "created one.system.yaml" in result.stderr
    text = cli.read("one.system.yaml")
    assert "system_version: 1\nlaunch:\n  path: launch/one.launch.yaml\nprocesses:\n" in text
    assert "  /ns/speaker:\n    publishers:\n      - name: /ns/chatter\n" in text
    missing = cli("check", "other.system.yaml")
    assert missing.returncode == 2 and "does not exist" in missing.stderr


def test_a_launched_process_that_creates_no_node(cli):
    cli.write("launch/silent.launch.xml", f"""\
        <launch>
          <node exec="{sys.executable}" args="{NODES / 'no_node.py'}" name="silent"/>
          <node pkg="rmw_introspect_examples" exec="talker"/>
        </launch>
        """)
    cli("capture", "--launch", "launch/silent.launch.xml", "-o", "silent.system.yaml", timeout=120)
    result = cli("check", "silent.system.yaml", timeout=120)
    assert result.returncode == 1, result
    assert "[LAUNCHED_NODE_NOT_CREATED] 1 finding in 1 process" in result.stdout and "node of /silent" in result.stdout
    assert "the launch file starts node /silent at launch/silent.launch.xml:2, but the process created no node at all" \
        in result.stdout
    assert f"  - {Path(sys.executable).name} (launch/silent.launch.xml:2) created no node\n" in result.stdout


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_an_interrupt_stops_the_running_processes_of_a_system_capture_first(cli, sig):
    """Ctrl-C or SIGTERM (a cancelled CI job) of `capture --launch` stops the processes it runs
    and ends the command at once; the processes of a system are captured in worker threads, which
    the interrupt does not reach, and each ran until its timeout (100 s here) before."""
    pids = [cli.path / f"hang{n}.pid" for n in range(3)]
    script = cli.write("hang.py", """\
        import os, sys, time
        open(sys.argv[1], "w").write(str(os.getpid()))
        time.sleep(300)
        """)
    nodes = "".join(f'  <node exec="{sys.executable}" args="{script} {pid}"/>\n' for pid in pids)
    cli.write("launch/hang.launch.xml", f"<launch>\n{nodes}</launch>\n")
    proc = subprocess.Popen([sys.executable, "-m", "pytest_rmw_introspect", "capture", "--launch",
                             "launch/hang.launch.xml", "--timeout", "100", "--jobs", "2"],
                            cwd=cli.path, env=cli.env, stderr=subprocess.PIPE, text=True)
    started = [wait_for_file(pid) for pid in pids[:2]]
    proc.send_signal(sig)
    try:
        _, stderr = proc.communicate(timeout=20)
    except subprocess.TimeoutExpired:
        proc.kill()
        pytest.fail("the command still ran 20 s after the interrupt")
    assert proc.returncode == 128 + sig if sig == signal.SIGTERM else proc.returncode == 130, stderr
    assert ("terminated" if sig == signal.SIGTERM else "interrupted") in stderr and "Traceback" not in stderr, stderr
    assert not pids[2].exists(), "a process of the system started after the interrupt"
    deadline = time.monotonic() + 10
    for pid in started:
        while os.path.exists(f"/proc/{pid}") and open(f"/proc/{pid}/stat").read().split(") ")[1][0] != "Z":
            assert time.monotonic() < deadline, "a process of the system outlived the command"
            time.sleep(0.05)


def test_unsupported_constructs_fail_unless_allowed(cli):
    cli.write("launch/timer.launch.xml", """\
        <launch>
          <timer period="2.0"><node pkg="rmw_introspect_examples" exec="listener"/></timer>
          <node pkg="rmw_introspect_examples" exec="talker"/>
        </launch>
        """)
    refused = cli("capture", "--launch", "launch/timer.launch.xml")
    assert refused.returncode == 2, refused
    assert "launch/timer.launch.xml:2: <timer>: delayed actions (<timer>) are not supported" in refused.stderr
    assert "--allow-unsupported" in refused.stderr
    allowed = cli("capture", "--launch", "launch/timer.launch.xml", "--allow-unsupported", timeout=120)
    assert allowed.returncode == 0, allowed
    assert "note: not captured (launch/timer.launch.xml:2): <timer>" in allowed.stderr
    assert "allow_unsupported: true" in allowed.stdout and "/talker:" in allowed.stdout


def test_launch_usage_errors(cli_nodes_only):
    cli = cli_nodes_only
    both = cli("capture", "--launch", "a.launch.xml", "--launch-package", "p", "--launch-file", "f")
    assert both.returncode == 2 and "not both" in both.stderr
    target = cli("capture", "--launch", "a.launch.xml", "--package", "p", "--executable", "e")
    assert target.returncode == 2 and "--executable, --package cannot be given" in target.stderr
    arg = cli("capture", "--package", "p", "--executable", "e", "--launch-arg", "a:=b")
    assert arg.returncode == 2 and "--launch-arg and --allow-unsupported need a launch file" in arg.stderr
    bad = cli("capture", "--launch", "a.launch.xml", "--launch-arg", "nonsense")
    assert bad.returncode == 2 and "is not of the form NAME:=VALUE" in bad.stderr


@pytest.mark.skipif(importlib.util.find_spec("launch_ros") is not None,
                    reason="launch_ros is importable here: Python launch files are read through it")
def test_python_launch_files_say_what_they_need(cli):
    cli.write("robot.launch.py", "def generate_launch_description():\n    pass\n")
    result = cli("capture", "--launch", "robot.launch.py")
    assert result.returncode == 2
    assert "robot.launch.py is a Python launch file" in result.stderr
    assert "The ROS 2 PyPI wheels do not include them" in result.stderr


def test_graph_of_a_system_contract(cli_nodes_only):
    cli = cli_nodes_only
    contract = EXAMPLES / "system_demo" / "broken_robot.system-demo.yaml"
    mermaid = cli("graph", str(contract))
    assert mermaid.returncode == 0, mermaid
    assert mermaid.stdout.startswith("flowchart LR\n") and '-- "TYPE_MISMATCH" -->' in mermaid.stdout
    html = cli("graph", str(contract), "--format", "html", "-o", "robot.html")
    assert html.returncode == 0, html
    page = cli.read("robot.html")
    assert page.startswith("<!DOCTYPE html>") and 'data-rules="TYPE_MISMATCH"' in page
    dot = cli("graph", str(contract), "--format", "dot", "--title", "broken robot")
    assert dot.returncode == 0 and dot.stdout.startswith('digraph "broken robot" {'), dot
    if shutil.which("dot") is None:
        pytest.skip("Graphviz (dot) is not installed: apt-get install graphviz")
    svg = subprocess.run(["dot", "-Tsvg"], input=dot.stdout, capture_output=True, text=True, timeout=60, check=False)
    assert svg.returncode == 0, svg.stderr
    assert "<svg" in svg.stdout and "TYPE_MISMATCH" in svg.stdout and "DUPLICATE_NODE_NAME" in svg.stdout
    missing = cli("graph", "nowhere.system.yaml")
    assert missing.returncode == 2 and "nowhere.system.yaml" in missing.stderr


def test_system_contracts_in_the_ci_formats(cli_nodes_only):
    cli = cli_nodes_only
    text = (EXAMPLES / "system_demo" / "broken_robot.system-demo.yaml").read_text()
    lines = text.splitlines()
    cli.write("robot.system.yaml", text)
    compat = {fmt: cli("compat", "robot.system.yaml", "--format", fmt) for fmt in ("sarif", "markdown", "github")}
    assert all(result.returncode == 1 for result in compat.values()), compat
    # markdown and github: `compat` of system contracts printed its text report for these two
    assert compat["markdown"].stdout.startswith("## Compatibility check of 1 contract(s): FAIL\n"), compat
    assert "| BREAKING | `/robot1/map` | `TYPE_MISMATCH` |" in compat["markdown"].stdout, compat
    annotations = [line for line in compat["github"].stdout.splitlines() if "TYPE_MISMATCH" in line]
    assert annotations and all(a.startswith("::error file=robot.system.yaml,line=") for a in annotations), compat
    line = int(annotations[0].split("line=")[1].split(",")[0])  # at the requesting end's entry
    assert lines[line - 1].strip() == "- name: /robot1/map", (line, annotations)
    results = json.loads(compat["sarif"].stdout)["runs"][0]["results"]
    assert {"TYPE_MISMATCH", "DUPLICATE_NODE_NAME"} <= {r["ruleId"] for r in results}
    for result in results:  # each on the system contract, at the entry of its requesting end
        location = result["locations"][0]["physicalLocation"]
        assert location["artifactLocation"] == {"uri": "robot.system.yaml", "uriBaseId": "%SRCROOT%"}, result
        line = lines[location["region"]["startLine"] - 1]
        assert result["ruleId"] == "DUPLICATE_NODE_NAME" or result["locations"][0]["logicalLocations"][0][
            "fullyQualifiedName"].rsplit("/", 1)[-1] in line, (result, line)
    cli.write("new.system.yaml", text.replace("type: std_msgs/msg/String", "type: std_msgs/msg/Int32", 1))
    diff = cli("diff", "robot.system.yaml", "new.system.yaml", "--format", "sarif")
    assert diff.returncode == 1, diff
    (changed,) = json.loads(diff.stdout)["runs"][0]["results"]
    assert changed["ruleId"] == "TYPE_CHANGED"
    assert changed["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] == "new.system.yaml"


def test_a_system_contract_accepts_findings_on_purpose(cli_nodes_only):
    cli = cli_nodes_only
    text = (EXAMPLES / "system_demo" / "broken_robot.system-demo.yaml").read_text()
    accept = ("accept:\n"
              "  - {rule: DUPLICATE_NODE_NAME, name: /robot1/reporter, reason: 'the demo starts two on purpose'}\n"
              "  - {rule: TYPE_MISMATCH, name: /robot1/map, node: /robot1/map_listener, reason: 'the demo mistake'}\n")
    cli.write("robot.system.yaml", text.replace("system_version: 1\n", "system_version: 1\n" + accept, 1))
    result = cli("compat", "robot.system.yaml")
    # the two accepted BREAKING problems no longer fail; the mis-wired service, not accepted, does
    assert result.returncode == 1, result
    assert "ACCEPTED (2)" in result.stdout and "the demo starts two on purpose" in result.stdout
    assert "[SERVICE_NAME_MISMATCH]" in result.stdout.split("ACCEPTED")[0]  # not accepted: still reported
    accept += "  - {rule: SERVICE_NAME_MISMATCH, name: /robot1/enable_motor, reason: 'the third demo mistake'}\n"
    cli.write("robot.system.yaml", text.replace("system_version: 1\n", "system_version: 1\n" + accept, 1))
    assert cli("compat", "robot.system.yaml").returncode == 0
    items = json.loads(cli("compat", "robot.system.yaml", "--format", "json").stdout)
    assert sorted(i["rule"] for i in items if "accepted" in i) == [
        "DUPLICATE_NODE_NAME", "SERVICE_NAME_MISMATCH", "TYPE_MISMATCH"]
