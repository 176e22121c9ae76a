"""Baselines: today's findings written to a file, a later run failing only on new ones."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from pytest_rmw_introspect.check import baselines, pipeline
from pytest_rmw_introspect.check.outcome import Verdict, decide
from pytest_rmw_introspect.compare import baseline
from pytest_rmw_introspect.compare.compatibility import check_compatibility
from pytest_rmw_introspect.compare.drift import compare
from pytest_rmw_introspect.errors import BaselineError
from pytest_rmw_introspect.model.contract import loads
from pytest_rmw_introspect.model.vocabulary import Severity

CONTRACT = "contract_version: 1\nnodes:\n  /talker:\n    publishers:\n      - {name: /chatter, type: std_msgs/msg/String}\n"


def drifted(contract_path: Path, *extra: str) -> pipeline.CheckResult:
    """A check of ``contract_path`` whose capture adds the publishers ``extra``."""
    contract = loads(CONTRACT, path=contract_path)
    actual = {"/talker": {"publishers": [{"name": n, "type": "std_msgs/msg/String"} for n in ("/chatter", *extra)]}}
    return pipeline.CheckResult(path=contract_path, shown=str(contract_path), contract=contract,
                                items=compare(contract.nodes, actual))


def test_a_written_baseline_accepts_exactly_the_findings_it_recorded(tmp_path):
    contract_path = tmp_path / "contracts" / "talker.yaml"
    file = tmp_path / "interfaces.baseline.json"
    file.write_text(baseline.render(baselines.findings([drifted(contract_path, "/debug")]), file))
    loaded = baseline.load(file)
    known = drifted(contract_path, "/debug")
    baselines.apply(known, loaded)
    assert known.items == [] and [a.item.name for a in known.accepted] == ["/debug"]
    assert decide(known, update=False).verdict is Verdict.PASS
    assert decide(known, update=False).message.endswith("matches (/talker); 1 finding(s) in the baseline")
    assert loaded.fixed() == []
    new = drifted(contract_path, "/debug", "/new")
    baselines.apply(new, baseline.load(file))
    assert [i.name for i in new.items] == ["/new"] and [a.item.name for a in new.accepted] == ["/debug"]
    outcome = decide(new, update=False)
    assert outcome.verdict is Verdict.FAIL
    assert "ACCEPTED (1)" in outcome.message and "in the baseline" in outcome.message


def test_findings_that_are_gone_are_counted_so_the_baseline_can_be_tightened(tmp_path):
    contract_path = tmp_path / "talker.yaml"
    file = tmp_path / "b.json"
    file.write_text(baseline.render(baselines.findings([drifted(contract_path, "/debug")]), file))
    loaded = baseline.load(file, "b.json")
    baselines.apply(drifted(contract_path), loaded)
    assert [e["rule"] for e in loaded.fixed()] == ["PUB_ADDED"]
    assert loaded.fixed_note([contract_path]) == ("1 finding(s) of the baseline b.json are gone; write it again "
                                                  "(--write-baseline b.json) to tighten it")
    assert loaded.fixed_note([tmp_path / "other.yaml"]) is None  # a run that did not check that contract


def test_contracts_are_keyed_relative_to_the_baseline_so_any_working_directory_agrees(tmp_path, monkeypatch):
    (tmp_path / "contracts").mkdir()
    file = tmp_path / "b.json"
    monkeypatch.chdir(tmp_path)
    file.write_text(baseline.render(baselines.findings([drifted(Path("contracts/talker.yaml"), "/debug")]), file))
    assert json.loads(file.read_text())["findings"][0]["contract"] == "contracts/talker.yaml"
    monkeypatch.chdir(tmp_path / "contracts")
    result = drifted(Path("talker.yaml"), "/debug")
    baselines.apply(result, baseline.load(os.path.relpath(file)))
    assert result.items == []


def test_writing_the_same_findings_again_changes_no_byte(tmp_path):
    file = tmp_path / "b.json"
    results = [drifted(tmp_path / "a.yaml", "/x", "/y"), drifted(tmp_path / "b.yaml", "/z")]
    first = baseline.render(baselines.findings(results), file)
    assert baseline.render(baselines.findings(list(reversed(results))), file) == first
    assert [f["contract"] for f in json.loads(first)["findings"]] == ["a.yaml", "a.yaml", "b.yaml"]


def test_system_problems_go_through_a_baseline_too(tmp_path):
    listener = {"/listener": {"subscriptions": [{"name": "/orders", "type": "std_msgs/msg/String"}]}}
    items = check_compatibility({"listener.yaml": listener})
    result = pipeline.CompatibilityResult(labels=["listener.yaml"], items=items, threshold=Severity.RISKY)
    file = tmp_path / "b.json"
    file.write_text(baseline.render(baselines.findings([result]), file))
    again = pipeline.CompatibilityResult(labels=["listener.yaml"], items=list(items), threshold=Severity.RISKY)
    baselines.apply(again, baseline.load(file))
    assert again.items == [] and not again.failed
    assert [a.item.rule for a in again.accepted] == ["SUBSCRIPTION_WITHOUT_PUBLISHER"]


@pytest.mark.parametrize(("text", "reason"), [
    (None, "the file does not exist"),
    ("{not json", "not a readable JSON file"),
    ('{"format": "sarif"}', 'not a baseline (it needs "format": "rmw_introspect_baseline")'),
    ('{"format": "rmw_introspect_baseline", "version": 7}', "version 7 is not supported"),
    ('{"format": "rmw_introspect_baseline", "version": 1, "findings": [{"key": "x"}]}',
     'findings[0] has no "key" list of strings'),
])
def test_a_bad_baseline_names_the_file_and_what_to_do(tmp_path, text, reason):
    file = tmp_path / "b.json"
    if text is not None:
        file.write_text(text)
    with pytest.raises(BaselineError) as caught:
        baseline.load(file, "b.json")
    assert caught.value.reason.startswith(reason)
    assert str(caught.value).startswith("baseline b.json: ") and "--write-baseline b.json" in str(caught.value)
