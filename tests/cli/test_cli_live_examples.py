"""Every node of the example package, started from its own contract's `target:` on Fast DDS (one
ROS_DOMAIN_ID of their own, localhost discovery) and checked live against that contract in one
`check --live` run (issue 52 item 5, over every node of examples/; the robot's launch file is
tests/cli/test_cli_live.py's), and the system demo's broken robot captured and checked live. The contracts are the recording middleware's captures, so what the
live check finds beyond its notes is what the capture and the running node really differ in, each
said here: the one-shot clients have exited (their node is gone), and the lifecycle node that a
capture drives to `active` is `unconfigured` when nobody drives it (and lacks the publisher it
creates on activation). About 17 s on a shared 2-core machine."""

from __future__ import annotations

import json
import time
from pathlib import Path

from cli_helpers import Cli

from pytest_rmw_introspect.live import bringup
from pytest_rmw_introspect.model import contract as contract_model
from pytest_rmw_introspect.run.target import TargetSpec

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "rmw_introspect_examples"
CONTRACTS = EXAMPLES / "contracts"
#: the system demo's robot, whose launch file has three mistakes (system_demo/README.md)
BROKEN_ROBOT = EXAMPLES / "system_demo" / "broken_robot.launch.xml"
#: the programs that do their work once and exit (their node is gone from a live graph)
ONE_SHOT = {"fibonacci_client", "motor_deadline_client", "motor_enable_client", "self_test"}
#: what the live check finds, by contract: the one-shot nodes gone, the lifecycle node not driven
EXPECTED = {
    **{f"{name}.interfaces.yaml": {"NODE_REMOVED", "SERVICE_CLIENT_REMOVED", "ACTION_CLIENT_REMOVED", "PUB_REMOVED"}
       for name in ONE_SHOT},
    "lifecycle_talker.interfaces.yaml": {"LIFECYCLE_STATE_CHANGED", "PUB_REMOVED"},
}


def test_every_example_node_runs_on_fast_dds_as_its_capture_says(cli: Cli):
    files = sorted(CONTRACTS.glob("*.interfaces.yaml"))
    contracts = [contract_model.load(f) for f in files]
    targets = [TargetSpec.from_mapping(c.target or {}, base_dir=f.parent, source=str(f))
               for f, c in zip(files, contracts, strict=True)]
    started = time.monotonic()
    system = bringup.start(targets)
    try:
        # the one-shot programs end by themselves (motor_deadline_client with an error when the server
        # answers late under load): read the graph once they have
        one_shot = [p for p in system.processes if Path(str(p.args[-1])).name in ONE_SHOT
                    or any(Path(str(a)).name in ONE_SHOT for a in p.args)]
        assert len(one_shot) == len(ONE_SHOT), [p.args for p in system.processes]
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and any(p.poll() is None for p in one_shot):
            time.sleep(0.2)
        assert all(p.poll() is not None for p in one_shot), system.exited()
        running = [p.args for p in system.processes if p not in one_shot and p.poll() is not None]
        assert not running, system.exited()  # every other node keeps running
        print(f"the one-shot programs ended {time.monotonic() - started:.1f} s after the start")
        system.wait_until_up(nodes={name for f, contract in zip(files, contracts, strict=True)
                                    if f.name.removesuffix(".interfaces.yaml") not in ONE_SHOT
                                    for name in contract.nodes})  # every other node is up
        # the default settle: discovery of a dozen processes comes in bursts (a Kilted run missed the C talker
        # at 1.5 s), and the reader waits for every node the contracts name (the one-shot ones, gone, 10 s)
        result = cli("check", "--live", *files, "--format", "json",
                     env={k: system.env[k] for k in ("ROS_DOMAIN_ID", "ROS_AUTOMATIC_DISCOVERY_RANGE")}, timeout=120)
    finally:
        system.stop()
    assert result.returncode == 1, result
    found: dict[str, set[str]] = {}
    for item in json.loads(result.stdout):
        found.setdefault(Path(item["contract"]).name, set()).add(item["rule"])
    assert set(found) == set(EXPECTED), found
    for name, rules in found.items():
        assert rules <= EXPECTED[name], (name, rules)


def test_the_broken_robot_is_found_broken_alike_live_and_from_its_capture(cli: Cli):
    """The system demo's robot: the same three mistakes from its capture and from the running
    robot (two nodes of one name, a listener on a map, a client one letter off its server), and
    no drift between them. The live check found no duplicate name until the reader counted the
    nodes the graph lists under one name."""
    captured = cli("capture", "--launch", BROKEN_ROBOT, "-o", "broken.system.yaml", timeout=120)
    assert captured.returncode == 0, captured
    offline = cli("check", "broken.system.yaml", "--format", "json", timeout=120)
    assert offline.returncode == 1, offline
    mistakes = {"DUPLICATE_NODE_NAME", "TYPE_MISMATCH", "SERVICE_NAME_MISMATCH"}
    assert {item["rule"] for item in json.loads(offline.stdout)} == mistakes, offline.stdout
    with bringup.running({"path": str(BROKEN_ROBOT)}, base_dir=BROKEN_ROBOT.parent) as system:
        system.wait_until_up()
        live = cli("check", "--live", "--settle", "1", "broken.system.yaml", "--format", "json",
                   env={k: system.env[k] for k in ("ROS_DOMAIN_ID", "ROS_AUTOMATIC_DISCOVERY_RANGE")}, timeout=120)
        assert not system.exited()  # the client still waits for its misnamed service
    assert live.returncode == 1, live
    found = json.loads(live.stdout)
    assert {item["rule"] for item in found} == mistakes, live.stdout  # the same mistakes, nothing else
    duplicate = next(item for item in found if item["rule"] == "DUPLICATE_NODE_NAME")
    assert duplicate["name"] == "/robot1/reporter" and "2 nodes are named /robot1/reporter" in duplicate["message"]
