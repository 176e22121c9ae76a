"""A failing system check of 150 processes reads at scale (issue 42): its problems grouped by
rule and by process, the longest lists cut with a count, in text, Markdown and GitHub
annotations. The findings are the compatibility rules' own, run on 150 processes' nodes (what a
capture of them gives the rules); no process runs here (tests/cli/test_cli_system_scale.py
captures a real 150-process system)."""

from __future__ import annotations

from pytest_rmw_introspect.compare import ci_report, report
from pytest_rmw_introspect.compare.ci_report import ContractOutcome
from pytest_rmw_introspect.compare.compatibility import LaunchedProcess, check_launched
from pytest_rmw_introspect.model.vocabulary import Severity

PAIRS = 75  # 150 processes


def _topic(name: str, type_: str = "std_msgs/msg/String") -> dict:
    return {"name": name, "type": type_}


def system_problems():
    """75 talkers and 75 listeners; every listener listens on a topic nobody publishes, and the
    first five talkers publish their chatter with another type than a sixth process expects."""
    processes = []
    for i in range(PAIRS):
        processes.append(LaunchedProcess(label=f"demo/talker #{i + 1}", expected=f"/r{i}/talker",
                                         nodes={f"/r{i}/talker": {"publishers": [_topic(f"/r{i}/chatter")]}}))
        processes.append(LaunchedProcess(label=f"demo/listener #{i + 1}", expected=f"/r{i}/listener",
                                         nodes={f"/r{i}/listener": {"subscriptions": [_topic(f"/r{i}/heard")]}}))
    processes.append(LaunchedProcess(label="demo/monitor", expected="/monitor", nodes={"/monitor": {
        "subscriptions": [_topic(f"/r{i}/chatter", "std_msgs/msg/Int32") for i in range(5)]}}))
    return check_launched(processes)


def test_findings_group_by_rule_then_process_most_findings_first():
    items = system_problems()
    groups = report.by_rule_and_process(items)
    rules = {group.rule: group for group in groups}
    assert set(rules) == {"DANGLING_SUBSCRIPTION", "TYPE_MISMATCH"}, [i.rule for i in items]
    assert rules["DANGLING_SUBSCRIPTION"].count == PAIRS
    assert len(rules["DANGLING_SUBSCRIPTION"].places) == PAIRS
    assert [(p.place, len(p.items)) for p in rules["TYPE_MISMATCH"].places] == [("demo/monitor", 5)]
    assert [g.severity for g in groups] == sorted((g.severity for g in groups), reverse=True)


def test_the_text_report_cuts_long_lists_and_counts_the_rest():
    items = system_problems()
    text = report.render_system_problems(items, threshold=Severity.BREAKING, title="System check of big.system.yaml")
    lines = text.splitlines()
    assert lines[0].startswith(f"System check of big.system.yaml: {len(items)} problems in {PAIRS + 1} processes (")
    assert "  [TYPE_MISMATCH] 5 findings in 1 process" in lines
    assert f"  [DANGLING_SUBSCRIPTION] {PAIRS} findings in {PAIRS} processes" in lines
    hidden = PAIRS - report.PROCESSES_SHOWN
    assert f"    ... and {hidden} more findings in {hidden} more processes (all of them: --format json)" in lines
    # one process with five findings of a rule: three shown, two counted
    assert "      ... and 2 more findings" in lines
    assert sum(1 for line in lines if line.startswith("      /r") and "TYPE" not in line) <= 30
    assert len(lines) < 60  # 80 findings, a screenful


def test_markdown_and_github_cut_the_same_way():
    items = system_problems()
    nodes = sorted({n for i in range(PAIRS) for n in (f"/r{i}/talker", f"/r{i}/listener")})
    outcome = ContractOutcome("big.system.yaml", (), Severity.RISKY, nodes, system_items=items,
                              system_threshold=Severity.BREAKING)
    markdown = ci_report.drift_markdown([outcome])
    assert f"and {len(nodes) - ci_report.NODES_SHOWN} more |" in markdown  # the table row stays a row
    assert "- " + Severity.BREAKING.name + " `TYPE_MISMATCH`: 5 finding(s) in 1 process(es)" in markdown
    hidden = PAIRS - report.PROCESSES_SHOWN
    assert f"  - ... and {hidden} more findings in {hidden} more processes" in markdown
    assert len(markdown.splitlines()) < 60
    github = ci_report.drift_github([outcome]).splitlines()
    assert len(github) == report.PROCESSES_SHOWN + report.FINDINGS_SHOWN + 2  # two rules: each cut, counted once
    assert any(f"{hidden} more finding(s) of this rule not annotated" in line for line in github)
    assert any("2 more finding(s) of this rule not annotated" in line for line in github)


def test_a_small_system_is_shown_whole():
    items = [i for i in system_problems() if i.rule == "TYPE_MISMATCH"][:2]
    text = report.render_system_problems(items)
    assert "more" not in text and text.count("/r") == 4  # each finding: its topic and its publisher's node


def drift_in_many_nodes(count: int):
    """``count`` talkers whose chatter was renamed, and one whose node is gone."""
    from pytest_rmw_introspect.compare import drift
    from pytest_rmw_introspect.compare.options import ComparisonOptions

    old = {f"/r{i}/talker": {"publishers": [_topic(f"/r{i}/chatter")]} for i in range(count)}
    new = {f"/r{i}/talker": {"publishers": [_topic(f"/r{i}/chat")]} for i in range(1, count)}
    return drift.compare(old, new, ComparisonOptions())


def test_drift_in_many_nodes_groups_by_rule_then_node_and_cuts():
    items = drift_in_many_nodes(40)
    assert report.at_scale(items)
    text = report.render_text(items, contract_path="big.system.yaml", threshold=Severity.BREAKING).splitlines()
    assert text[0].startswith(f"Interface drift against big.system.yaml: {len(items)} changes in 40 nodes (")
    rules = [line for line in text if line.startswith("  [")]
    assert rules == ["  [NODE_REMOVED] 1 change in 1 node", "  [PUB_REMOVED] 1 change in 1 node",
                     "  [PUB_RENAMED] 39 changes in 39 nodes"], text
    hidden = 39 - report.PROCESSES_SHOWN
    assert f"    ... and {hidden} more changes in {hidden} more nodes (all of them: --format json)" in text
    assert "    /r1/talker" in text and "    /r2/talker" in text and "    /r10/talker" in text  # natural order
    assert any(line.startswith("      publisher /r1/chatter: ") for line in text), text
    outcome = ContractOutcome("big.system.yaml", items, Severity.RISKY, [f"/r{i}/talker" for i in range(40)])
    markdown = ci_report.drift_markdown([outcome])
    assert f"  - ... and {hidden} more changes in {hidden} more nodes" in markdown
    github = ci_report.drift_github([outcome]).splitlines()
    assert len(github) == 2 + report.PROCESSES_SHOWN + 1  # the removed node and its publisher; ten renames; the rest counted
    assert any(f"{hidden} more change(s) of this rule not annotated" in line for line in github)


def test_drift_in_a_few_nodes_is_listed_whole_by_node():
    items = drift_in_many_nodes(report.PROCESSES_SHOWN)
    assert not report.at_scale(items)
    text = report.render_text(items, threshold=Severity.BREAKING)
    assert "[PUB_RENAMED]" in text and "more nodes" not in text
    assert ci_report.drift_github([ContractOutcome("c.yaml", items, Severity.RISKY, [])]).count("\n") == len(items)
