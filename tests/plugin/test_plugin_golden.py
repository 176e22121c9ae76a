"""Missing golden → --update-golden creates it → the test passes → regenerating changes no byte."""

from __future__ import annotations

from sample_contracts import talker_contract

from pytest_rmw_introspect.run import ros_env

TALKER_TEST = """
@pytest.mark.interfaces("contracts/talker.yaml", script=NODES + "/talker.py")
def test_talker(interfaces):
    assert interfaces["/talker"].publishers[0].name == "/chatter"
"""

#: the ROS 2 distribution this venv runs: golden writes record it (``ros_distribution:``)
DISTRIBUTION = ros_env.detect().distro
RECORDED = f"contract_version: 1\nros_distribution: {DISTRIBUTION}\n"

EXPECTED_TALKER_CONTRACT = talker_contract(
    header="# Interface contract checked by pytest-rmw-introspect.\n"
    "# Regenerate with `pytest --update-golden`; comments and keys above `nodes:` are kept.\n",
    distribution=DISTRIBUTION)


def expected_talker_contract(project) -> str:
    """The golden TALKER_TEST writes: with its marker's target (issue 47: checkable by itself)."""
    return EXPECTED_TALKER_CONTRACT.replace(RECORDED, f"{RECORDED}target:\n  script: {project.node('talker.py')}\n")


def test_missing_golden_fails_with_the_command_that_creates_it(project):
    project.test(TALKER_TEST)
    result = project.run()
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines([
        "*The golden contract contracts/talker.yaml does not exist.*",
        "*pytest --update-golden test_nodes.py::test_talker",
        "*Captured:*",
        "*/talker*",
        "*publishers: /chatter [[]std_msgs/msg/String[]]*",
    ])
    assert not (project.path / "contracts" / "talker.yaml").exists()
    assert "Traceback" not in result.stdout.str()


def test_update_golden_creates_the_contract_and_then_it_passes(project):
    project.test(TALKER_TEST)
    result = project.run("--update-golden")
    result.assert_outcomes(passed=1)
    result.stdout.fnmatch_lines([
        "*rmw-introspect: --update-golden*",
        "*rmw-introspect: golden contracts*",
        "created  contracts/talker.yaml",
        "1 golden contract(s) written",
    ])
    assert project.read("contracts/talker.yaml") == expected_talker_contract(project)

    project.run().assert_outcomes(passed=1, skipped=1)  # the golden's own item: skipped, its marker test checks it

    again = project.run("--update-golden")
    again.assert_outcomes(passed=1, skipped=1)
    again.stdout.fnmatch_lines(["*no golden contract needed changes*"])
    assert project.read("contracts/talker.yaml") == expected_talker_contract(project)


def test_update_golden_on_an_invalid_golden_says_so_and_leaves_it(project):
    project.test(TALKER_TEST)
    broken = "contract_version: 1\nnodes:\n  /talker:\n    publishers: [\n"
    project.write("contracts/talker.yaml", broken)
    result = project.run("--update-golden")
    result.assert_outcomes(failed=1, skipped=1)
    out = result.stdout.str()
    # the path as everywhere else in pytest's messages: relative to where pytest was started
    assert "invalid contract contracts/talker.yaml:5: YAML syntax error" in out
    failure = out.split("FAILURES")[1].split("rmw-introspect: golden contracts")[0]
    assert str(project.path) not in failure
    assert "--update-golden does not overwrite an invalid contract" in out
    result.stdout.fnmatch_lines([
        "*rmw-introspect: golden contracts*",
        "invalid  contracts/talker.yaml  (not written: fix or delete it, then run --update-golden again)",
        "0 golden contract(s) written; 1 invalid golden contract(s) not written",
    ])
    assert "no golden contract needed changes" not in out
    assert project.read("contracts/talker.yaml") == broken


def test_update_rewrites_a_drifted_golden_keeping_header_target_and_options(project):
    header = (
        "# The talker's interface. Owner: team-demo.\n"
        "contract_version: 1\n"
        "\n"
        "# run the demo talker with its defaults\n"
        "target:\n"
        f"  script: {project.node('talker.py')}\n"
        "options:\n"
        "  fail_on: any   # everything counts\n"
    )
    project.write("contracts/talker.yaml", header + (
        "nodes:\n"
        "  /talker:\n"
        "    publishers:\n"
        "      - {name: /old_topic, type: std_msgs/msg/String, qos: default}\n"
    ))
    project.test("""
        @pytest.mark.interfaces("contracts/talker.yaml")
        def test_talker(interfaces):
            pass
    """)
    project.run().assert_outcomes(failed=2)  # the golden names its target and the marker adds nothing: both check it
    result = project.run("--update-golden")
    result.assert_outcomes(passed=2)
    result.stdout.fnmatch_lines(["updated  contracts/talker.yaml"])
    text = project.read("contracts/talker.yaml")
    assert text.startswith(header)
    assert text == header + EXPECTED_TALKER_CONTRACT.split(RECORDED, 1)[1]
    project.run().assert_outcomes(passed=2)


def test_update_golden_refuses_a_read_only_golden(project):
    drifted = "contract_version: 1\nnodes:\n  /talker:\n    publishers: []\n"
    golden = project.write("contracts/talker.yaml", drifted)
    golden.chmod(0o444)
    project.test(TALKER_TEST)
    result = project.run("--update-golden")
    result.assert_outcomes(failed=1, skipped=1)
    result.stdout.fnmatch_lines(["*cannot write *contracts/talker.yaml: it is read-only (mode 0444*"
                                 "Make it writable (chmod u+w *"])
    assert project.read("contracts/talker.yaml") == drifted and golden.stat().st_mode & 0o777 == 0o444


def test_update_keeps_equivalent_spellings_of_undrifted_entries(project):
    project.write("contracts/svc.yaml", (
        "contract_version: 1\n"
        "nodes:\n"
        "  /talker:\n"
        "    publishers:\n"
        "      - name: /chatter\n"
        "        type: std_msgs/msg/String\n"
        "        qos: default\n"
    ))
    project.test("""
        @pytest.mark.interfaces("contracts/svc.yaml", script=NODES + "/talker.py", parameters={"listen": "/in"})
        def test_talker():
            pass
    """)
    project.run("--update-golden").assert_outcomes(passed=1, skipped=1)
    text = project.read("contracts/svc.yaml")
    # the untouched entry keeps its profile name and its (absent) type hash; the new one is complete
    assert "      - name: /chatter\n        type: std_msgs/msg/String\n        qos: default\n" in text
    assert "      - name: /in\n        type: std_msgs/msg/String\n        type_hash: RIHS01_" in text


def test_ci_refuses_update_golden(project):
    project.test(TALKER_TEST)
    project.pytester._monkeypatch.setenv("CI", "true")
    result = project.run("--update-golden")
    assert result.ret == 4  # pytest.ExitCode.USAGE_ERROR
    result.stderr.fnmatch_lines(["*--update-golden refuses to write golden contracts in CI*'true'*"])
    assert not (project.path / "contracts").exists()


def test_ci_set_to_false_does_not_refuse(project):
    project.test(TALKER_TEST)
    project.pytester._monkeypatch.setenv("CI", "false")
    project.run("--update-golden").assert_outcomes(passed=1)
    assert (project.path / "contracts" / "talker.yaml").exists()


def test_ci_without_update_golden_is_fine(project):
    project.test(TALKER_TEST)
    project.pytester._monkeypatch.setenv("CI", "1")
    project.run().assert_outcomes(failed=1)  # the golden is missing: a failure, not a usage error


def test_only_selected_tests_update_their_goldens(project):
    project.test("""
        @pytest.mark.interfaces("a.yaml", script=NODES + "/talker.py")
        def test_a():
            pass

        @pytest.mark.interfaces("b.yaml", script=NODES + "/talker.py")
        def test_b():
            pass
    """)
    project.run("--update-golden", "test_nodes.py::test_a").assert_outcomes(passed=1)
    assert (project.path / "a.yaml").exists()
    assert not (project.path / "b.yaml").exists()


def test_test_body_failure_is_reported_and_nothing_is_written(project):
    project.test("""
        @pytest.mark.interfaces("c.yaml", script=NODES + "/talker.py")
        def test_talker(interfaces):
            assert "/listener" in interfaces, "expected a listener"
    """)
    result = project.run("--update-golden")
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(["*AssertionError: expected a listener*"])
    assert not (project.path / "c.yaml").exists()
