"""Issue 47, findings 3 and 7, in pytest: a system whose `cmd_vel` is remapped on one side only
(its subscription dangles) and whose driver runs fine without its device. Under
`--update-golden` the system contract's item and a `system_contract` marker test write the
contract and fail, saying that it was written and what is still broken (the item printed
"1 passed"); the device note is said once in the run's terminal summary, short and without the
stand-in advice, not in every failure report."""

from __future__ import annotations

from sample_systems import half_remapped_robot

HEADER = "system_version: 1\nlaunch: {path: launch/robot.launch.xml}\n"


def test_update_golden_over_a_broken_system_writes_and_fails_and_notes_once(project):
    project.write("launch/robot.launch.xml", half_remapped_robot())
    project.write("robot.system.yaml", HEADER)
    project.test("""
        @pytest.mark.system_contract("robot.system.yaml")
        def test_robot(system_capture):
            assert "/robot/base" in system_capture.node_names
        """)
    result = project.run("--update-golden", "robot.system.yaml", "test_nodes.py")
    result.assert_outcomes(failed=2)  # finding 3: the item was "1 passed"
    out = result.stdout.str()
    # the item writes the contract; the marker test, after it, finds nothing left to write
    result.stdout.fnmatch_lines([
        "*updated robot.system.yaml, but the system still fails its check: 1 system problem(s) at or above "
        "system_fail_on (breaking): DANGLING_SUBSCRIPTION /robot/chatter.*",
        "*[[]DANGLING_SUBSCRIPTION[]]*",
    ])
    assert out.count("[DANGLING_SUBSCRIPTION]") == 2, out
    assert "  /robot/base:\n" in project.read("robot.system.yaml")
    result.stdout.fnmatch_lines(["*rmw-introspect: golden contracts*", "*updated*robot.system.yaml*"])
    # finding 7: one note for the run, in the summary, short, no stand-in advice
    notes = [line for line in out.splitlines() if "/dev/ttyFAKE" in line]
    assert notes == ["robot.system.yaml: /robot/driver: parameter `port` is '/dev/ttyFAKE:115200': the device "
                     "/dev/ttyFAKE, which this machine does not have (not judged: the robot has it)"], out
    assert out.index("rmw-introspect: notes") < out.index(notes[0])
