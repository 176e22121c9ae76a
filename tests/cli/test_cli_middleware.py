"""Issue 49 item 3 end to end with `rmw-introspect check`: a camera publishing BEST_EFFORT and a
detector subscribing RELIABLE. On a DDS middleware the match is refused (QOS_INCOMPATIBLE,
BREAKING); on rmw_zenoh_cpp it connects, and the pair is a note. The middleware comes from the
contract's `rmw:`, else RMW_IMPLEMENTATION in the launch environment, else `--rmw`."""

from __future__ import annotations

from sample_systems import in_namespace, script_node

HEADER = "system_version: 1\nlaunch: {path: launch/robot.launch.xml}\n"
CAMERA = script_node("talker.py", "camera", '<param name="topic" value="image"/>',
                     '<param name="reliability" value="best_effort"/>')
DETECTOR = script_node("talker.py", "detector", '<param name="topic" value="detections"/>',
                       '<param name="listen" value="image"/>')
NOTE = ("note: robot.system.yaml: /robot/detector: rmw_zenoh_cpp connects these whatever their QoS, a DDS middleware "
        "would refuse the match (BEST_EFFORT publisher and RELIABLE subscription): it matters if the system moves to DDS")


def test_the_system_s_middleware_judges_its_qos(cli):
    cli.write("launch/robot.launch.xml", in_namespace("robot", CAMERA, DETECTOR))
    cli.write("robot.system.yaml", HEADER)
    updated = cli("check", "--update", "robot.system.yaml", timeout=120)
    assert updated.returncode == 1, updated  # written, and broken under the DDS rules
    assert "[QOS_INCOMPATIBLE]" in updated.stdout and "BEST_EFFORT publisher and RELIABLE subscription" in updated.stdout
    contract = cli.read("robot.system.yaml")

    # --rmw for a contract that does not say
    zenoh = cli("check", "robot.system.yaml", "--rmw", "rmw_zenoh_cpp", timeout=120)
    assert zenoh.returncode == 0, zenoh
    assert NOTE in zenoh.stderr.splitlines(), zenoh.stderr
    assert cli("check", "robot.system.yaml", "--rmw", "rmw_cyclonedds_cpp", timeout=120).returncode == 1

    # the contract's word beats --rmw
    cli.write("robot.system.yaml", contract.replace("launch:", "rmw: rmw_zenoh_cpp\nlaunch:", 1))
    said = cli("check", "robot.system.yaml", "--rmw", "rmw_fastrtps_cpp", timeout=120)
    assert said.returncode == 0 and NOTE in said.stderr.splitlines(), said

    # RMW_IMPLEMENTATION in the launch environment, for a contract that does not say
    cli.write("robot.system.yaml", contract)
    cli.write("launch/robot.launch.xml", in_namespace("robot", CAMERA, DETECTOR).replace(
        "<launch>\n", '<launch>\n  <set_env name="RMW_IMPLEMENTATION" value="rmw_zenoh_cpp"/>\n', 1))
    launched = cli("check", "robot.system.yaml", timeout=120)
    assert launched.returncode == 0 and NOTE in launched.stderr.splitlines(), launched

    # a middleware the rules do not know: an error naming the file and the known ones
    cli.write("robot.system.yaml", contract.replace("launch:", "rmw: rmw_gurumdds_cpp\nlaunch:", 1))
    unknown = cli("check", "robot.system.yaml", timeout=120)
    assert unknown.returncode == 2, unknown
    assert "robot.system.yaml" in unknown.stderr and "rmw_gurumdds_cpp" in unknown.stderr
    assert "rmw_zenoh_cpp" in unknown.stderr
