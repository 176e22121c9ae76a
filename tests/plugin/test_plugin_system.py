"""System contracts in pytest: `*.system.yaml` files collected as items, the `system_contract`
marker with its `system_capture` fixture, --update-golden, drift and system problems as failures.
The launch files start the plugin tests' rclpy node scripts."""

from __future__ import annotations

import os
import sys


def launch(project, *, mistake: bool = False) -> None:
    """launch/robot.launch.xml: a talker and a listener in /robot, and (mistake) a second talker
    with the same node name."""
    second = (f'    <node exec="{sys.executable}" args="{project.node("talker.py")}" name="talker"/>\n'
              if mistake else "")
    project.robot_launch(f'{second}    <node exec="{sys.executable}" args="{project.node("qos_node.py")}"/>\n')


def test_update_golden_writes_a_system_contract_and_the_item_checks_it(project):
    launch(project)
    project.write("robot.system.yaml", "# my robot\nsystem_version: 1\nlaunch:\n  path: launch/robot.launch.xml\n")
    written = project.run("--update-golden", "robot.system.yaml", "-v")
    # written, and failed: nothing in the launch file feeds the qos node's subscriptions (issue 47)
    written.assert_outcomes(failed=1)
    written.stdout.fnmatch_lines(["*robot.system.yaml::system FAILED*",
                                  "*updated robot.system.yaml, but the system still fails its check: 2 system "
                                  "problem(s) *DANGLING_SUBSCRIPTION /robot/commands*",
                                  "*updated*robot.system.yaml*"])
    text = project.read("robot.system.yaml")
    # the hand-written header is kept; the subscriptions nothing in the launch file feeds are proposed
    # as its outside world, commented out
    proposal = ("# external:\n#   publishers:\n#     /robot/commands: WHO    # std_msgs/msg/String, for /robot/qos_node\n"
                "#     /robot/qos_node/private: WHO    # std_msgs/msg/String, for /robot/qos_node\n")
    assert text.startswith("# my robot\nsystem_version: 1\nlaunch:\n  path: launch/robot.launch.xml\n# Endpoints ")
    assert proposal in text and text.index(proposal) < text.index("\nprocesses:\n")
    assert "    name: /robot/talker\n    nodes: [/robot/talker]\n" in text
    assert "  /robot/talker:\n    publishers:\n      - name: /robot/chatter\n" in text
    undeclared = project.run("robot.system.yaml")
    undeclared.assert_outcomes(failed=1)
    undeclared.stdout.fnmatch_lines(["*[[]DANGLING_SUBSCRIPTION[]] 2 findings in 1 process*",
                                     "*: subscription of /robot/qos_node*"])
    text = text.replace(proposal, "external:\n  publishers:\n    /robot/commands: operator\n"
                                  "    /robot/qos_node/private: operator\n")
    project.write("robot.system.yaml", text)
    project.run("robot.system.yaml").assert_outcomes(passed=1)
    # another namespace: every node drifts
    project.write("robot.system.yaml", text.replace("  path: launch/robot.launch.xml\n",
                                                    "  path: launch/robot.launch.xml\n  arguments: {ns: other}\n"))
    drifted = project.run("robot.system.yaml")
    drifted.assert_outcomes(failed=1)
    drifted.stdout.fnmatch_lines(["*[[]NODE_REMOVED[]]*/robot/talker*", "*[[]NODE_ADDED[]]*/other/talker*",
                                  "*pytest --update-golden robot.system.yaml::system*"])


def test_the_marker_captures_the_system_and_fails_on_system_problems(project):
    launch(project, mistake=True)
    project.write("robot.system.yaml", "system_version: 1\nlaunch:\n  path: launch/robot.launch.xml\n")
    # written, and failed: the system is broken (issue 47)
    project.run("--update-golden", "robot.system.yaml").assert_outcomes(failed=1)
    assert "  /robot/talker:\n" in project.read("robot.system.yaml")
    project.test("""
        import os
        import sys

        @pytest.mark.system_contract("robot.system.yaml")
        def test_robot(system_capture):
            exe = os.path.basename(sys.executable)
            assert [p.label for p in system_capture.processes] == [exe, f"{exe} #2", f"{exe} #3"]
            assert system_capture.node_names == ["/robot/qos_node", "/robot/talker"]

        @pytest.mark.system_contract("robot.system.yaml", system_fail_on="any", launch_arguments={"ns": "robot"})
        def test_robot_without_the_fixture():
            pass

        @pytest.mark.system_contract("robot.system.yaml", bogus=1)
        def test_bad_marker():
            pass
        """)
    result = project.run("test_nodes.py", "--rmw-introspect-contracts", "none")
    exe = os.path.basename(sys.executable)
    result.assert_outcomes(failed=3)
    result.stdout.fnmatch_lines([
        "*System check of robot.system.yaml: 3 problems in * (3 breaking, 0 risky, 0 safe)*",
        "*[[]DUPLICATE_NODE_NAME[]] * finding*",
        f"*node of /robot/talker ({exe}) and node of /robot/talker ({exe} #2)*",
        "*unknown keyword argument(s) bogus*",
    ])
    assert "To accept these changes" not in result.stdout.str()


def test_system_contract_items_report_bad_files(project):
    project.write("bad.system.yaml", "system_version: 1\nlaunch: {path: a.xml, nope: 1}\n")
    result = project.run("-v")
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(["*bad.system.yaml::invalid FAILED*", "*invalid contract *bad.system.yaml:2: at launch: unknown key(s) *nope*"])
