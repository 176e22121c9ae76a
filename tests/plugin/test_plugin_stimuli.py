"""Stimuli as a marker keyword and in a contract's target block (issue 10): the interfaces a
node creates only on input are captured, checked, and written by --update-golden."""

from __future__ import annotations

from pathlib import Path

CAMERA = str(Path(__file__).resolve().parents[1] / "middleware" / "nodes" / "stim_camera.py")

MARKER_TEST = f"""
@pytest.mark.interfaces("contracts/camera.yaml", script={CAMERA!r}, stimuli=["/camera_info"], horizon=0)
def test_camera(interfaces):
    assert interfaces["/camera_proc"].names("publishers") == ["/image_rect"]
"""


def test_marker_stimuli_are_captured_and_written_to_the_golden(project):
    project.test(MARKER_TEST)
    project.run("--update-golden").assert_outcomes(passed=1)
    text = project.read("contracts/camera.yaml")
    assert "      - name: /image_rect\n        type: sensor_msgs/msg/Image\n" in text
    assert "\n  stimuli:\n  - /camera_info\n" in text  # the marker's target, stimuli included (issue 47)
    project.run().assert_outcomes(passed=1, skipped=1)


def test_contract_target_stimuli_and_a_misnamed_one(project):
    project.write("camera.interfaces.yaml", f"""\
        contract_version: 1
        target:
          script: {CAMERA}
          horizon: 0
          stimuli: [/camera_inf]
        nodes: {{}}
        """)
    result = project.run()
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines([
        "*The stimuli of the target script*did not work out:*",
        "*no subscription or service named /camera_inf in this process (subscriptions: /camera_info, /cmd_vel, "
        "/raw_in; services: /calibrate)*",
    ])
    assert "Traceback" not in result.stdout.str()
