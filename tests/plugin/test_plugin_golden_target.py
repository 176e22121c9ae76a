"""Issue 47, finding 4: the golden a marker test writes is a contract file like any other. The quick
start's golden (``contracts/talker.yaml``, written by ``pytest --update-golden``) is checked by
``rmw-introspect check`` (exit 0 on the unchanged node, 1 once the node drifts) and collected by
``pytest contracts/``, in a user's repository (a temporary git repository, as the trial had)."""

from __future__ import annotations

import os
import shutil
import subprocess

from cli_process import Result, console_script
from git_history import GitRepo
from sample_contracts import talker_contract

from pytest_rmw_introspect.model import contract_kind

TEST_FILE = """
@pytest.mark.interfaces("contracts/talker.yaml", script="nodes/talker.py", parameters={"depth": 10})
def test_talker(interfaces):
    assert "/talker" in interfaces.nodes
"""


def _check(project, *args: str) -> Result:
    proc = subprocess.run([console_script(), "check", *args], cwd=project.path, capture_output=True, text=True,
                          timeout=120, check=False, env=os.environ)
    return Result(proc.returncode, proc.stdout, proc.stderr)


def test_a_marker_golden_is_checked_by_rmw_introspect_check_and_collected_by_pytest_contracts(project):
    repo = GitRepo(project.path)
    (project.path / "test" / "nodes").mkdir(parents=True)
    shutil.copy(project.node("talker.py"), project.path / "test" / "nodes" / "talker.py")
    project.test(TEST_FILE, name="test/test_talker.py")
    project.write("test/contracts/params.yaml", "/talker:\n  ros__parameters:\n    depth: 10\n")

    written = project.run("--update-golden", "test/test_talker.py")
    written.assert_outcomes(passed=1)
    repo.commit("the quick start: a marker test and its golden")

    unchanged = _check(project, "test/contracts/talker.yaml")  # before issue 47: exit 2, "has no target: block"
    assert unchanged.returncode == 0, unchanged
    assert "test/contracts/talker.yaml: matches (/talker)" in unchanged.stdout
    golden = project.path / "test" / "contracts" / "talker.yaml"
    # the marker's target, relative to the golden, above `nodes:`; in the order of the contract's keys
    assert "\ntarget:\n  script: ../nodes/talker.py\n  parameters:\n    depth: 10\nnodes:\n" in golden.read_text()
    assert contract_kind.kind_of_file(golden) is contract_kind.Kind.NODE

    # pytest contracts/ collects the golden by its content, and not the parameters file beside it
    collected = project.run("--collect-only", "-q", "test/contracts")
    collected.stdout.fnmatch_lines(["test/contracts/talker.yaml::/talker", "1 test collected*"])
    assert "params.yaml" not in collected.stdout.str()

    # the node drifts: its topic is renamed
    node = project.path / "test" / "nodes" / "talker.py"
    node.write_text(node.read_text().replace('"topic", "chatter"', '"topic", "scan"'))
    drifted = _check(project, "test/contracts/talker.yaml")
    assert drifted.returncode == 1, drifted
    assert "/chatter" in drifted.stdout and "/scan" in drifted.stdout


def test_contract_files_are_collected_by_content_and_a_golden_without_target_says_the_one_command(project):
    project.test(TEST_FILE, name="test/test_talker.py")
    (project.path / "test" / "nodes").mkdir(parents=True)
    shutil.copy(project.node("talker.py"), project.path / "test" / "nodes" / "talker.py")
    project.write("test/contracts/talker.yaml", talker_contract())  # written before goldens had a target
    project.write("test/contracts/camera.yml", talker_contract(target="script: ../nodes/talker.py"))
    project.write("test/contracts/robot.yaml", "system_version: 1\nlaunch:\n  file: robot.launch.xml\n")
    project.write("test/contracts/params.yaml", "/talker:\n  ros__parameters:\n    depth: 10\n")
    project.write("test/contracts/talker.nodl.yaml", "nodl_version: 2\n")
    project.write("test/launch/robot.launch.yaml", "launch:\n  - node: {pkg: demo, exec: talker}\n")

    collected = project.run("--collect-only", "-q")
    collected.stdout.fnmatch_lines_random([
        "test/contracts/camera.yml::/talker", "test/contracts/robot.yaml::*",
        "test/contracts/talker.yaml::/talker", "test/test_talker.py::test_talker"])
    collected.stdout.fnmatch_lines(["4 tests collected*"])

    # the golden has no target: `check` names the one command that writes it (exit status 2)
    result = _check(project, "test/contracts/talker.yaml")
    assert result.returncode == 2, result
    assert ("test/contracts/talker.yaml is the golden of the marker test test/test_talker.py::test_talker"
            in result.stderr), result
    assert "\n  pytest --update-golden test/test_talker.py::test_talker\n" in result.stderr

    # ... and that command writes the marker's target into it, keeping the rest
    before = project.read("test/contracts/talker.yaml")
    project.run("--update-golden", "test/test_talker.py::test_talker").assert_outcomes(passed=1)
    after = project.read("test/contracts/talker.yaml")
    assert after.replace("target:\n  script: ../nodes/talker.py\n  parameters:\n    depth: 10\n", "") == before
