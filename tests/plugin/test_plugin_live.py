"""Live systems in pytest (issue 52 item 4): the `live_system` fixture and
`system_contract(..., live=True)` bring a launch file up on Fast DDS in a ROS_DOMAIN_ID of their
own (localhost discovery) and check the running graph against a system contract written on the
recording middleware; the system is stopped when the test ends."""

from __future__ import annotations


def test_a_launch_file_brought_up_by_a_test_is_checked_live(project):
    project.robot_launch()
    project.write("robot.system.yaml", "system_version: 1\nlaunch:\n  path: launch/robot.launch.xml\n")
    project.run("--update-golden", "robot.system.yaml").assert_outcomes(passed=1)
    project.test("""
        import os

        def test_fixture(live_system):
            robot = live_system("launch/robot.launch.xml")
            result = robot.check("robot.system.yaml")
            assert "/robot/talker" in robot.graphs[-1].capture.nodes
            assert not result.failed
            print("DOMAIN", robot.domain_id, os.environ.get("ROS_DOMAIN_ID"))

        @pytest.mark.system_contract("robot.system.yaml", live=True)
        def test_marker(system_capture):
            assert sorted(system_capture.nodes) == ["/robot/talker"]

        def test_drift(live_system):
            live_system("launch/robot.launch.xml", launch_arguments={"ns": "other"}).check("robot.system.yaml")
        """, name="test_live.py")
    result = project.run("test_live.py", "-p", "no:rmw_introspect_items", "-s", "-v", timeout=180)
    result.assert_outcomes(passed=2, failed=1)
    result.stdout.fnmatch_lines(["*test_drift FAILED*"])
    result.stdout.fnmatch_lines(["*[[]NODE_REMOVED[]]*/robot/talker*"])
    result.stdout.fnmatch_lines(["*[[]NODE_ADDED[]]*/other/talker*"])
    assert "Notes on the live graph" in result.stdout.str()
    words = next(line for line in result.stdout.lines if "DOMAIN " in line).split("DOMAIN ", 1)[1].split()
    assert words[0] != words[1], words  # a domain of its own, not the session's
