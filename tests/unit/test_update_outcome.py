"""Issue 47: an update that leaves a system broken writes the golden and fails the run (finding
3), and a check's notes are said once per run, as notices under ``--format github`` (finding 7):
``check.outcome.decide`` and ``compare.ci_report`` without capturing."""

from __future__ import annotations

from pathlib import Path

from pytest_rmw_introspect.check import system_pipeline
from pytest_rmw_introspect.check.outcome import Verdict, decide
from pytest_rmw_introspect.compare import ci_report
from pytest_rmw_introspect.compare.compatibility import CompatItem, ContractEndpoint
from pytest_rmw_introspect.compare.drift import compare
from pytest_rmw_introspect.compare.options import ComparisonOptions
from pytest_rmw_introspect.model.contract_shapes import ContractNodes
from pytest_rmw_introspect.model.system_contract import loads as load_system
from pytest_rmw_introspect.model.vocabulary import Severity

TEXT = "system_version: 1\nlaunch: {path: robot.launch.xml}\nprocesses: []\nnodes:\n  /base: {}\n"
BASE: ContractNodes = {"/base": {"subscriptions": [{"name": "/chatter", "type": "std_msgs/msg/String"}]}}


def dangling(severity: Severity = Severity.BREAKING) -> CompatItem:
    return CompatItem("DANGLING_SUBSCRIPTION", severity, "/chatter", ContractEndpoint("python #2", "/base",
                      "subscriptions"), None, "no publisher in the system")


def result(*problems: CompatItem, drift: bool = True, contract: bool = True) -> system_pipeline.SystemCheckResult:
    system = load_system(TEXT, path="robot.system.yaml") if contract else None
    return system_pipeline.SystemCheckResult(
        path=Path("robot.system.yaml"), shown="robot.system.yaml", contract=system, options=ComparisonOptions(),
        drift_items=compare(system.nodes, BASE) if system is not None and drift else [], system_items=list(problems))


def test_an_update_over_a_system_still_broken_writes_and_fails():
    written = decide(result(dangling()), update=True)
    assert written.verdict is Verdict.WRITE and written.failed
    assert written.unfixed.startswith("the system still fails its check: 1 system problem(s) at or above "
                                      "system_fail_on (breaking): DANGLING_SUBSCRIPTION /chatter. ")
    assert "[DANGLING_SUBSCRIPTION]" in written.report  # what is still broken, with the drift written
    # a new contract too
    created = decide(result(dangling(), contract=False), update=True)
    assert created.verdict is Verdict.WRITE and created.failed and "[DANGLING_SUBSCRIPTION]" in created.report


def test_a_clean_update_and_problems_below_the_threshold_pass():
    for problems in ((), (dangling(Severity.RISKY),)):
        written = decide(result(*problems), update=True)
        assert written.verdict is Verdict.WRITE and not written.failed and written.unfixed == ""
    assert not decide(result(contract=False), update=True).failed


def test_the_ci_formats_count_a_written_contract_by_what_the_update_left():
    written = result(dangling()).for_ci(written="updated")
    assert written.failed  # the system problem: the drift is what was written
    assert "✏️ updated, but ❌ system check: 1 breaking, 0 risky, 0 safe" in ci_report.drift_markdown([written])
    clean = result().for_ci(written="updated")
    assert not clean.failed and "all 1 pass" in ci_report.drift_markdown([clean])


def test_notes_are_notices_said_once_per_run():
    note = ("/driver: parameter `port` is '/dev/ttyFAKE': the device /dev/ttyFAKE, which this machine does not have "
            "(not judged: the robot has it)")
    first = ci_report.ContractOutcome(contract="a.system.yaml", notices=[(note, 7)])
    second = ci_report.ContractOutcome(contract="b.system.yaml", notices=[(note, 9)], notes=["a rename"])
    assert ci_report.once([first, second]) == [[(note, 7)], []]
    github = ci_report.drift_github([first, second]).splitlines()
    assert github == [f"::notice file=a.system.yaml,line=7,title=note::{note}",
                      "::notice file=b.system.yaml,title=note::a rename"]
    markdown = ci_report.drift_markdown([first, second])
    assert markdown.count("parameter `port`") == 1 and "> a rename" in markdown


def test_the_stand_in_advice_is_given_where_a_node_without_its_device_fails():
    note = CompatItem("PARAM_DEVICE_ABSENT", Severity.SAFE, "port", ContractEndpoint("python", "/base", "node"), None,
                      "parameter `port` is '/dev/ttyFAKE': ...")
    checked = result()  # /base drifts: it gains a subscription
    checked.rule_notes = [note]
    assert checked.stand_in_advice() == []
    checked.drift_items = compare(BASE, {"/base": {}})  # it lost its subscription
    [advice] = checked.stand_in_advice()
    assert advice.startswith("/base ran without the device its parameter `port` names") and "stand_ins:" in advice
    assert "Hardware processes" in checked.render_text()
    checked.drift_items = []  # the node matches: a note, and no advice
    assert checked.stand_in_advice() == [] and "stand_ins" not in checked.render_text()


def dead_remap() -> CompatItem:
    return CompatItem("REMAP_UNUSED", Severity.NOTE, "/gps_imu/filter:=/imu/filter",
                      ContractEndpoint("python #2", "/base", "node"), None,
                      "the remapping /gps_imu/filter -> /imu/filter changed none of the names of /base")


def test_a_note_is_shown_in_every_format_and_fails_no_threshold():
    """Severity.NOTE: below SAFE, shown by text, JSON, markdown, github and SARIF, never failing
    (not at fail_on any, not at system_fail_on any), and no drift an update must accept."""
    from pytest_rmw_introspect.compare import sarif
    from pytest_rmw_introspect.model.vocabulary import parse_threshold

    checked = result(dead_remap(), drift=False)
    for word in ("any", "risky", "breaking"):
        checked.options = ComparisonOptions(fail_on=word, system_fail_on=word)
        assert not checked.failed, word
    assert not checked.drifted
    outcome = decide(checked, update=False)
    assert outcome.verdict is Verdict.PASS and not outcome.failed
    assert outcome.message.startswith("robot.system.yaml: matches (")
    assert outcome.message.endswith("; 1 note")
    assert "NOTE (1) - notes, never failing" in outcome.report
    assert "0 breaking, 0 risky, 0 safe, 1 note" in outcome.report
    assert "[REMAP_UNUSED]" in outcome.report
    assert [(i["rule"], i["severity"]) for i in outcome.json] == [("REMAP_UNUSED", "NOTE")]
    assert decide(checked, update=True).verdict is Verdict.PASS  # nothing for an update to write
    ci = checked.for_ci()
    assert not ci.failed
    assert "✅ matches (0 breaking, 0 risky, 0 safe, 1 note)" in ci_report.drift_markdown([ci])
    assert ci_report.annotation_level(Severity.NOTE, parse_threshold("any")) == "notice"
    assert sarif.level(Severity.NOTE, parse_threshold("any")) == "note"
    levels = [r["level"] for r in sarif.drift_log([ci], tool_version="0")["runs"][0]["results"]]
    assert levels == ["note"]
