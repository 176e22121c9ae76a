"""JUnit XML of a report (``--format junit``, ``compare.junit``): what fails a test case, what is
only said, and XML that a CI system's parser reads (the commands' output is compared with these
writers in tests/unit/test_report_formats.py)."""

from __future__ import annotations

import xml.etree.ElementTree as ET

from pytest_rmw_introspect.compare import junit
from pytest_rmw_introspect.compare.acceptance import Accepted
from pytest_rmw_introspect.compare.ci_report import ContractOutcome
from pytest_rmw_introspect.compare.compatibility import CompatItem, ContractEndpoint
from pytest_rmw_introspect.compare.drift import DriftItem
from pytest_rmw_introspect.model.acceptance import Acceptance
from pytest_rmw_introspect.model.vocabulary import Severity


def _item(rule: str, severity: Severity, message: str = "changed") -> DriftItem:
    return DriftItem(node="/talker", kind="publishers", name="/chatter", change="qos.depth", old=10, new=5,
                     rule=rule, severity=severity, message=message)


def _cases(xml: str) -> dict[str, ET.Element]:
    return {case.get("name"): case for case in ET.fromstring(xml).iter("testcase")}


def test_findings_at_the_threshold_fail_their_contract_and_the_rest_are_properties():
    accepted = Accepted(_item("PUB_REMOVED", Severity.BREAKING), Acceptance(rule="PUB_REMOVED", reason="moved"))
    xml = junit.drift_junit([
        ContractOutcome("a.yaml", items=[_item("QOS_DEPTH_CHANGED", Severity.RISKY, "depth 10 -> 5 <&>"),
                                         _item("REMAP_UNUSED", Severity.NOTE)], threshold=Severity.RISKY),
        ContractOutcome("b.yaml", items=[_item("QOS_DEPTH_CHANGED", Severity.RISKY)], threshold=Severity.BREAKING,
                        accepted=[accepted], stale=[Acceptance(rule="NODE_ADDED", reason="old")]),
        ContractOutcome("c.yaml", error="c.yaml: no such file\n  create it"),
        ContractOutcome("d.yaml", items=[_item("QOS_DEPTH_CHANGED", Severity.BREAKING)], written="updated"),
    ])
    suites = ET.fromstring(xml)
    assert (suites.get("tests"), suites.get("failures"), suites.get("errors")) == ("4", "1", "1")
    cases = _cases(xml)
    failure = cases["a.yaml"].find("failure")
    assert failure.get("message") == "1 finding at or above the threshold (fail on: risky)"
    assert failure.text == "[QOS_DEPTH_CHANGED] RISKY /talker publishers /chatter: depth 10 -> 5 <&>"
    assert [p.get("value") for p in cases["a.yaml"].iter("property")] == [
        "[REMAP_UNUSED] NOTE /talker publishers /chatter: changed"]
    assert cases["b.yaml"].find("failure") is None
    said = {p.get("name"): p.get("value") for p in cases["b.yaml"].iter("property")}
    assert said["rmw_introspect_accepted"] == "[PUB_REMOVED] changed (accepted: moved)"
    assert "matches nothing" in said["rmw_introspect_note"]
    error = cases["c.yaml"].find("error")
    assert error.get("message") == "c.yaml: no such file" and "create it" in error.text
    assert cases["d.yaml"].find("failure") is None  # the update wrote it


def test_compat_has_a_test_case_per_contract_file_and_a_problem_fails_the_requesting_end():
    requester = ContractEndpoint("listener.yaml", "/listener", "subscriptions")
    provider = ContractEndpoint("talker.yaml", "/talker", "publishers")
    item = CompatItem("QOS_INCOMPATIBLE", Severity.BREAKING, "/chatter", requester, provider, "best effort")
    cases = _cases(junit.compat_junit([item], threshold=Severity.BREAKING, labels=["talker.yaml", "listener.yaml"]))
    assert cases["talker.yaml"].find("failure") is None
    assert "QOS_INCOMPATIBLE" in cases["listener.yaml"].find("failure").text
