"""`rmw-introspect capture/check --stimulus NAME` on a real rclpy node whose publisher, client
and service only appear once it receives input (issue 10, stimuli)."""

from __future__ import annotations

import shutil
from pathlib import Path

import yaml

from pytest_rmw_introspect.model import contract as contract_module

CAMERA = Path(__file__).resolve().parents[1] / "middleware" / "nodes" / "stim_camera.py"
UNSPUN = CAMERA.parent / "stim_unspun.py"


def test_capture_with_stimuli_writes_them_into_the_target_and_check_repeats_them(cli):
    shutil.copy(CAMERA, cli.path / "stim_camera.py")
    result = cli("capture", "--script", "stim_camera.py", "--stimulus", "/camera_info", "--stimulus", "/calibrate",
                 "--horizon", "0", "-o", "camera.interfaces.yaml")
    assert result.returncode == 0, result
    text = cli.read("camera.interfaces.yaml")
    loaded = contract_module.loads(text)  # the schema takes the stimuli
    assert loaded.target == {"script": "stim_camera.py", "horizon": 0.0, "stimuli": ["/camera_info", "/calibrate"]}
    camera = yaml.safe_load(text)["nodes"]["/camera_proc"]
    assert [p["name"] for p in camera["publishers"]] == ["/calibration_status", "/image_rect"]
    assert [c["name"] for c in camera["service_clients"]] == ["/save_calibration"]
    # The contract's target block brings the stimuli back: the check sees the same interface.
    check = cli("check", "camera.interfaces.yaml")
    assert check.returncode == 0, check
    assert "camera.interfaces.yaml: matches (/camera_proc)" in check.stdout
    # Without them, what only input reveals is missing: drift.
    without = cli("check", "camera.interfaces.yaml", "--stimulus", "/cmd_vel")
    assert without.returncode == 1, without
    assert "/image_rect" in without.stdout and "/save_calibration" in without.stdout


def test_stimuli_that_do_not_work_are_errors_naming_them(cli):
    result = cli("capture", "--script", UNSPUN, "--stimulus", "/nothing", "--stimulus", "/ignored")
    assert result.returncode == 2, result
    assert "The stimuli of the target" in result.stderr
    assert "no subscription or service named /nothing in this process (subscriptions: /heard, /ignored" in result.stderr
    assert "/ignored (subscription of /idle): no executor takes from the subscription /ignored" in result.stderr
    assert "Traceback" not in result.stderr

    relative = cli("capture", "--script", CAMERA, "--stimulus", "camera_info")
    assert relative.returncode == 2, relative
    assert "`stimuli`: 'camera_info' is not a fully resolved topic or service name" in relative.stderr
