"""Hardware processes, end to end with real rclpy nodes on the recording middleware: a launch
file whose IMU driver needs `/dev/ttyFAKE`, a device this machine does not have. Capturing the
launch file fails and proposes the `stand_ins:` block; the driver is captured once "on the
robot" (where its device is: here a file standing for it) with `rmw-introspect capture`; the
system contract stands in for the driver with that node contract, and the check passes, says
which process it did not run and treats the driver's interfaces as present (the monitor's
subscription to /robot1/imu is not dangling). A stand-in that is missing or invalid is one
clear error naming both files."""

from __future__ import annotations

import sys

import pytest
from cli_helpers import NODES
from sample_systems import imu_robot

HEADER = "system_version: 1\nlaunch: {path: launch/robot.launch.xml}\n"


@pytest.fixture
def robot(cli):
    cli.write("launch/robot.launch.xml", imu_robot())
    return cli


def proposed_block(stderr: str) -> str:
    """The `stand_ins:` block a failed capture proposes, as the user pastes it."""
    lines = stderr.splitlines()
    start = next(i for i, line in enumerate(lines) if line.strip() == "stand_ins:")
    block = [lines[start]]
    for line in lines[start + 1:]:
        if not line.startswith("    ") or not line.strip():
            break
        block.append(line)
    indent = len(block[0]) - len(block[0].lstrip())
    return "\n".join(line[indent:] for line in block) + "\n"


def capture_on_the_robot(cli) -> None:
    """The driver alone, where its device is (a file stands for it), as the robot's team runs it."""
    device = cli.write("robot_dev/ttyFAKE", "")
    captured = cli("capture", "-o", "contracts/robot1_imu_driver.interfaces.yaml", "--", sys.executable,
                   NODES / "serial_driver.py", "--ros-args", "-r", "__node:=imu_driver", "-r", "__ns:=/robot1",
                   "-p", f"port:={device}", timeout=120)
    assert captured.returncode == 0, captured


def test_a_driver_without_its_device_fails_then_a_stand_in_passes(robot):
    # the capture machine is not the robot: the driver exits for lack of its device
    failed = robot("capture", "--launch", "launch/robot.launch.xml", "-o", "robot.system.yaml", timeout=180)
    assert failed.returncode == 2, failed
    assert "could not open /dev/ttyFAKE" in failed.stderr
    assert "Traceback" not in failed.stderr
    block = proposed_block(failed.stderr)
    assert block == (f"stand_ins:\n- executable: {sys.executable}\n  name: /robot1/imu_driver\n"
                     "  contract: contracts/robot1_imu_driver.interfaces.yaml\n  reason: needs /dev/ttyFAKE\n")
    assert not (robot.path / "robot.system.yaml").exists()

    # the proposal adopted: the driver captured once on the robot, the contract filled in here
    capture_on_the_robot(robot)
    robot.write("robot.system.yaml", HEADER + block)
    written = robot("check", "robot.system.yaml", "--update", timeout=180)
    assert written.returncode == 0, written
    text = robot.read("robot.system.yaml")
    assert text.startswith(HEADER + block)  # the header and the stand-in kept as written
    assert "/robot1/imu_driver:\n" in text and "name: /robot1/imu\n" in text

    checked = robot("check", "robot.system.yaml", timeout=180)
    assert checked.returncode == 0, checked
    assert checked.stdout.startswith("robot.system.yaml: matches (2 nodes in 2 processes)")
    assert (f"stood in for, not run here: {sys.executable.rsplit('/', 1)[-1]} by "
            "contracts/robot1_imu_driver.interfaces.yaml") in checked.stdout
    # the monitor's subscription is fed by the stood-in driver: nothing dangles
    assert "DANGLING" not in checked.stdout + checked.stderr


@pytest.mark.parametrize("case", ["missing", "invalid", "no process"])
def test_a_stand_in_that_cannot_be_used_is_one_clear_error(robot, case):
    contract = {"missing": "contracts/nowhere.interfaces.yaml", "invalid": "contracts/bad.interfaces.yaml",
                "no process": "contracts/good.interfaces.yaml"}[case]
    robot.write("contracts/bad.interfaces.yaml", "contract_version: 1\nnodes:\n  /robot1/imu_driver:\n"
                                                 "    publishers: [{name: imu}]\n")
    robot.write("contracts/good.interfaces.yaml", "contract_version: 1\nnodes:\n  /robot1/imu_driver:\n"
                                                  "    publishers: [{name: /robot1/imu, type: sensor_msgs/msg/Imu}]\n")
    name = "/robot1/gps_driver" if case == "no process" else "/robot1/imu_driver"
    robot.write("robot.system.yaml", HEADER + f"stand_ins:\n  - executable: python\n    name: {name}\n"
                                              f"    contract: {contract}\n")
    checked = robot("check", "robot.system.yaml", timeout=180)
    assert checked.returncode == 2, checked
    assert "Traceback" not in checked.stderr
    lines = [line for line in checked.stderr.splitlines() if line.startswith("rmw-introspect:")]
    assert len(lines) == 1, checked.stderr
    message = checked.stderr
    if case == "missing":
        assert lines[0].startswith("rmw-introspect: invalid contract robot.system.yaml:4: at stand_ins[0].contract: "
                                   "the stand-in for python (/robot1/imu_driver), contracts/nowhere.interfaces.yaml, "
                                   "does not exist: capture it where the hardware is"), message
    elif case == "invalid":
        assert lines[0].startswith("rmw-introspect: invalid contract robot.system.yaml:4: at stand_ins[0].contract: "
                                   "the stand-in for python (/robot1/imu_driver), contracts/bad.interfaces.yaml, is "
                                   "not a valid node contract or NoDL document: contracts/bad.interfaces.yaml:4: at "
                                   "nodes./robot1/imu_driver.publishers[0]: 'type' is required"), message
    else:
        assert "the stand-in for python (/robot1/gps_driver) (contracts/good.interfaces.yaml) names no process" in message
        assert "it starts: python (/robot1/imu_driver); python #2 (/robot1/imu_monitor)" in message
