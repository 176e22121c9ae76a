"""Stimuli (issue 10, item 5): with RMW_INTROSPECT_STIMULI the middleware, after the probing,
hands one default-constructed message to each named subscription (rmw_take*) and one default
request to each named service (rmw_take_request; its answer is discarded), each followed by a
settle, so that what a node creates in response is captured. Real rclpy nodes on the raw
middleware, then through the Python runner (`capture(stimuli=...)`)."""

import re

import pytest
import rmwi_helpers as h
from rmwi_helpers import ep, node
from rmwi_helpers import rclpy_node_infrastructure as infra

import pytest_rmw_introspect
from pytest_rmw_introspect.errors import StimulusFailed, TargetConfigError

CAMERA = "/camera_proc"


def camera_own(*created):
    """The camera node's own endpoints at start-up, then `created`."""
    n = CAMERA
    return infra(n) + [
        ep("subscription", n, "/camera_info", "sensor_msgs/msg/CameraInfo"),
        ep("subscription", n, "/raw_in", "std_msgs/msg/String"),
        ep("subscription", n, "/cmd_vel", "geometry_msgs/msg/Twist"),
        ep("service", n, "/calibrate", "std_srvs/srv/Trigger", h.QOS_SERVICES),
        *created,
    ]


def target(kind, type_, result="taken", node_=CAMERA, error=None):
    return {"kind": kind, "node": node_, "type": type_, "result": result, "error": error}


def stimulus(name, *targets, state="done", error=None):
    return {"name": name, "state": state, "targets": list(targets), "error": error}


def created_in(capture):
    return {e["name"]: e["created_in"] for e in capture["endpoints"]}


@pytest.mark.parametrize("delivery", ["0", "1"])
def test_stimuli_reveal_what_a_node_creates_on_input(run, delivery):
    # Also with in-process delivery on: the stimulus comes before whatever the process sends.
    result = run(h.python_node("stim_camera.py"),
                 env={"RMW_INTROSPECT_STIMULI": "/camera_info, /raw_in,/calibrate,/cmd_vel",
                      "RMW_INTROSPECT_DELIVERY": delivery})
    h.assert_settled_process(result)
    capture = result.capture
    assert capture["format_minor"] == 4
    n = CAMERA
    h.assert_capture(capture, [node("camera_proc")], camera_own(
        ep("publisher", n, "/image_rect", "sensor_msgs/msg/Image", h.qos(depth=5)),
        ep("publisher", n, "/raw_seen", "std_msgs/msg/String"),
        ep("client", n, "/save_calibration", "std_srvs/srv/Trigger", h.QOS_SERVICES),
        ep("publisher", n, "/calibration_status", "std_msgs/msg/String"),
    ))
    assert capture["stimuli"] == [
        stimulus("/camera_info", target("subscription", "sensor_msgs/msg/CameraInfo")),
        stimulus("/raw_in", target("subscription", "std_msgs/msg/String")),
        stimulus("/calibrate", target("service", "std_srvs/srv/Trigger", "answered")),
        stimulus("/cmd_vel", target("subscription", "geometry_msgs/msg/Twist")),
    ]
    made = created_in(capture)
    assert made["/image_rect"] == "stimulus:/camera_info"
    assert made["/raw_seen"] == "stimulus:/raw_in"
    assert made["/save_calibration"] == made["/calibration_status"] == "stimulus:/calibrate"
    assert made["/camera_info"] is None and made["/rosout"] is None
    # One default-constructed message each: zero numbers (fixed arrays too), empty strings and
    # sequences; the raw subscription got the CDR of an empty std_msgs/String.
    assert "camera_info: width=0 height=0 frame_id='' k=[" in result.stderr, result.stderr
    k = re.search(r"camera_info: .* k=\[([^\]]*)\] d=\[\] model=''", result.stderr)
    assert k is not None and k.group(1).count("0.0") == 9, result.stderr
    assert "raw_in: bytes of 9 bytes" in result.stderr  # encapsulation + length 1 + '\0' (+ padding)
    assert "calibrate: Trigger_Request" in result.stderr
    assert "cmd_vel: 0.0" in result.stderr
    # Delivered once each, and invisible as traffic: the takes are not the node's activity.
    assert result.stderr.count("camera_info:") == 1 and result.stderr.count("calibrate:") == 1
    assert capture["probe"]["state"] == "done" and capture["probe"]["requests"] == 3
    assert capture["settled_by"] == "wait"


def test_stimuli_are_off_by_default_and_add_nothing(run):
    result = run(h.python_node("stim_camera.py"))
    h.assert_settled_process(result)
    h.assert_capture(result.capture, [node("camera_proc")], camera_own())
    assert result.capture["stimuli"] == []
    assert all(e["created_in"] is None for e in result.capture["endpoints"])
    assert "camera_info:" not in result.stderr and "calibrate:" not in result.stderr
    assert result.capture["probe"]["requests"] == 3  # the parameters only


def test_a_timer_the_reaction_starts_fires_in_the_warp(run):
    result = run(h.python_node("stim_camera.py"),
                 env={"RMW_INTROSPECT_STIMULI": "/calibrate", "RMW_INTROSPECT_HORIZON_MS": "3000"})
    h.assert_settled_process(result)
    made = created_in(result.capture)
    assert made["/calibration_status"] == "stimulus:/calibrate"
    # Created 1 s later in virtual time, after the process had settled from the stimulus: it is
    # captured, but not claimed as the stimulus's reaction.
    assert "/calibration_report" in made and made["/calibration_report"] is None
    assert result.capture["time"]["jumps"] >= 1


def test_stimuli_without_probing_and_with_a_lifecycle_node(run):
    only = run(h.python_node("stim_camera.py"),
               env={"RMW_INTROSPECT_STIMULI": "/camera_info", "RMW_INTROSPECT_PARAMETERS": "0",
                    "RMW_INTROSPECT_LIFECYCLE": "none"})
    h.assert_settled_process(only)
    assert only.capture["probe"]["state"] == "done" and only.capture["probe"]["requests"] == 0
    assert created_in(only.capture)["/image_rect"] == "stimulus:/camera_info"
    assert all(record["parameters"] is None for record in only.capture["nodes"])
    # The lifecycle node's subscription and service exist once it is active: the stimuli come
    # after the driving, and what activate created keeps its label.
    managed = run(h.python_node("lc_managed.py"), env={"RMW_INTROSPECT_STIMULI": "/cmd,/reset"})
    h.assert_settled_process(managed)
    assert managed.capture["stimuli"] == [
        stimulus("/cmd", target("subscription", "std_msgs/msg/String", node_="/managed")),
        stimulus("/reset", target("service", "std_srvs/srv/Trigger", "answered", node_="/managed")),
    ]
    assert created_in(managed.capture)["/cmd"] == "activate"


def test_names_that_match_nothing_or_no_executor_are_reported_and_the_rest_delivered(run):
    # No answer timeout is spent on the unserved one: with a 60 s answer timeout, waiting for it
    # would overrun the run's own 20 s timeout (no wall-clock bound here: the machine may be loaded)
    result = run(h.python_node("stim_unspun.py"),
                 env={"RMW_INTROSPECT_STIMULI": "/nothing,/heard,/ignored,/echo",
                      "RMW_INTROSPECT_ANSWER_TIMEOUT_MS": "60000"}, timeout=20)
    h.assert_settled_process(result)
    assert result.capture["probe"]["answer_timeout_ms"] == 60000
    nothing, heard, ignored, echo = result.capture["stimuli"]
    assert nothing["state"] == "no_match" and nothing["targets"] == []
    assert nothing["error"].startswith(
        "no subscription or service named /nothing in this process (subscriptions: /heard, /ignored; "
        "services: none)."), nothing["error"]
    assert heard == stimulus("/heard", target("subscription", "std_msgs/msg/String", node_="/spun"))
    assert ignored == stimulus("/ignored", target(
        "subscription", "std_msgs/msg/String", "failed", node_="/idle",
        error="no executor takes from the subscription /ignored (it was never in a wait set)"))
    # /echo exists by now (the reaction to /heard), but as a publisher.
    assert echo["state"] == "no_match"
    assert "There is a publisher /echo (of /spun), but stimuli go to subscriptions and services." in echo["error"]
    assert created_in(result.capture)["/echo"] == "stimulus:/heard"


def test_a_process_that_never_waits_gets_no_stimulus_and_the_capture_says_why(run):
    result = run(h.python_node("vt_old_school.py"), env={"RMW_INTROSPECT_STIMULI": "/topic_in"})
    h.assert_settled_process(result)
    assert result.capture["probe"]["state"] == "skipped"
    assert result.capture["stimuli"] == [stimulus(
        "/topic_in", state="skipped",
        error="not delivered: no thread of the process ever waited in rmw_wait (no executor spins), so nothing "
              "could take it")]


def test_a_node_that_cannot_cope_with_a_default_message_ends_and_says_so(run):
    result = run(h.python_node("stim_crash.py"), env={"RMW_INTROSPECT_STIMULI": "/image"})
    assert result.returncode == 1, str(result)
    assert "IndexError" in result.stderr
    capture = result.capture
    assert capture["state"] == "exit" and capture["ended"] == {"before_settle": True}
    # The take never came back to the middleware as an outcome: still in flight.
    assert capture["stimuli"] == [stimulus("/image", target(
        "subscription", "sensor_msgs/msg/Image", "pending", node_="/fragile"))]


def test_bad_names_are_warned_about_and_left_out(run):
    result = run(h.python_node("talker.py"), env={"RMW_INTROSPECT_STIMULI": "chatter,/chatter,/chatter"})
    h.assert_settled_process(result)
    assert ("[rmw_introspect] warning: RMW_INTROSPECT_STIMULI: 'chatter' is not a fully qualified topic or "
            "service name") in result.stderr
    assert "'/chatter' is named twice: it is stimulated once" in result.stderr
    [only] = result.capture["stimuli"]
    assert only["name"] == "/chatter" and only["state"] == "no_match"  # the talker publishes it


# ----------------------------------------------------------------------------- Python runner
def node_script(name):
    return str(h.NODES / name)


def test_runner_capture_with_stimuli():
    cap = pytest_rmw_introspect.capture(script=node_script("stim_camera.py"), stimuli=["/camera_info", "/calibrate"])
    camera = cap[CAMERA]
    # The runner's default horizon (10 s) lets the report timer the reaction started fire.
    assert [p.name for p in camera.publishers] == ["/calibration_report", "/calibration_status", "/image_rect"]
    assert [c.name for c in camera.service_clients] == ["/save_calibration"]
    assert [s["name"] for s in cap.raw["stimuli"]] == ["/camera_info", "/calibrate"]
    without = pytest_rmw_introspect.capture(script=node_script("stim_camera.py"))
    assert [p.name for p in without[CAMERA].publishers] == []
    assert without.raw["stimuli"] == []


def test_runner_fails_clearly_on_stimuli_that_did_not_work():
    with pytest.raises(StimulusFailed) as failed:
        pytest_rmw_introspect.capture(script=node_script("stim_unspun.py"), stimuli="/nothing /ignored /heard")
    message = str(failed.value)
    assert message.startswith(f"The stimuli of the target script {node_script('stim_unspun.py')} did not work out:\n")
    assert "  - no subscription or service named /nothing in this process" in message
    assert ("  - /ignored (subscription of /idle): no executor takes from the subscription /ignored (it was never "
            "in a wait set)") in message
    assert failed.value.partial is not None and "/echo" in [p.name for p in failed.value.partial["/spun"].publishers]
    assert len(failed.value.problems) == 2

    with pytest.raises(StimulusFailed) as crashed:
        pytest_rmw_introspect.capture(script=node_script("stim_crash.py"), stimuli=["/image"])
    message = str(crashed.value)
    assert ("the process exited with status 1 after the middleware delivered a stimulus (the last: a default "
            "message or request to the subscription /image of /fragile)") in message
    assert "IndexError" in message  # the stderr tail


def test_runner_refuses_names_that_are_not_fully_resolved():
    with pytest.raises(TargetConfigError, match=r"`stimuli`: 'camera_info' is not a fully resolved"):
        pytest_rmw_introspect.capture(script=node_script("stim_camera.py"), stimuli=["camera_info"])
