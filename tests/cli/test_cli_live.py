"""`check --live` and `capture --live` (issue 52) on real processes on Fast DDS, each system in a
ROS_DOMAIN_ID of its own (``live.bringup.reserve_domain``: a lock file per id, so xdist workers and
other sessions never share one) with localhost discovery; never a mock graph.

The example robot (examples/rmw_introspect_examples/launch/robot.launch.xml) is brought up once for
the module and captured once on the recording middleware (the existing `capture --launch` path):
the live check of that capture against the running robot is the capture's independent truth
(issue 52 item 5). Its one difference is said as such: motor_enable_client calls its service once
and exits, so its node is gone from the live graph (`NODE_REMOVED`), as on a robot.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterator
from pathlib import Path

import pytest
import yaml
from cli_helpers import NODES, Cli

from pytest_rmw_introspect.live import bringup
from pytest_rmw_introspect.run.target import TargetSpec

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = REPO / "examples" / "rmw_introspect_examples"
ROBOT = {"path": str(EXAMPLES / "launch" / "robot.launch.xml")}
#: the node of the robot whose process ends by itself (it calls /robot1/enable_motors once)
ONE_SHOT = "/robot1/motor_enabler"
QUICK = ("--settle", "1", "--timeout", "20")
#: for a capture that must see every node: with no contract to name the nodes to wait for, the reader
#: waits for a quiet graph, and a new reader on a loaded machine learns of the nodes with gaps of more
#: than a second (a Kilted run missed two of the robot's nodes with --settle 1)
WHOLE = ("--settle", "3", "--timeout", "30")


@pytest.fixture(scope="module")
def robot() -> Iterator[bringup.RunningSystem]:
    """The example robot running on Fast DDS, one bring-up for the module."""
    with bringup.running(ROBOT, base_dir=EXAMPLES) as system:
        system.wait_until_up()
        yield system


@pytest.fixture
def live_cli(cli: Cli, robot: bringup.RunningSystem) -> Cli:
    """``cli`` in the robot's domain (with the recording middleware's library still named, as in
    every CLI test: the live reader must not use it)."""
    cli.env.update(ROS_DOMAIN_ID=str(robot.domain_id), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST")
    return cli


@pytest.fixture(scope="module")
def robot_capture(tmp_path_factory: pytest.TempPathFactory, middleware_library: Path) -> Path:
    """The robot captured on the recording middleware, once for the module."""
    out = tmp_path_factory.mktemp("capture") / "robot.system.yaml"
    env = {k: v for k, v in os.environ.items() if k not in ("CI", "PYTEST_ADDOPTS")}
    env["RMW_INTROSPECT_LIBRARY"] = str(middleware_library)
    result = Cli(out.parent, env)("capture", "--launch", ROBOT["path"], "-o", str(out), timeout=120)
    assert result.returncode == 0, result
    return out


def test_the_live_check_agrees_with_the_capture_of_the_same_launch_file(live_cli, robot_capture, robot):
    """Item 5: what the recording middleware captured is what runs on Fast DDS; the differences
    are the documented unobservable fields (notes) and the one-shot node that has exited."""
    result = live_cli("check", "--live", *QUICK, robot_capture, "--format", "json", timeout=120)
    assert result.returncode == 1, result  # the one-shot node is gone
    items = json.loads(result.stdout)
    assert {item.get("node") for item in items} == {ONE_SHOT}, items
    assert {item["rule"] for item in items} == {"NODE_REMOVED", "SERVICE_CLIENT_REMOVED"}, items
    assert any("motor_enable_client" in gone and "exited with 0" in gone for gone in robot.exited())
    text = live_cli("check", "--live", *QUICK, robot_capture, timeout=120)
    assert "Notes on the live graph" in text.stdout, text
    assert "QoS history and depth, which the middleware does not report (UNKNOWN)" in text.stdout
    assert "the type hashes of services" in text.stdout
    assert "joined ROS_DOMAIN_ID" in text.stderr and "waiting for the graph to be stable" in text.stderr


def test_a_contract_of_the_running_robot_checks_against_it_and_leaves_nothing_behind(live_cli, robot, middleware_library):
    env = {"LD_PRELOAD": str(middleware_library)}  # the recording middleware activated: stripped, said
    written = live_cli("capture", "--live", *QUICK, "-o", "live.system.yaml", env=env, timeout=120)
    assert written.returncode == 2 and "give its launch file" in written.stderr, written
    written = live_cli("capture", "--live", *WHOLE, "--launch", ROBOT["path"], "-o", "live.system.yaml", env=env,
                       timeout=120)
    assert written.returncode == 0, written
    assert written.stderr.count("the live reader runs without it") == 1, written
    contract = yaml.safe_load(live_cli.read("live.system.yaml"))
    nodes = set(contract["nodes"])
    assert {"/robot1/lidar", "/robot1/map_server", "/robot1/status_reporter"} <= nodes
    assert not any("_rmw_introspect_live" in n for n in nodes), nodes  # its own node is hidden
    lidar = contract["nodes"]["/robot1/lidar"]
    assert {p["name"]: p["default_value"] for p in lidar["parameters"]}["rate"] == 20.0  # from the params file
    # a second reader sees no node of the first (destroyed with its context) and the same graph; a node
    # contract is compared with the nodes it names only
    nodes_only = live_cli("capture", "--live", *QUICK, "--format", "json", timeout=120)
    assert json.loads(nodes_only.stdout)["other_readers"] == [], nodes_only
    talker = str(EXAMPLES / "contracts" / "talker.interfaces.yaml")
    again = live_cli("check", "--live", *QUICK, "live.system.yaml", talker, "--format", "sarif", "--summary", "sum.md",
                     timeout=120)
    assert again.returncode == 1, again  # no /talker runs on the robot (it is /robot1/status_reporter)
    results = json.loads(again.stdout)["runs"][0]["results"]
    assert {r["ruleId"] for r in results} == {"NODE_REMOVED", "PUB_REMOVED"}, results
    assert all("talker.interfaces.yaml" in json.dumps(r["locations"]) for r in results), results
    assert "live.system.yaml" in live_cli.read("sum.md")


@pytest.fixture
def empty_domain() -> Iterator[int]:
    domain = bringup.reserve_domain()
    try:
        yield domain.id
    finally:
        domain.release()


def test_nothing_running_is_a_clear_error(cli, empty_domain):
    result = cli("check", "--live", "--settle", "0.2", "--timeout", "1.5", EXAMPLES / "contracts" / "talker.interfaces.yaml",
                 env={"ROS_DOMAIN_ID": str(empty_domain), "ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST"})
    assert result.returncode == 2, result
    assert f"nothing is running in ROS_DOMAIN_ID {empty_domain}" in result.stderr


@pytest.mark.parametrize(("middleware", "said"), [
    ("rmw_cyclonedds_cpp", "RMW_IMPLEMENTATION=rmw_cyclonedds_cpp names a middleware that is not installed here"),
    ("rmw_introspect_cpp", "is the recording middleware, which sees no other process"),
])
def test_a_middleware_the_reader_cannot_use_is_refused(cli, empty_domain, middleware, said):
    result = cli("check", "--live", EXAMPLES / "contracts" / "talker.interfaces.yaml",
                 env={"ROS_DOMAIN_ID": str(empty_domain), "RMW_IMPLEMENTATION": middleware})
    assert result.returncode == 2, result
    assert said in result.stderr


def test_contracts_are_read_before_the_graph_is_joined(cli, empty_domain):
    cli.write("broken.interfaces.yaml", "contract_version: 1\nnodes: [\n")
    result = cli("check", "--live", "broken.interfaces.yaml", env={"ROS_DOMAIN_ID": str(empty_domain)})
    assert result.returncode == 2, result
    assert "broken.interfaces.yaml" in result.stderr and "joined ROS_DOMAIN_ID" not in result.stderr
    missing = cli("check", "--live", env={"ROS_DOMAIN_ID": str(empty_domain)})
    assert missing.returncode == 2 and "CONTRACT" in missing.stderr, missing
    target = cli("check", "--live", "--script", "node.py", "broken.interfaces.yaml")
    assert target.returncode == 2 and "cannot be given with it" in target.stderr, target


def test_parameters_and_lifecycle_states_are_read_and_a_node_that_does_not_answer_is_a_note(cli):
    """The camera (a lifecycle node with a driver's mix of parameter descriptors) captured in
    `unconfigured` on the recording middleware matches it running on Fast DDS, parameters and state
    included; a node that never spins cannot answer for its parameters: a note, not drift."""
    camera = NODES / "managed_camera.py"
    captured = cli("capture", "--script", camera, "--lifecycle", "unconfigured", "-o", "camera.interfaces.yaml")
    assert captured.returncode == 0, captured
    assert "lifecycle: unconfigured" in cli.read("camera.interfaces.yaml")
    cli.write("sleeper.interfaces.yaml", """\
        contract_version: 1
        nodes:
          /sleeper:
            publishers:
              - {name: /snore, type: std_msgs/msg/String, qos: {history: KEEP_LAST, depth: 10, reliability: RELIABLE, durability: VOLATILE}}
            subscriptions: []
            service_servers: []
            service_clients: []
            action_servers: []
            action_clients: []
            parameters:
              - {name: volume, type: integer, default_value: 3}
        """)
    system = bringup.start([TargetSpec(script=camera), TargetSpec(script=NODES / "hanging_node.py")])
    try:
        system.wait_until_up(nodes={"/camera", "/sleeper"})  # both started (slowly, under load)
        # 8 s: under load the camera's own parameter services have taken more than 4 s to answer
        result = cli("check", "--live", "--settle", "1", "--parameter-timeout", "8", "camera.interfaces.yaml",
                     "sleeper.interfaces.yaml", "-v", env={k: system.env[k] for k in ("ROS_DOMAIN_ID",
                                                                                       "ROS_AUTOMATIC_DISCOVERY_RANGE")},
                     timeout=120)
    finally:
        system.stop()
    assert result.returncode == 0, result.stdout + result.stderr
    assert "camera.interfaces.yaml: matches (1 node running in ROS_DOMAIN_ID" in result.stdout, result
    assert "sleeper.interfaces.yaml: matches" in result.stdout, result
    # the camera's parameters and state were read and compared; only the sleeper's are noted
    assert ("note: sleeper.interfaces.yaml: parameters not read (the node's parameter services did not answer "
            "within 8 s), not compared: /sleeper\n") in result.stderr, result
    assert "lifecycle state not read" not in result.stderr, result
