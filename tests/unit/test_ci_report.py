"""The CI formats (``--format markdown`` and ``--format github``) against golden text.

The golden files are in tests/unit/golden_text/; after an intended change of the output,
regenerate them with ``RMWI_REGENERATE_GOLDEN_TEXT=1 pytest tests/unit/test_ci_report.py`` and
review the diff.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from sample_contracts import REPORT_CAPTURED as CAPTURED
from sample_contracts import REPORT_LISTENER as LISTENER
from sample_contracts import REPORT_TALKER as TALKER

from pytest_rmw_introspect.compare import ci_report
from pytest_rmw_introspect.compare.ci_report import ContractOutcome
from pytest_rmw_introspect.compare.compatibility import check_compatibility
from pytest_rmw_introspect.compare.drift import compare
from pytest_rmw_introspect.model.contract import loads
from pytest_rmw_introspect.model.locate import line_index, line_of
from pytest_rmw_introspect.model.vocabulary import Severity

GOLDEN = Path(__file__).parent / "golden_text"

def outcomes() -> list[ContractOutcome]:
    items = compare(loads(TALKER).nodes, CAPTURED)
    return [
        ContractOutcome("contracts/talker.interfaces.yaml", items, Severity.RISKY, ["/talker"], lines=line_index(TALKER)),
        ContractOutcome("contracts/listener.interfaces.yaml", (), Severity.SAFE, ["/listener"]),
        ContractOutcome("contracts/broken.interfaces.yaml",
                        error="contracts/broken.interfaces.yaml:3: nodes./x: not a fully qualified node name\nmore"),
    ]


def compat_items():
    systems = {"contracts/talker.interfaces.yaml": CAPTURED, "contracts/listener.interfaces.yaml": loads(LISTENER).nodes}
    return check_compatibility(systems)


def check_golden(name: str, text: str) -> None:
    path = GOLDEN / name
    if os.environ.get("RMWI_REGENERATE_GOLDEN_TEXT"):
        path.write_text(text, encoding="utf-8")
    assert text == path.read_text(encoding="utf-8"), f"{name} differs from its golden text"


def test_drift_markdown():
    check_golden("drift.md", ci_report.drift_markdown(outcomes()))


def test_drift_github_annotations():
    check_golden("drift.github.txt", ci_report.drift_github(outcomes()))


def test_compat_markdown_and_github():
    items = compat_items()
    labels = ["contracts/talker.interfaces.yaml", "contracts/listener.interfaces.yaml"]
    check_golden("compat.md", ci_report.compat_markdown(items, threshold=Severity.BREAKING, labels=labels))
    lines = {"contracts/listener.interfaces.yaml": line_index(LISTENER)}
    check_golden("compat.github.txt", ci_report.compat_github(items, threshold=Severity.BREAKING, lines=lines))


def test_all_passing_markdown_says_so():
    text = ci_report.drift_markdown([ContractOutcome("a.interfaces.yaml", nodes=["/a"])])
    assert text.startswith("## Interface contracts: all 1 pass\n") and "✅ matches" in text
    assert ci_report.drift_github([ContractOutcome("a.interfaces.yaml", nodes=["/a"])]) == ""


@pytest.mark.parametrize("message, expected", [
    ("a%b", "::error::a%25b"),
    ("two\nlines\r", "::error::two%0Alines%0D"),
])
def test_annotation_data_is_escaped(message, expected):
    assert ci_report.annotation("error", message) == expected


def test_annotation_properties_are_escaped():
    line = ci_report.annotation("warning", "m", file="dir,x/a:b.yaml", line=3, title="T: one, two")
    assert line == "::warning file=dir%2Cx/a%3Ab.yaml,line=3,title=T%3A one%2C two::m"


def test_line_index_of_a_contract():
    index = line_index(TALKER)
    assert line_of(index, "/talker", "publishers", "/status") == 8
    assert line_of(index, "/talker", "service_servers", "/talker/reset") == 11
    assert line_of(index, "/talker", "publishers", "/missing") == 3  # the node's line
    assert line_of(index, "/nobody", "node", "/nobody") is None
    assert line_index("nodes: [unclosed") == {}


def test_parameter_drift_in_markdown_and_github_annotations_on_the_parameter_line():
    text = """contract_version: 1
nodes:
  /cam:
    lifecycle: active
    publishers: []
    parameters:
      - name: rate
        type: double
        default_value: 10.0
"""
    old = loads(text)
    new = {"/cam": {"lifecycle": "inactive", "parameters": [{"name": "rate", "type": "double", "default_value": 5.0}]}}
    items = compare(old.nodes, new)
    outcome = ContractOutcome(contract="cam.interfaces.yaml", items=items, nodes=["/cam"], lines=line_index(text))
    markdown = ci_report.drift_markdown([outcome])
    assert "- `/cam` parameter `rate`: `PARAM_DEFAULT_CHANGED` default value 10.0 -> 5.0" in markdown
    assert "- `/cam`: `LIFECYCLE_STATE_CHANGED` the contract describes /cam active" in markdown
    github = ci_report.drift_github([outcome]).splitlines()
    assert github[0].startswith("::error file=cam.interfaces.yaml,line=3,title=LIFECYCLE_STATE_CHANGED (RISKY)::")
    assert github[1].startswith("::error file=cam.interfaces.yaml,line=7,title=PARAM_DEFAULT_CHANGED (RISKY)::"
                                "/cam parameter rate: default value 10.0 -> 5.0")


@pytest.mark.parametrize(("severity", "threshold", "level"), [
    (Severity.BREAKING, Severity.SAFE, "error"), (Severity.RISKY, Severity.RISKY, "error"),
    (Severity.RISKY, Severity.BREAKING, "warning"),
    # a SAFE finding breaks nothing: never an error, even when --fail-on any fails the check on it
    (Severity.SAFE, Severity.SAFE, "warning"), (Severity.SAFE, Severity.RISKY, "notice"),
])
def test_an_annotations_level_follows_the_findings_severity_and_the_gate(severity, threshold, level):
    assert ci_report.annotation_level(severity, threshold) == level
