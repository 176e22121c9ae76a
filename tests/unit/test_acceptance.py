"""``accept:`` entries of contracts: loading, which findings they accept, stale entries, and how
accepted findings and stale entries are reported (text, JSON, SARIF, the outcome)."""

from __future__ import annotations

import json

import pytest

from pytest_rmw_introspect.check import pipeline
from pytest_rmw_introspect.check.outcome import Verdict, decide
from pytest_rmw_introspect.compare import acceptance, report, sarif
from pytest_rmw_introspect.compare.compatibility import check_compatibility
from pytest_rmw_introspect.compare.drift import compare
from pytest_rmw_introspect.errors import ContractError
from pytest_rmw_introspect.model.acceptance import Acceptance
from pytest_rmw_introspect.model.contract import loads
from pytest_rmw_introspect.model.system_contract import loads as load_system

LISTENER = """\
contract_version: 1
accept:
  - rule: SUBSCRIPTION_WITHOUT_PUBLISHER
    name: /initialpose
    reason: published by rviz, not launched
  - rule: CLIENT_WITHOUT_SERVER
    name: /map_server/load_map
    node: /listener
    reason: the map server runs on the robot only
nodes:
  /listener:
    subscriptions:
      - name: /initialpose
        type: geometry_msgs/msg/PoseWithCovarianceStamped
      - name: /chatter
        type: std_msgs/msg/String
"""


def test_entries_are_read_with_their_lines():
    contract = loads(LISTENER, path="listener.yaml")
    assert contract.accept == (
        Acceptance("SUBSCRIPTION_WITHOUT_PUBLISHER", "published by rviz, not launched", name="/initialpose",
                   source="listener.yaml", line=3),
        Acceptance("CLIENT_WITHOUT_SERVER", "the map server runs on the robot only", name="/map_server/load_map",
                   node="/listener", source="listener.yaml", line=6),
    )
    assert contract.accept[1].where() == "listener.yaml:6"
    assert loads("contract_version: 1\nnodes: {}\n").accept == ()


@pytest.mark.parametrize(("entry", "line", "reason"), [
    ("  - rule: SUB_REMOVED\n", 3, "'reason' is required"),
    ("  - rule: SUB_REMOVED\n    reason: '   '\n", 4, "an accepted finding needs a reason"),
    ("  - rule: sub_removed\n    reason: r\n", 3, "'sub_removed' is not a rule id"),
    ("  - rule: SUB_REMOVED\n    node: listener\n    reason: r\n", 4, "'listener' is not a fully qualified node name"),
    ("  - rule: SUB_REMOVED\n    topic: /x\n    reason: r\n", 4, "unknown key 'topic'"),  # the key's own line
])
def test_bad_entries_name_the_file_line_and_what_to_write(entry, line, reason):
    with pytest.raises(ContractError) as caught:
        loads(f"contract_version: 1\naccept:\n{entry}nodes: {{}}\n", path="c.yaml")
    assert caught.value.line == line
    assert reason in caught.value.reason


def test_a_system_contract_reads_its_entries_too():
    text = ("system_version: 1\nlaunch: {path: robot.launch.xml}\naccept:\n  - rule: DUPLICATE_NODE_NAME\n"
            "    name: /reporter\n    reason: two reporters on purpose\nprocesses: []\nnodes: {}\n")
    (entry,) = load_system(text, path="robot.system.yaml").accept
    assert (entry.rule, entry.name, entry.line) == ("DUPLICATE_NODE_NAME", "/reporter", 4)


def test_an_unknown_rule_is_refused_naming_the_entry():
    (entry,) = loads("contract_version: 1\naccept:\n  - {rule: PUB_RENOVED, reason: typo}\nnodes: {}\n",
                     path="c.yaml").accept
    with pytest.raises(ContractError) as caught:
        acceptance.check_rules([entry])
    assert caught.value.line == 3 and "unknown rule PUB_RENOVED" in str(caught.value)
    assert "docs/drift-rules.md" in str(caught.value)


def system_items():
    talker = {"/talker": {"publishers": [{"name": "/chatter", "type": "std_msgs/msg/String"}]}}
    listener = loads(LISTENER, path="listener.yaml")
    return check_compatibility({"talker.yaml": talker, "listener.yaml": listener.nodes}), listener.accept


def test_entries_accept_the_findings_they_name_and_stale_ones_are_kept_apart():
    items, accept = system_items()
    assert [i.rule for i in items] == ["SUBSCRIPTION_WITHOUT_PUBLISHER"]
    judged = pipeline.judge_compatibility(items, accept)
    assert judged.kept == []
    assert [(a.item.name, a.acceptance.reason) for a in judged.accepted] == [("/initialpose", "published by rviz, not launched")]
    assert [s.rule for s in judged.stale] == ["CLIENT_WITHOUT_SERVER"]  # no client of that name any more


def test_an_entry_accepts_only_what_it_names():
    items, _ = system_items()
    (item,) = items
    entry = Acceptance("SUBSCRIPTION_WITHOUT_PUBLISHER", "r", source="listener.yaml")
    assert acceptance.matches(entry, item)
    assert not acceptance.matches(Acceptance("CLIENT_WITHOUT_SERVER", "r"), item)
    assert not acceptance.matches(Acceptance("SUBSCRIPTION_WITHOUT_PUBLISHER", "r", name="/other"), item)
    assert acceptance.matches(Acceptance("SUBSCRIPTION_WITHOUT_PUBLISHER", "r", node="/listener"), item)
    assert not acceptance.matches(Acceptance("SUBSCRIPTION_WITHOUT_PUBLISHER", "r", node="/talker"), item)
    # an entry of another contract does not accept a problem of this one
    other = Acceptance("SUBSCRIPTION_WITHOUT_PUBLISHER", "r", source="talker.yaml")
    assert pipeline.judge_compatibility(items, [other]).kept == items


def test_stale_entries_are_only_those_of_the_checks_that_ran():
    items, accept = system_items()
    drift_only = acceptance.judge(items, accept, rules=acceptance.DRIFT_RULES)  # a check, not compat
    assert drift_only.stale == []


def drift_judged():
    contract = loads("contract_version: 1\naccept:\n  - rule: PUB_ADDED\n    name: /debug\n    reason: debug output\n"
                     "  - rule: SUB_REMOVED\n    reason: gone long ago\nnodes:\n  /talker: {}\n", path="talker.yaml")
    items = compare(contract.nodes, {"/talker": {"publishers": [{"name": "/debug", "type": "std_msgs/msg/String"}]}})
    return contract, acceptance.judge(items, contract.accept, rules=acceptance.DRIFT_RULES)


def test_the_text_report_lists_accepted_findings_with_reasons_and_stale_entries():
    _, judged = drift_judged()
    text = report.render_text(judged.kept, contract_path="talker.yaml", accepted=judged.accepted, stale=judged.stale)
    assert text == (
        "Interface drift: no drift against talker.yaml.\n"
        "\n"
        "ACCEPTED (1) - accepted on purpose (`accept:` entries, a baseline), not failing\n"
        "  /talker publisher /debug: [PUB_ADDED] new publisher on /debug (std_msgs/msg/String): nothing existing depends on it\n"
        "    accepted (talker.yaml:3): debug output\n"
        "\n"
        "STALE ACCEPTANCES (1) - `accept:` entries that match nothing any more; remove them before they hide a new finding\n"
        "  talker.yaml:6: SUB_REMOVED (reason given: gone long ago)\n"
    )


def test_json_marks_accepted_findings_and_stale_entries():
    _, judged = drift_judged()
    (accepted,) = report.accepted_to_json(judged.accepted)
    assert accepted["rule"] == "PUB_ADDED" and accepted["accepted"]["reason"] == "debug output"
    (stale,) = report.stale_to_json(judged.stale)
    assert stale["rule"] == "ACCEPTANCE_STALE" and stale["accept"]["line"] == 6


def checked(contract, judged) -> pipeline.CheckResult:
    return pipeline.CheckResult(path=contract.path, shown="talker.yaml", contract=contract, items=judged.kept,
                                accepted=judged.accepted, stale=judged.stale)


def test_accepted_drift_passes_and_a_stale_entry_warns():
    contract, judged = drift_judged()
    warned = decide(checked(contract, judged), update=False)
    assert warned.verdict is Verdict.WARN and not warned.failed
    assert "1 finding(s) accepted" in warned.message and "SUB_REMOVED" in warned.message
    assert "remove them" in warned.message
    judged.stale = []
    passed = decide(checked(contract, judged), update=False)
    assert passed.verdict is Verdict.PASS
    assert passed.message == "talker.yaml: matches (/talker); 1 finding(s) accepted in the contract"
    assert passed.json[0]["accepted"]["reason"] == "debug output"


def test_sarif_shows_accepted_findings_as_suppressed_and_stale_entries_as_results():
    contract, judged = drift_judged()
    outcome = checked(contract, judged).for_ci()
    results = json.loads(json.dumps(sarif.drift_log([outcome])))["runs"][0]["results"]
    accepted = next(r for r in results if r["ruleId"] == "PUB_ADDED")
    assert accepted["suppressions"] == [{
        "kind": "inSource", "status": "accepted", "justification": "debug output",
        "location": {"physicalLocation": {"artifactLocation": {"uri": "talker.yaml", "uriBaseId": "%SRCROOT%"},
                                          "region": {"startLine": 3}}}}]
    stale = next(r for r in results if r["ruleId"] == sarif.ACCEPTANCE_STALE)
    assert stale["level"] == "warning"
    assert stale["locations"][0]["physicalLocation"]["region"] == {"startLine": 6}


def test_compat_of_contract_files_applies_their_entries(tmp_path):
    (tmp_path / "listener.yaml").write_text(LISTENER)
    (tmp_path / "talker.yaml").write_text("contract_version: 1\nnodes:\n  /talker:\n    publishers:\n"
                                          "      - {name: /chatter, type: std_msgs/msg/String}\n")
    result = pipeline.check_compatibility([tmp_path / "talker.yaml", tmp_path / "listener.yaml"], fail_on="risky")
    assert result.items == [] and not result.failed
    assert [a.item.rule for a in result.accepted] == ["SUBSCRIPTION_WITHOUT_PUBLISHER"]
    assert [s.rule for s in result.stale] == ["CLIENT_WITHOUT_SERVER"]
    assert "ACCEPTED (1)" in result.render_text() and "STALE ACCEPTANCES (1)" in result.render_text()


def test_updating_a_contract_keeps_its_entries():
    from pytest_rmw_introspect.model.contract import update_text

    for text in (LISTENER, LISTENER.replace("accept:", "x_accept:", 1)):  # before nodes; and a sanity probe
        updated = update_text(text, {"/listener": {"subscriptions": []}})
        assert updated.split("nodes:")[0] == text.split("nodes:")[0]


def test_the_ci_formats_show_accepted_findings_and_stale_entries():
    from pytest_rmw_introspect.compare import ci_report

    contract, judged = drift_judged()
    outcome = checked(contract, judged).for_ci()
    github = ci_report.drift_github([outcome]).splitlines()
    assert github == [
        "::notice file=talker.yaml,line=3,title=PUB_ADDED accepted::new publisher on /debug (std_msgs/msg/String): "
        "nothing existing depends on it (accepted: debug output)",
        "::warning file=talker.yaml,line=6,title=ACCEPTANCE_STALE::`accept:` entry SUB_REMOVED matches nothing any "
        "more; remove it",
    ]
    markdown = ci_report.drift_markdown([outcome])
    assert "Accepted on purpose (1, not failing):" in markdown and "debug output" in markdown
    assert "- `talker.yaml:6`: SUB_REMOVED" in markdown
