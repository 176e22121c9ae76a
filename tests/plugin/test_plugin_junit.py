"""JUnit XML: one test case per contract file with the drift report as the failure message, and
the machine-readable drift as the `rmw_introspect_drift` property (contract items and marker
tests alike)."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET

from sample_contracts import talker_contract, talker_depth_drift


def talker(script: str, *, depth: int = 10, target: bool = True) -> str:
    """The publisher of nodes/talker.py (``script``) alone, with or without a target block."""
    return talker_contract(target=f"script: {script}" if target else None, depth=depth, complete=False)


def cases(path) -> dict[str, ET.Element]:
    root = ET.parse(path).getroot()
    return {f"{c.get('classname')}::{c.get('name')}": c for c in root.iter("testcase")}


def drift_property(case: ET.Element) -> list[dict] | None:
    values = [p.get("value") for p in case.iter("property") if p.get("name") == "rmw_introspect_drift"]
    assert len(values) <= 1
    return json.loads(values[0]) if values else None


def test_junit_has_one_case_per_contract_with_the_report_and_the_drift_items(project):
    script = project.node("talker.py")
    project.write("contracts/ok.interfaces.yaml", talker(script))
    project.write("contracts/drifted.interfaces.yaml", talker(script, depth=3))
    project.write("contracts/notarget.interfaces.yaml", talker(script, target=False))
    result = project.run("--junitxml=report.xml")
    result.assert_outcomes(passed=1, failed=2)

    found = cases(project.path / "report.xml")
    assert sorted(found) == [
        "contracts.drifted.interfaces.yaml::/talker",
        "contracts.notarget.interfaces.yaml::/talker",
        "contracts.ok.interfaces.yaml::/talker",
    ]

    ok = found["contracts.ok.interfaces.yaml::/talker"]
    assert ok.find("failure") is None
    assert drift_property(ok) is None

    drifted = found["contracts.drifted.interfaces.yaml::/talker"]
    failure = drifted.find("failure")
    assert failure is not None
    message = failure.get("message")
    assert "Interface drift of script" in message
    assert "against contracts/drifted.interfaces.yaml: 1 change (0 breaking, 0 risky, 1 safe)" in message
    assert "[QOS_DEPTH_INCREASED] depth 3 -> 10" in message
    assert "pytest --update-golden contracts/drifted.interfaces.yaml::/talker" in message
    assert "Traceback" not in failure.text
    assert drift_property(drifted) == [talker_depth_drift("contracts/drifted.interfaces.yaml")]

    notarget = found["contracts.notarget.interfaces.yaml::/talker"].find("failure")
    assert "has no `target:` block" in notarget.get("message")


def test_marker_tests_attach_the_drift_items_too(project):
    script = project.node("talker.py")
    project.write("contracts/talker.yaml", talker(script, depth=3, target=False))
    project.write("contracts/same.yaml", talker(script, target=False))
    project.test(f"""
        @pytest.mark.interfaces("contracts/talker.yaml", script={script!r}, fail_on="breaking")
        def test_below_threshold(interfaces):
            pass

        @pytest.mark.interfaces("contracts/talker.yaml", script={script!r})
        def test_drift(interfaces):
            pass

        @pytest.mark.interfaces("contracts/same.yaml", script={script!r})
        def test_match(interfaces):
            pass
    """)
    result = project.run("--junitxml=report.xml")
    result.assert_outcomes(passed=2, failed=1, skipped=2, warnings=1)
    found = cases(project.path / "report.xml")

    match = found["test_nodes::test_match"]
    assert match.find("failure") is None
    assert drift_property(match) is None

    for name in ("test_nodes::test_drift", "test_nodes::test_below_threshold"):
        items = drift_property(found[name])
        assert [(i["contract"], i["rule"], i["severity"], i["old"], i["new"]) for i in items] == [
            ("contracts/talker.yaml", "QOS_DEPTH_INCREASED", "SAFE", 3, 10)
        ], name

    failure = found["test_nodes::test_drift"].find("failure")
    assert "[QOS_DEPTH_INCREASED] depth 3 -> 10" in failure.text
    assert "pytest --update-golden test_nodes.py::test_drift" in failure.text
    assert found["test_nodes::test_below_threshold"].find("failure") is None


def test_a_marker_sets_a_rule_s_level_and_the_junit_property_says_so(project):
    """Issue 49: the marker keyword `rules`; the finding it made a note passes and is kept, with
    its level and who set it, in the JUnit property."""
    script = project.node("talker.py")
    project.write("contracts/talker.yaml", talker(script, depth=3, target=False))
    project.test(f"""
        @pytest.mark.interfaces("contracts/talker.yaml", script={script!r}, rules={{"QOS_DEPTH_*": "note"}})
        def test_noted(interfaces):
            pass
    """)
    result = project.run("--junitxml=report.xml")
    result.assert_outcomes(passed=1, skipped=1)  # (the contract file itself has no target: skipped)
    [item] = drift_property(cases(project.path / "report.xml")["test_nodes::test_noted"])
    assert (item["rule"], item["severity"]) == ("QOS_DEPTH_INCREASED", "NOTE")
    assert item["level_set_by"].startswith("set by rules `QOS_DEPTH_*`: in "), item
    # the note is said in the session's summary too
    result.stdout.fnmatch_lines(["*rmw-introspect: notes*",
                                 "contracts/talker.yaml: [[]QOS_DEPTH_INCREASED] depth 3 -> 10*"])
