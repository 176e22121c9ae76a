""".ci/run's closing table and its failures (issue 48, item 6 and "fast feedback first"): each tier,
its minutes and its budget (.ci/budgets, the one place budgets are written), a tier over budget
named as a warning, never a failure; a failing tier names the command that reproduces it; lint,
the docs and the unit tier run before the long tiers."""

from __future__ import annotations

import importlib.util
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
CI = ROOT / ".ci"
_spec = importlib.util.spec_from_file_location("tier_table", CI / "tier_table.py")
assert _spec is not None and _spec.loader is not None
tier_table = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(tier_table)


def _tiers_of_ci_run() -> list[str]:
    """The tier names .ci/run gives, in order (``tier NAME ...`` and the conformance suites)."""
    text = (CI / "run").read_text(encoding="utf-8")
    names = re.findall(r"^\s*tier ([a-z0-9-]+) ", text, re.M)
    names += [f"conformance-{d}" for d in re.findall(r"^\s*conformance (jazzy|kilted) ", text, re.M)]
    return names


def test_the_budgets_name_every_tier_of_ci_run_and_nothing_else():
    budgets = tier_table.read_budgets((CI / "budgets").read_text(encoding="utf-8"))
    tiers = _tiers_of_ci_run()
    assert "conformance-$1" not in tiers and {"lint", "unit", "test", "py312", "lowest", "kilted", "slow"} <= set(tiers)
    assert sorted(set(budgets) - {"total"}) == sorted(set(tiers))
    assert budgets["total"] == 90


def test_lint_docs_and_the_unit_tier_run_before_the_long_tiers():
    tiers = [t for t in _tiers_of_ci_run() if not t.startswith("conformance")]
    assert tiers.index("lint") < tiers.index("unit") < tiers.index("test") < tiers.index("py312")
    assert tiers.index("docs") < tiers.index("test")


def test_the_table_gives_minutes_and_budgets_and_names_what_is_over():
    times = tier_table.read_times("lint 30 0\ntest 1700 0\nconformance-kilted 0 skipped\npy312 100 2\nnew 60 0\n")
    lines, over = tier_table.table(times, {"lint": 2, "test": 25, "conformance-kilted": 15, "py312": 22, "total": 30})
    assert over == ["test", "total"]
    assert lines[1].split() == ["ci:", "lint", "0.5", "2", "ok"]
    assert lines[2].split()[:5] == ["ci:", "test", "28.3", "25", "ok,"] and "OVER BUDGET by 3.3 min" in lines[2]
    assert lines[3].split() == ["ci:", "conformance-kilted", "0.0", "15", "skipped"]
    assert "FAILED (exit 2)" in lines[4] and "OVER" not in lines[4]
    assert lines[5].split() == ["ci:", "new", "1.0", "-", "ok"]  # a tier without a budget: shown, never over
    assert lines[6].split() == ["ci:", "total", "31.5", "30"]


def test_over_budget_is_a_warning_and_the_exit_status_stays_0(tmp_path):
    (tmp_path / "times").write_text("test 6000 0\n")
    out = subprocess.run([sys.executable, str(CI / "tier_table.py"), str(tmp_path / "times"), str(CI / "budgets")],
                         capture_output=True, text=True)
    assert out.returncode == 0
    assert "ci: warning: over budget" in out.stdout and out.stdout.rstrip().endswith("test, total")
    # no tier ran (CI failed before the first): an empty table, still exit status 0
    out = subprocess.run([sys.executable, str(CI / "tier_table.py"), str(tmp_path / "none"), str(CI / "budgets")],
                         capture_output=True, text=True)
    assert out.returncode == 0 and "total" in out.stdout


@pytest.fixture
def ci_functions() -> str:
    """.ci/run's ``words``, ``tier`` and ``skipped`` functions, to run in a shell of the test's own."""
    text = (CI / "run").read_text(encoding="utf-8")
    return text[text.index("words() {"):text.index("# Chromium and Graphviz")]


def test_a_failing_tier_stops_the_run_with_the_command_that_reproduces_it(tmp_path, ci_functions):
    script = ci_functions + textwrap.dedent("""
        ci_times=times.tsv
        tier first true
        tier broken sh -c 'exit 3' PYTEST_ARGS="-p no:cacheprovider -m 'e2e or plugin'"
        echo not reached
    """)
    out = subprocess.run(["bash", "-c", script], cwd=tmp_path, capture_output=True, text=True)
    assert out.returncode == 3 and "not reached" not in out.stdout
    assert "ci: tier broken FAILED (exit 3); reproduce it locally with:" in out.stdout
    assert """ci:   sh -c exit\\ 3 PYTEST_ARGS="-p no:cacheprovider -m 'e2e or plugin'\"""" in out.stdout
    assert (tmp_path / "times.tsv").read_text().split("\n")[:2] == ["first 0 0", "broken 0 3"]

