"""The lint hooks (.pre-commit-config.yaml): `make lint` and CI run them, and they must work
offline from a fresh clone. These tests fail when a hook would download something (a remote
repository, a language pre-commit installs an environment for), when a hook's tool is not in the
locks, or when `make lint` or `.ci/run` stop running the hooks."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
CONFIG = ROOT / ".pre-commit-config.yaml"
HOOK_SCRIPT = ROOT / "scripts" / "lint-hook.sh"


def _hooks() -> list[dict]:
    config = yaml.safe_load(CONFIG.read_text(encoding="utf-8"))
    return [hook for repo in config["repos"] for hook in repo["hooks"]]


def test_every_hook_is_local_and_runs_a_tool_of_the_venv():
    config = yaml.safe_load(CONFIG.read_text(encoding="utf-8"))
    assert [repo["repo"] for repo in config["repos"]] == ["local"] * len(config["repos"]), \
        "a remote hook repository is cloned at run time: make it `repo: local`"
    hooks = _hooks()
    assert {hook["id"] for hook in hooks} == {"ruff", "clang-format"}
    for hook in hooks:
        assert hook["language"] == "system", f"{hook['id']}: pre-commit would install an environment for it"
        assert hook["entry"].split()[0] == "scripts/lint-hook.sh", hook


@pytest.mark.parametrize("lock", ["jazzy", "kilted"])
def test_the_hooks_tools_are_in_the_lock(lock):
    text = (ROOT / "requirements" / f"{lock}.txt").read_text(encoding="utf-8")
    missing = [tool for tool in ("pre-commit", "ruff", "clang-format") if not re.search(rf"^{tool}==\S+ \\$", text, re.M)]
    assert missing == [], f"requirements/{lock}.txt does not pin {missing}: add them to requirements/tools.in, `make lock`"


def test_the_clang_format_hook_covers_the_middleware_and_the_cpp_examples():
    (hook,) = [hook for hook in _hooks() if hook["id"] == "clang-format"]
    files = re.compile(hook["files"])
    cpp = sorted(str(p.relative_to(ROOT)) for pattern in ("*.cpp", "*.hpp")
                 for top in ("rmw_introspect_cpp", "examples") for p in (ROOT / top).rglob(pattern))
    assert any(p.startswith("rmw_introspect_cpp/src/") for p in cpp) and any(p.startswith("examples/") for p in cpp)
    assert [p for p in cpp if not files.search(p)] == []
    assert not files.search("pytest_rmw_introspect/cli/parser.py")


def test_make_lint_and_ci_run_the_hooks():
    makefile = (ROOT / "Makefile").read_text(encoding="utf-8")
    recipe = makefile.split("\nlint:", 1)[1].split("\n\n", 1)[0]
    assert "pre-commit run --all-files" in recipe
    assert re.search(r"^(tier [a-z0-9-]+ )?make lint$", (ROOT / ".ci" / "run").read_text(encoding="utf-8"), re.M)


def test_the_clang_format_hook_skips_while_the_root_has_no_style():
    """Until the root has a .clang-format there is no style to check: the hook passes, saying so."""
    if (ROOT / ".clang-format").is_file():
        pytest.skip("the root has a .clang-format: `make lint` checks the C++ against it")
    skipped = subprocess.run([str(HOOK_SCRIPT), "clang-format", "rmw_introspect_cpp/src/rmw_client.cpp"],
                             capture_output=True, text=True, env={"PATH": "/usr/bin:/bin"})
    assert skipped.returncode == 0 and "no .clang-format at the root" in skipped.stdout


def test_the_hook_script_names_a_missing_tool(tmp_path):
    missing = subprocess.run([str(HOOK_SCRIPT), "ruff"], capture_output=True, text=True,
                             env={"PATH": "/usr/bin:/bin", "VENV": str(tmp_path)})
    assert missing.returncode == 1 and "no ruff in" in missing.stderr and "make bootstrap" in missing.stderr
