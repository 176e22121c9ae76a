"""The precision table of docs/drift-rules.md is the one the precision suite's recorded results
give (tests/precision/results.json, written by `make precision-table`; the suite's own tests fail
when a run differs from the record), and the table counts what it says it counts."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
SCRIPT = REPO / "scripts" / "precision_table.py"


def _suite():
    spec = importlib.util.spec_from_file_location("precision_suite_for_table",
                                                  REPO / "tests" / "precision" / "precision_suite.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up
    spec.loader.exec_module(module)
    return module


suite = _suite()


def test_the_page_shows_the_table_of_the_recorded_results():
    page = (REPO / "docs" / "drift-rules.md").read_text(encoding="utf-8")
    table = suite.render_table(suite.load_results())
    assert suite.with_table(page, table) == page, "docs/drift-rules.md: run `make precision-table`"
    assert "### Precision and recall on modelled bring-ups" in page


def test_every_modelled_system_is_in_the_record():
    recorded = suite.load_results()["systems"]
    names = {system.name for system in suite.systems()}
    assert len(names) >= 15 and set(recorded) == names
    for name, record in recorded.items():
        assert set(suite.MUTATION_KINDS) <= set(record["mutations"]) <= set(suite.ALL_MUTATION_KINDS), name


def test_the_check_command_fails_on_a_stale_page_and_the_command_rewrites_it(tmp_path):
    page = tmp_path / "drift-rules.md"
    page.write_text(f"# rules\n\n{suite.TABLE_START}\n| an old table |\n{suite.TABLE_END}\n", encoding="utf-8")

    def run(*args):
        return subprocess.run([sys.executable, str(SCRIPT), "--doc", str(page), *args], capture_output=True, text=True)

    stale = run("--check")
    assert stale.returncode == 1 and "run `make precision-table`" in stale.stderr, stale
    assert run().returncode == 0
    assert run("--check").returncode == 0
    assert "an old table" not in page.read_text(encoding="utf-8")
    page.write_text("# a page without the markers\n", encoding="utf-8")
    missing = run("--check")
    assert missing.returncode == 2 and "markers" in missing.stderr and "Traceback" not in missing.stderr, missing


RECORD = {"systems": {
    "good": {"title": "a good robot", "correct": [["PARAM_DEVICE_ABSENT", "SAFE", "port"]], "mutations": {
        "remap_to_wrong_name": {"expect": ["TOPIC_NAME_MISMATCH"],
                                "found": [["TOPIC_NAME_MISMATCH", "BREAKING", "/scan"],
                                          ["REMAP_UNUSED", "BREAKING", "scan:=/scna"]]},
        "retyped_topic": {"expect": ["TYPE_MISMATCH"], "found": []}}},
    "flagged": {"title": "a robot a rule gets wrong", "correct": [["DANGLING_SERVICE_CLIENT", "BREAKING", "/a"],
                                                                  ["DANGLING_SERVICE_CLIENT", "BREAKING", "/b"]],
                "mutations": {"retyped_topic": {"expect": ["TYPE_MISMATCH"],
                                                "found": [["TYPE_MISMATCH", "BREAKING", "/odom"]]}}},
}}


def _row(table: str, first_cell: str) -> list[str]:
    [line] = [line for line in table.splitlines() if line.startswith(f"| {first_cell} |")]
    return [cell.strip() for cell in line.strip("|").split("|")]


def test_the_table_counts_false_and_true_findings_per_rule():
    table = suite.render_table(RECORD)
    assert table.startswith("1 of 2 correct systems pass the default gate with no finding (notes aside), "
                            "1 of 2 pass it; 2 of 3 seeded bugs fail it.")
    assert _row(table, "`DANGLING_SERVICE_CLIENT` (BREAKING)") == [
        "`DANGLING_SERVICE_CLIENT` (BREAKING)", "2", "0", "0", "0", "0/2 (0 %)", "n/a"]
    assert _row(table, "`TYPE_MISMATCH` (BREAKING)") == ["`TYPE_MISMATCH` (BREAKING)", "0", "1", "2", "1",
                                                         "1/1 (100 %)", "1/2 (50 %)"]
    assert _row(table, "`REMAP_UNUSED` (BREAKING)")[1:5] == ["0", "1", "0", "0"]
    assert _row(table, "`PARAM_DEVICE_ABSENT` (SAFE)")[5] == "note"
    assert _row(table, "a retyped topic") == ["a retyped topic", "2", "1", "1"]
    assert "| `flagged` | a robot a rule gets wrong |" in table


def test_the_table_goes_between_the_markers_and_nowhere_else():
    page = f"before\n{suite.TABLE_START}\nold\n{suite.TABLE_END}\nafter\n"
    assert suite.with_table(page, "new\n") == f"before\n{suite.TABLE_START}\nnew\n{suite.TABLE_END}\nafter\n"
    with pytest.raises(suite.SuiteError, match="markers"):
        suite.with_table("a page without them\n", "new\n")


def test_a_correct_system_with_notes_only_counts_as_passing_with_no_finding():
    record = {"systems": {"dead_remap": {"title": "an estimator with a dead remapping", "correct": [
        ["REMAP_UNUSED", "NOTE", "/gps_imu/filter:=/imu/filter"]], "mutations": {}}}}
    table = suite.render_table(record)
    assert table.startswith("1 of 1 correct systems pass the default gate with no finding (notes aside), "
                            "1 of 1 pass it")
    assert _row(table, "`REMAP_UNUSED` (NOTE)")[1:6] == ["1", "0", "0", "0", "note"]
    assert suite.is_note("REMAP_UNUSED", "NOTE") and not suite.is_note("REMAP_NEAR_MISS", "BREAKING")
