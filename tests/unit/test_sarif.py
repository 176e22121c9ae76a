"""``--format sarif``: SARIF 2.1.0 logs of drift, system problems and invalid contracts.

The logs are validated against the official SARIF 2.1.0 JSON schema as Microsoft's SARIF SDK
ships it (the npm package ``@microsoft/jest-sarif``, ``lib/schemas/sarif-2.1.0-rtm.5.json``;
``scripts/install-test-tools.sh`` installs it) or the file named by ``RMWI_SARIF_SCHEMA``;
without either, the schema test is skipped, saying so. The schema is never copied into this
repository.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest
from sample_contracts import REPORT_CAPTURED as CAPTURED
from sample_contracts import REPORT_LISTENER as LISTENER
from sample_contracts import REPORT_TALKER as TALKER

from pytest_rmw_introspect.compare import compatibility, drift, sarif
from pytest_rmw_introspect.compare.ci_report import ContractOutcome
from pytest_rmw_introspect.compare.compatibility import check_compatibility
from pytest_rmw_introspect.compare.drift import compare
from pytest_rmw_introspect.model.contract import loads
from pytest_rmw_introspect.model.locate import line_index
from pytest_rmw_introspect.model.vocabulary import Severity

SCHEMA_FILE = Path("@microsoft", "jest-sarif", "lib", "schemas", "sarif-2.1.0-rtm.5.json")


def _official_schema() -> Path | None:
    given = os.environ.get("RMWI_SARIF_SCHEMA")
    if given:
        return Path(given)
    npm = shutil.which("npm")
    if npm is None:
        return None
    root = subprocess.run([npm, "root", "-g"], capture_output=True, text=True, timeout=60).stdout.strip()
    candidate = Path(root) / SCHEMA_FILE
    return candidate if candidate.is_file() else None


@pytest.fixture(scope="module")
def sarif_validator():
    path = _official_schema()
    if path is None:
        pytest.skip("the official SARIF 2.1.0 schema is not installed: `npm install -g @microsoft/jest-sarif` "
                    "(scripts/install-test-tools.sh does it) or set RMWI_SARIF_SCHEMA to the schema file")
    import jsonschema

    schema = json.loads(path.read_text(encoding="utf-8"))
    assert "SARIF" in schema["title"] and "2.1.0" in schema["title"], path
    validator_class = jsonschema.validators.validator_for(schema)
    return validator_class(schema, format_checker=validator_class.FORMAT_CHECKER)


TALKER_FILE = "contracts/talker.interfaces.yaml"


def talker_outcome(threshold: Severity = Severity.RISKY) -> ContractOutcome:
    items = compare(loads(TALKER).nodes, CAPTURED)
    return ContractOutcome(TALKER_FILE, items, threshold, ["/talker"], lines=line_index(TALKER))


def compat_items():
    return check_compatibility({"contracts/talker.interfaces.yaml": CAPTURED,
                               "contracts/listener.interfaces.yaml": loads(LISTENER).nodes})


def logs() -> dict[str, dict]:
    broken = ContractOutcome("contracts/broken.interfaces.yaml", error="contracts/broken.interfaces.yaml:3: bad\nmore")
    return {
        "drift": sarif.drift_log([talker_outcome(), broken]),
        "empty": sarif.drift_log([]),
        "compat": sarif.compat_log(compat_items(), threshold=Severity.BREAKING,
                                   lines={"contracts/listener.interfaces.yaml": line_index(LISTENER)}),
        "invalid": sarif.invalid_log([("a b/bad.yaml", 4, "not a mapping"), ("/abs/other.yaml", None, "empty")]),
    }


@pytest.mark.parametrize("name", ["drift", "empty", "compat", "invalid"])
def test_every_log_is_valid_against_the_official_sarif_schema(name, sarif_validator):
    document = json.loads(json.dumps(logs()[name]))  # what the command prints
    errors = sorted(sarif_validator.iter_errors(document), key=lambda e: list(e.path))
    assert not errors, "\n".join(f"{list(e.path)}: {e.message}" for e in errors)


def test_the_schema_check_rejects_a_broken_log(sarif_validator):
    document = logs()["drift"]
    document["runs"][0]["results"][0]["level"] = "fatal"  # not a SARIF level
    del document["runs"][0]["tool"]["driver"]["name"]
    assert len(list(sarif_validator.iter_errors(document))) == 2


def test_the_rules_are_every_documented_rule_with_description_and_default_level():
    rules = logs()["drift"]["runs"][0]["tool"]["driver"]["rules"]
    by_id = {rule["id"]: rule for rule in rules}
    assert set(by_id) == set(drift.RULES) | set(compatibility.RULES) | set(sarif.TOOL_RULES)
    assert by_id["PUB_REMOVED"]["defaultConfiguration"] == {"level": "error"}
    assert by_id["PUB_REMOVED"]["shortDescription"]["text"] == "publisher removed"
    assert by_id["SUB_ADDED"]["defaultConfiguration"] == {"level": "warning"}
    assert by_id["PUB_ADDED"]["defaultConfiguration"] == {"level": "note"}
    assert by_id["SUBSCRIPTION_WITHOUT_PUBLISHER"]["shortDescription"]["text"] == "nobody publishes a subscribed topic"
    assert all(rule["shortDescription"]["text"] and rule["properties"]["severity"] in {"BREAKING", "RISKY", "SAFE", "NOTE"}
               for rule in rules)


def test_one_result_per_drift_item_on_its_contract_line():
    outcome = talker_outcome()
    run = sarif.drift_log([outcome])["runs"][0]
    results = run["results"]
    assert len(results) == len(outcome.items) > 0
    rules = run["tool"]["driver"]["rules"]
    for item, result in zip(outcome.items, results, strict=True):
        assert result["ruleId"] == item.rule == rules[result["ruleIndex"]]["id"]
        assert item.message in result["message"]["text"]
    by_rule = {r["ruleId"]: r for r in results}
    added = by_rule["PUB_ADDED"]  # /extra: not in the contract, so on its node's line
    assert added["locations"][0]["physicalLocation"] == {
        "artifactLocation": {"uri": TALKER_FILE, "uriBaseId": "%SRCROOT%"}, "region": {"startLine": 3}}
    assert added["level"] == "note"  # SAFE below the threshold RISKY
    weakened = by_rule["QOS_RELIABILITY_WEAKENED"]  # /chatter is listed on line 5
    assert weakened["locations"][0]["physicalLocation"]["region"] == {"startLine": 5}
    assert weakened["locations"][0]["logicalLocations"] == [{"fullyQualifiedName": "/talker/publishers//chatter"}]
    assert weakened["level"] == "error"
    assert by_rule["QOS_DEPTH_DECREASED"]["level"] == "error"  # RISKY at the threshold


def test_result_levels_follow_the_fail_threshold():
    assert [sarif.level(s, Severity.BREAKING) for s in (Severity.BREAKING, Severity.RISKY, Severity.SAFE)] == \
        ["error", "warning", "note"]
    assert [sarif.level(s, Severity.SAFE) for s in (Severity.BREAKING, Severity.RISKY, Severity.SAFE)] == \
        ["error", "error", "error"]


def test_fingerprints_are_stable_and_tell_findings_apart():
    first = [r["partialFingerprints"][sarif.FINGERPRINT] for r in sarif.drift_log([talker_outcome()])["runs"][0]["results"]]
    again = [r["partialFingerprints"][sarif.FINGERPRINT]
             for r in sarif.drift_log([talker_outcome(Severity.SAFE)])["runs"][0]["results"]]
    assert first == again  # the threshold changes levels, not identities
    assert len(set(first)) == len(first)


def test_a_contract_that_could_not_be_checked_is_an_error_result_and_an_unsuccessful_run():
    run = logs()["drift"]["runs"][0]
    errors = [r for r in run["results"] if r["ruleId"] == sarif.CONTRACT_NOT_CHECKED]
    assert len(errors) == 1
    assert errors[0]["level"] == "error"
    assert errors[0]["message"]["text"] == "contracts/broken.interfaces.yaml:3: bad\nmore"
    assert errors[0]["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] == "contracts/broken.interfaces.yaml"
    assert run["invocations"] == [{"executionSuccessful": False}]
    assert logs()["empty"]["runs"][0]["invocations"] == [{"executionSuccessful": True}]


def test_system_problems_point_at_the_requesting_contract():
    results = logs()["compat"]["runs"][0]["results"]
    assert {r["ruleId"] for r in results} == {i.rule for i in compat_items()}
    missing = next(r for r in results if r["ruleId"] == "CLIENT_WITHOUT_SERVER")  # the /talker/reset client
    location = missing["locations"][0]["physicalLocation"]
    assert location["artifactLocation"]["uri"] == "contracts/listener.interfaces.yaml"
    assert location["region"] == {"startLine": 9}
    assert missing["level"] == "warning"  # RISKY below the threshold BREAKING


def test_invalid_files_are_results_with_uris_encoded_and_absolute_paths_as_file_uris():
    results = logs()["invalid"]["runs"][0]["results"]
    assert [r["ruleId"] for r in results] == [sarif.CONTRACT_INVALID] * 2
    assert results[0]["locations"][0]["physicalLocation"] == {
        "artifactLocation": {"uri": "a%20b/bad.yaml", "uriBaseId": "%SRCROOT%"}, "region": {"startLine": 4}}
    assert results[1]["locations"][0]["physicalLocation"] == {"artifactLocation": {"uri": "file:///abs/other.yaml"}}


def test_system_problems_of_a_launched_system_point_at_the_launch_file_too(sarif_validator):
    from pytest_rmw_introspect.compare.compatibility import LaunchedProcess, check_launched

    talker = {"/robot/reporter": {"publishers": []}}
    processes = [LaunchedProcess("demo/talker", None, talker, where="launch/robot.launch.xml:7"),
                 LaunchedProcess("demo/talker #2", None, talker, where="launch/robot.launch.xml:9")]
    items = check_launched(processes)
    outcome = ContractOutcome("robot.system.yaml", system_items=items,
                              launched_at={p.label: p.where for p in processes if p.where})
    document = json.loads(json.dumps(sarif.drift_log([outcome])))
    assert not list(sarif_validator.iter_errors(document))
    (duplicate,) = document["runs"][0]["results"]
    assert duplicate["ruleId"] == "DUPLICATE_NODE_NAME"
    assert duplicate["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] == "robot.system.yaml"
    assert [(r["physicalLocation"]["artifactLocation"]["uri"], r["physicalLocation"]["region"]["startLine"])
            for r in duplicate["relatedLocations"]] == [("launch/robot.launch.xml", 9), ("launch/robot.launch.xml", 7)]
    assert "the launch file starts demo/talker #2 here" in duplicate["relatedLocations"][0]["message"]["text"]
