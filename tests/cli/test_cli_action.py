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
from sample_contracts import talker_contract

ACTION = Path(__file__).resolve().parents[2] / "action.yml"
TALKER = f"script: {NODES / 'talker.py'}"


def _run_check_step(cli, contracts: str, **inputs: str) -> tuple[subprocess.CompletedProcess[str], str, str]:
    step = next(s for s in yaml.safe_load(ACTION.read_text())["runs"]["steps"] if s.get("id") == "check")
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


def test_check_summary_to_a_file_that_cannot_be_written_is_an_error(cli):
    cli.write("talker.interfaces.yaml", talker_contract(target=TALKER))
    result = cli("check", "talker.interfaces.yaml", "--summary", "no/such/dir/summary.md")
    assert result.returncode == 2, result
    assert "--summary no/such/dir/summary.md: cannot append the report" in result.stderr
