"""scripts/coverage_summary.py (issue 48, item 3): one run's line coverage and exercised set in one
file, and what a later run covers less (so that a cut of the suite never lowers either)."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location("coverage_summary", ROOT / "scripts" / "coverage_summary.py")
assert _spec is not None and _spec.loader is not None
coverage_summary = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(coverage_summary)


def _coverage(percent: float, files: dict[str, float]) -> dict:
    return {"totals": {"percent_covered": percent, "covered_lines": int(percent * 10), "num_statements": 1000},
            "files": {path: {"summary": {"percent_covered": p}} for path, p in files.items()}}


def _run(directory: Path, percent: float, files: dict[str, float], exercised: dict) -> Path:
    (directory / "cost").mkdir(parents=True)
    (directory / "coverage.json").write_text(json.dumps(_coverage(percent, files)))
    (directory / "cost" / "report.json").write_text(json.dumps({"exercised": exercised}))
    return directory


def test_the_summary_and_a_comparison_that_finds_nothing_less(tmp_path, capsys):
    before = _run(tmp_path / "a", 70.0, {"p/a.py": 50.0}, {"e2e": {"rule": ["PUB_REMOVED"]}, "unit": {}})
    assert coverage_summary.main([str(before)]) == 0
    summary = json.loads((before / "summary.json").read_text())
    assert summary["line_coverage"] == {"percent": 70.0, "covered": 700, "statements": 1000, "files": {"p/a.py": 50.0}}
    after = _run(tmp_path / "b", 71.0, {"p/a.py": 50.0, "p/new.py": 10.0},
                 {"e2e": {"rule": ["PUB_REMOVED", "SUB_ADDED"]}, "unit": {}})
    assert coverage_summary.main([str(after), "--compare", str(before / "summary.json")]) == 0
    out = capsys.readouterr().out
    assert "line coverage of pytest_rmw_introspect: 71.0% (710 of 1000 lines)" in out and "nothing less than" in out


def test_less_names_a_lower_total_a_lower_file_and_what_is_no_longer_exercised_end_to_end():
    old = coverage_summary.summary(_coverage(70.0, {"p/a.py": 50.0, "p/b.py": 90.0}),
                                   {"exercised": {"e2e": {"rule": ["A", "B"], "format": ["check sarif"]},
                                                  "unit": {"rule": ["U"]}}})
    new = coverage_summary.summary(_coverage(69.5, {"p/a.py": 50.0, "p/b.py": 80.0}),
                                   {"exercised": {"e2e": {"rule": ["A"]}, "unit": {}}})
    assert coverage_summary.less(old, new) == [
        "line coverage 70.0% -> 69.5%", "p/b.py: 90.0% -> 80.0%",
        "no longer exercised end to end (rule): B", "no longer exercised end to end (format): check sarif"]
    assert coverage_summary.less(old, old) == []
