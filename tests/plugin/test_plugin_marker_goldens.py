"""Goldens of marker tests that are also contract files pytest collects (issue 31): the marker
test checks its golden and the file's own item is skipped, naming the test, so that the
sequence a user runs (--update-golden, then pytest, then pytest -n 2) is green whatever the
golden is called; goldens outside the contract patterns and rmw_capture tests stay green too.
Real pytest sessions on real rclpy nodes."""

from __future__ import annotations

from pathlib import Path

import pytest
from test_plugin_system import launch

NODES = Path(__file__).parent / "nodes"

#: the test of the issue, word for word: a golden next to the test, a node run by command
ZOO_TEST = """
import sys, pytest
@pytest.mark.interfaces({golden!r}, command=[sys.executable, "qos_zoo.py"])
def test_zoo(interfaces):
    assert interfaces.nodes
"""


def skipped_as_checked_by(golden: str, test: str, *, runs_alone: bool = True) -> str:
    """The line of ``-rs`` for a contract item skipped because ``test`` checks its file."""
    line = f"SKIPPED [[]1[]] *{golden} is the golden of {test}, which checks it in this session"
    return line + (f" with the marker's keywords; *run it alone: pytest {golden}" if runs_alone else "")


@pytest.mark.parametrize("golden", ["zoo.interfaces.yaml", "zoo.yaml"])
def test_update_then_plain_then_xdist_runs_of_the_issue_are_green(project, golden):
    project.write("qos_zoo.py", (NODES / "qos_node.py").read_text())
    project.write("test_zoo.py", ZOO_TEST.format(golden=golden))

    written = project.run("--update-golden")
    written.assert_outcomes(passed=1)
    written.stdout.fnmatch_lines([f"created  {golden}", "1 golden contract(s) written"])
    assert "\ntarget:\n  command:\n" in project.read(golden)  # the marker's target (issue 47)

    # a contract by its content whatever its name (issue 47): collected, and skipped for its test
    for extra in ((), ("-n", "2")):
        result = project.run("-rs", *extra)
        result.assert_outcomes(passed=1, skipped=1)
        result.stdout.fnmatch_lines([skipped_as_checked_by(golden, "test_zoo.py::test_zoo")])
        assert "has no `target:` block" not in result.stdout.str()

    again = project.run("--update-golden")
    again.assert_outcomes(passed=1, skipped=1)
    again.stdout.fnmatch_lines(["*no golden contract needed changes*"])

    # run alone, without the test: the golden names the marker's target, so it checks by itself
    project.run(golden).assert_outcomes(passed=1)


def test_the_marker_checks_its_golden_with_its_keywords_and_the_item_only_runs_without_it(project):
    """A contract file with a target of its own, and a marker test naming it with keywords that
    change what the target creates: checked once, by the marker test, with the marker's keywords;
    --update-golden writes them into the file's target (issue 47), so the item alone checks the same."""
    project.write("contracts/talker.interfaces.yaml",
                  f"contract_version: 1\ntarget:\n  script: {NODES / 'talker.py'}\nnodes: {{}}\n")
    project.test("""
        @pytest.mark.interfaces("contracts/talker.interfaces.yaml", namespace="/robot1")
        def test_talker(interfaces):
            assert "/robot1/talker" in interfaces
        """)
    written = project.run("--update-golden", "-rs")
    written.assert_outcomes(passed=1, skipped=1)
    written.stdout.fnmatch_lines(["updated  contracts/talker.interfaces.yaml"])
    assert "/robot1/talker:" in project.read("contracts/talker.interfaces.yaml")

    for extra in ((), ("-n", "2")):
        result = project.run("-rs", *extra)
        result.assert_outcomes(passed=1, skipped=1)
        result.stdout.fnmatch_lines([skipped_as_checked_by("contracts/talker.interfaces.yaml",
                                                           "test_nodes.py::test_talker")])

    assert "\n  namespace: /robot1\n" in project.read("contracts/talker.interfaces.yaml")

    # a deselected marker test checks nothing: the file is an item of its own again, with the marker's target
    project.run("--deselect", "test_nodes.py::test_talker").assert_outcomes(passed=1)


def test_a_golden_named_through_a_symlink_is_the_file_it_links_to(project):
    """A contract shared through a symlink: the marker names the link, pytest collects the file."""
    project.write("shared/talker.interfaces.yaml", f"contract_version: 1\ntarget:\n  script: {NODES / 'talker.py'}\n"
                  "nodes: {}\n")
    (project.path / "pkg").mkdir()
    (project.path / "pkg" / "talker.yaml").symlink_to(project.path / "shared" / "talker.interfaces.yaml")
    project.test("""
        @pytest.mark.interfaces("talker.yaml", namespace="/robot1")
        def test_talker(interfaces):
            pass
        """, name="pkg/test_nodes.py")
    # the link is a contract by its content too: both items are skipped for the test
    project.run("--update-golden").assert_outcomes(passed=1, skipped=2)
    assert (project.path / "pkg" / "talker.yaml").is_symlink()
    result = project.run("-rs")
    result.assert_outcomes(passed=1, skipped=2)
    result.stdout.fnmatch_lines([skipped_as_checked_by("shared/talker.interfaces.yaml", "pkg/test_nodes.py::test_talker")])


def test_a_marker_without_keywords_on_a_file_with_a_target_leaves_the_item_running(project):
    """The item checks what the test checks (the example package's contracts, checked both ways)."""
    project.write("contracts/talker.interfaces.yaml",
                  f"contract_version: 1\ntarget:\n  script: {NODES / 'talker.py'}\nnodes: {{}}\n")
    project.test("""
        @pytest.mark.interfaces("contracts/talker.interfaces.yaml")
        def test_talker(interfaces):
            assert "/talker" in interfaces
        """)
    project.run("--update-golden").assert_outcomes(passed=2)
    result = project.run("-rA")
    result.assert_outcomes(passed=2)
    result.stdout.fnmatch_lines(["PASSED contracts/talker.interfaces.yaml::/talker"])


def test_a_system_contract_that_a_marker_test_names_is_checked_by_that_test(project):
    launch(project)  # a talker and a qos_node in the namespace of the launch argument `ns` (default robot)
    # the qos_node's two inputs come from outside the launch file (declared: issue 26's rules)
    project.write("robot.system.yaml", "system_version: 1\nlaunch:\n  path: launch/robot.launch.xml\n"
                  "external:\n  publishers:\n    /other/commands: a teleop\n    /other/qos_node/private: a test\n")
    project.test("""
        @pytest.mark.system_contract("robot.system.yaml", launch_arguments={"ns": "other"})
        def test_robot(system_capture):
            assert system_capture.node_names == ["/other/qos_node", "/other/talker"]
        """)
    written = project.run("--update-golden")
    written.assert_outcomes(passed=1, skipped=1)
    written.stdout.fnmatch_lines(["updated  robot.system.yaml"])
    for extra in ((), ("-n", "2")):
        result = project.run("-rs", *extra)
        result.assert_outcomes(passed=1, skipped=1)
        result.stdout.fnmatch_lines([skipped_as_checked_by("robot.system.yaml", "test_nodes.py::test_robot")])


def test_goldens_outside_the_contract_patterns_and_rmw_capture_tests_stay_green(project):
    """The contract patterns narrowed to contracts/ (as the security note of docs/contract-files.md suggests):
    a marker golden under tests/goldens/ is not an item, a contract file in contracts/ is, and an
    rmw_capture test writes nothing; every run of the sequence is green, the file item included."""
    project.pytester.makeini("[pytest]\nrmw_introspect_contracts = contracts/*.interfaces.yaml\n")
    project.write("contracts/listener.interfaces.yaml",
                  f"contract_version: 1\ntarget:\n  script: {NODES / 'talker.py'}\n"
                  "  node_name: listener\n  parameters: {listen: /chatter}\nnodes: {}\n")
    project.test("""
        @pytest.mark.interfaces("goldens/talker.interfaces.yaml", script=NODES + "/talker.py")
        def test_talker(interfaces):
            assert "/talker" in interfaces

        def test_capture(rmw_capture):
            capture = rmw_capture(script=NODES + "/talker.py", namespace="/robot2")
            assert capture.node_names == ["/robot2/talker"]
        """, name="tests/test_nodes.py")
    written = project.run("--update-golden")
    written.assert_outcomes(passed=3)
    written.stdout.fnmatch_lines(["created  tests/goldens/talker.interfaces.yaml"])
    written.stdout.fnmatch_lines(["updated  contracts/listener.interfaces.yaml"])
    for extra in ((), ("-n", "2")):
        result = project.run("-rA", *extra)
        result.assert_outcomes(passed=3)
        result.stdout.fnmatch_lines(["PASSED contracts/listener.interfaces.yaml::/listener"])
        assert "goldens/talker.interfaces.yaml::" not in result.stdout.str()


def test_a_golden_that_does_not_load_fails_once_in_the_test_that_names_it(project):
    """Nothing to run alone: the marker test reports the file, its items are skipped."""
    project.write("bad.system.yaml", "system_version: 1\nlaunch: {path: a.xml, nope: 1}\n")
    project.write("bad.interfaces.yaml", "contract_version: 1\nnodes: [\n")
    project.test("""
        @pytest.mark.system_contract("bad.system.yaml")
        def test_robot(system_capture):
            pass

        @pytest.mark.interfaces("bad.interfaces.yaml")
        def test_node(interfaces):
            pass
        """)
    result = project.run("-rs")
    result.assert_outcomes(failed=2, skipped=2)
    result.stdout.fnmatch_lines([skipped_as_checked_by("bad.interfaces.yaml", "test_nodes.py::test_node", runs_alone=False)])
    result.stdout.fnmatch_lines([skipped_as_checked_by("bad.system.yaml", "test_nodes.py::test_robot", runs_alone=False)])
    result.stdout.fnmatch_lines(["*invalid contract *bad.system.yaml:2: at launch: unknown key(s) *nope*"])
