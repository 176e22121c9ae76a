"""Hardware processes in pytest: a system contract's item whose launch file starts an IMU driver
that needs `/dev/ttyFAKE`, a device this machine lacks. Without a stand-in the item fails with
the `stand_ins:` block to add; with the driver's node contract standing in for it (captured "on
the robot", where a file stands for the device), --update-golden writes the contract, the item
passes, the monitor's subscription is fed by the stood-in driver (not dangling), and the terminal
summary says which process was not run, under xdist too."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest
from sample_systems import imu_robot

HEADER = "system_version: 1\nlaunch: {path: launch/robot.launch.xml}\n"
STAND_IN = ("stand_ins:\n- executable: {exe}\n  name: /robot1/imu_driver\n"
            "  contract: contracts/robot1_imu_driver.interfaces.yaml\n  reason: needs /dev/ttyFAKE\n")


@pytest.fixture
def robot(project):
    project.write("launch/robot.launch.xml", imu_robot())
    return project


def capture_on_the_robot(project) -> None:
    """The driver alone, where its device is (a file stands for it), as the robot's team runs it."""
    device = project.write("robot_dev/ttyFAKE", "")
    captured = subprocess.run(
        [sys.executable, "-m", "pytest_rmw_introspect", "capture", "-o", "contracts/robot1_imu_driver.interfaces.yaml",
         "--", sys.executable, project.node("serial_driver.py"), "--ros-args", "-r", "__node:=imu_driver",
         "-r", "__ns:=/robot1", "-p", f"port:={device}"],
        cwd=project.path, capture_output=True, text=True, timeout=120, env=dict(os.environ))
    assert captured.returncode == 0, captured.stderr


def test_a_stand_in_lets_the_system_item_pass_and_the_summary_names_the_process_not_run(robot):
    robot.write("robot.system.yaml", HEADER)
    failed = robot.run("--update-golden", "robot.system.yaml")
    failed.assert_outcomes(failed=1)
    exe = os.path.basename(sys.executable)
    failed.stdout.fnmatch_lines(["*could not open /dev/ttyFAKE*", "*stand_ins:*", "*- executable: *",
                                 "*name: /robot1/imu_driver*", "*reason: needs /dev/ttyFAKE*"])
    assert "Traceback" not in failed.stdout.str()

    capture_on_the_robot(robot)
    robot.write("robot.system.yaml", HEADER + STAND_IN.format(exe=sys.executable))
    written = robot.run("--update-golden", "robot.system.yaml")
    written.assert_outcomes(passed=1)
    text = robot.read("robot.system.yaml")
    assert text.startswith(HEADER + STAND_IN.format(exe=sys.executable))  # kept as written
    assert "/robot1/imu_driver:\n" in text and "name: /robot1/imu\n" in text

    for args in ((), ("-n", "2")):
        checked = robot.run("robot.system.yaml", *args)
        checked.assert_outcomes(passed=1)
        out = checked.stdout.str()
        checked.stdout.fnmatch_lines(["*rmw-introspect: processes stood in for, not run here (stand_ins:)*",
                                      f"robot.system.yaml: {exe} by contracts/robot1_imu_driver.interfaces.yaml"])
        assert "DANGLING" not in out


def test_a_system_without_stand_ins_has_no_such_summary(robot):
    device = robot.write("robot_dev/ttyFAKE", "")  # on the robot: the driver runs
    robot.write("launch/robot.launch.xml", imu_robot(str(device)))
    robot.write("robot.system.yaml", HEADER)
    robot.run("--update-golden", "robot.system.yaml").assert_outcomes(passed=1)
    checked = robot.run("robot.system.yaml")
    checked.assert_outcomes(passed=1)
    assert "stood in for" not in checked.stdout.str()
