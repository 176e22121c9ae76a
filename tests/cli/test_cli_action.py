"""The check step of the GitHub Action (action.yml) run by bash as a runner runs it, with the real
`rmw-introspect` on real nodes: globs find the contracts, drift becomes annotations on the contract
lines, the Markdown report lands in the job summary, the exit status in the step's output."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import yaml
from cli_helpers import NODES
from git_history import GitRepo, endpoint, node_contract
from sample_contracts import talker_contract

ACTION = Path(__file__).resolve().parents[2] / "action.yml"
TALKER = f"script: {NODES / 'talker.py'}"


def _step(step_id: str) -> dict:
    return next(s for s in yaml.safe_load(ACTION.read_text())["runs"]["steps"] if s.get("id") == step_id)


def _run_check_step(cli, contracts: str, **inputs: str) -> tuple[subprocess.CompletedProcess[str], str, str]:
    step = _step("check")
    summary, output = cli.path / "summary.md", cli.path / "output.txt"
    summary.write_text("# earlier step\n")
    output.write_text("")
    env = dict(cli.env, PATH=f"{Path(sys.executable).parent}{os.pathsep}{cli.env.get('PATH', '')}",
               GITHUB_STEP_SUMMARY=str(summary), GITHUB_OUTPUT=str(output), RMWI_CONTRACTS=contracts,
               RMWI_FAIL_ON=inputs.get("fail_on", ""), RMWI_BASELINE="", RMWI_ARGS=inputs.get("args", ""))
    result = subprocess.run(["bash", "-e", "-c", step["run"]], cwd=cli.path, env=env, capture_output=True,
                            text=True, timeout=180)
    return result, summary.read_text(), output.read_text()


def test_the_action_annotates_drift_and_writes_the_job_summary(cli):
    cli.write("contracts/a/talker.interfaces.yaml", talker_contract(target=TALKER))
    cli.write("contracts/b/drifted.interfaces.yaml", talker_contract(target=TALKER, depth=3))
    result, summary, output = _run_check_step(cli, "contracts/**/*.interfaces.yaml\n  other/*.interfaces.yaml")
    assert result.returncode == 1, result
    assert "::warning file=contracts/b/drifted.interfaces.yaml,line=" in result.stdout or \
        "::error file=contracts/b/drifted.interfaces.yaml,line=" in result.stdout, result.stdout
    assert "QOS_DEPTH_INCREASED" in result.stdout
    assert summary.startswith("# earlier step\n"), summary  # appended, never replaced
    assert "| `contracts/a/talker.interfaces.yaml` |" in summary and "✅ matches" in summary, summary
    assert "`contracts/b/drifted.interfaces.yaml`" in summary and "QOS_DEPTH_INCREASED" in summary, summary
    assert output == "exit-code=1\n"

    below = _run_check_step(cli, "contracts/b/drifted.interfaces.yaml", fail_on="breaking", args="--ignore-qos depth")
    assert below[0].returncode == 0 and below[2] == "exit-code=0\n", below


def test_the_action_fails_when_no_contract_matches(cli):
    result, _, output = _run_check_step(cli, "nothing/**/*.interfaces.yaml")
    assert result.returncode == 2 and output == "exit-code=2\n", result
    assert "::error title=rmw-introspect action::no contract file matches 'nothing/**/*.interfaces.yaml'" in result.stdout


def test_the_action_finds_the_contracts_by_their_content_by_default(cli):
    """Issue 47: the check step's `**/*.interfaces.yaml` found no contract named as the README
    names them; without `contracts` it checks every contract under working-directory by content."""
    cli.write("test/contracts/talker.yaml", talker_contract(target=TALKER))
    cli.write("config/params.yaml", "talker:\n  ros__parameters:\n    rate: 10\n")
    result, summary, output = _run_check_step(cli, "")
    assert result.returncode == 0 and output == "exit-code=0\n", result
    assert "| `test/contracts/talker.yaml` |" in summary and "✅ matches" in summary, summary
    assert "1 contract under . (1 node contract); not contracts" in result.stderr and "config/params.yaml" in result.stderr


def test_the_action_fails_when_it_finds_no_contract_by_content(cli_nodes_only):
    cli_nodes_only.write("config/params.yaml", "talker:\n  ros__parameters:\n    rate: 10\n")
    result, summary, output = _run_check_step(cli_nodes_only, "")
    assert result.returncode == 2 and output == "exit-code=2\n", result
    assert "::error title=rmw-introspect action::no `node` or `golden` or `system` contract under ." in result.stdout
    assert "error (exit 2)" in summary and "config/params.yaml" in summary, summary


def test_check_summary_to_a_file_that_cannot_be_written_is_an_error(cli):
    cli.write("talker.interfaces.yaml", talker_contract(target=TALKER))
    result = cli("check", "talker.interfaces.yaml", "--summary", "no/such/dir/summary.md")
    assert result.returncode == 2, result
    assert "--summary no/such/dir/summary.md: cannot append the report" in result.stderr


def test_the_action_gates_a_pull_request_against_its_base(tmp_path):
    """The gate step (input `against`) on a repository with real history: the breaking change of
    the branch is an annotation on the contract line, the report lands in the job summary."""
    repo = GitRepo(tmp_path / "repo")
    repo.write("contracts/talker.interfaces.yaml", node_contract(publishers=endpoint("/chatter"), version="1.0.0"))
    repo.commit("talker")
    repo.git("checkout", "-q", "-b", "pr")
    repo.write("contracts/talker.interfaces.yaml", node_contract(publishers=endpoint("/chatter", "std_msgs/msg/Int32"),
                                                                 version="1.1.0"))
    repo.commit("retype with a minor bump")
    result, summary, output = _run_gate_step(repo, tmp_path)
    assert result.returncode == 1, result
    assert ("::error file=contracts/talker.interfaces.yaml,line=2,title=INTERFACE_VERSION_BUMP_MISSING (BREAKING)::"
            in result.stdout), result.stdout
    assert "write interface_version: 2.0.0" in summary and summary.startswith("# earlier")
    assert "1 contract: 1 marker golden; 1 changed" in summary
    assert output == "exit-code=1\n"

    repo.write("contracts/talker.interfaces.yaml", node_contract(publishers=endpoint("/chatter", "std_msgs/msg/Int32"),
                                                                 version="2.0.0"))
    repo.commit("2.0.0")
    again, _, output = _run_gate_step(repo, tmp_path)
    assert again.returncode == 0 and output == "exit-code=0\n", again


def test_the_action_gate_fails_when_it_finds_no_contract(tmp_path):
    """Issue 47: the gate step wrote "all 0 pass" with an empty table, exit 0."""
    repo = GitRepo(tmp_path / "repo")
    repo.write("config/params.yaml", "driver:\n  ros__parameters:\n    rate: 10\n")
    repo.commit("no contract")
    result, summary, output = _run_gate_step(repo, tmp_path)
    assert result.returncode == 2 and output == "exit-code=2\n", result
    assert "::error title=rmw-introspect gate::no contract to compare" in result.stdout, result.stdout
    assert "error (exit 2)" in summary and "config/params.yaml" in summary, summary


def _run_gate_step(repo: GitRepo, tmp_path: Path) -> tuple[subprocess.CompletedProcess[str], str, str]:
    summary, output = tmp_path / "summary.md", tmp_path / "output.txt"
    summary.write_text("# earlier step\n")
    output.write_text("")
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}",
               GITHUB_STEP_SUMMARY=str(summary), GITHUB_OUTPUT=str(output), RMWI_AGAINST="main...HEAD",
               RMWI_FAIL_ON="", RMWI_BASELINE="")
    result = subprocess.run(["bash", "-e", "-c", _step("gate")["run"]], cwd=repo.path, env=env, capture_output=True,
                            text=True, timeout=180)
    return result, summary.read_text(), output.read_text()
