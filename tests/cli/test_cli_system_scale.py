"""A system of 150 processes (issue 42): `check` of its contract starts them warm like
`capture --launch` does, and a passing check says how many nodes in how many processes matched
(their names with -v), not 150 names on one line; a failing one, every node drifted, groups the
changes by rule and node and cuts the long lists in text, Markdown and GitHub annotations (JSON
lists them all)."""

from __future__ import annotations

import json

from sample_systems import many_processes, node_names

from pytest_rmw_introspect.compare import report

PROCESSES = 150


def test_a_150_process_system_checks_and_reads_at_scale(cli):
    cli.write("big.launch.xml", many_processes(PROCESSES))
    created = cli("capture", "--launch", "big.launch.xml", "-o", "big.system.yaml", timeout=600)
    assert created.returncode == 0, created
    checked = cli("check", "big.system.yaml", timeout=600)
    assert checked.returncode == 0, checked
    assert checked.stdout == f"big.system.yaml: matches ({PROCESSES} nodes in {PROCESSES} processes)\n", checked
    named = cli("check", "--verbose", "big.system.yaml", timeout=600)
    assert named.stdout == (f"big.system.yaml: matches ({PROCESSES} nodes in {PROCESSES} processes: "
                            f"{', '.join(node_names(PROCESSES))})\n"), named
    as_json = cli("check", "big.system.yaml", "--format", "json", timeout=600)
    assert as_json.returncode == 0 and json.loads(as_json.stdout) == [], as_json  # no finding

    # every node's topic renamed in the golden: 150 nodes drift, and the report still reads at scale
    cli.write("big.system.yaml", cli.read("big.system.yaml").replace("/chatter", "/chat"))
    drifted = cli("check", "big.system.yaml", "--summary", "summary.md", timeout=600)
    assert drifted.returncode == 1, drifted
    lines = drifted.stdout.splitlines()
    assert f"changes in {PROCESSES} nodes (" in lines[0], lines[0]
    rule_lines = [line for line in lines if line.startswith("  [")]
    assert rule_lines and all(f"in {PROCESSES // 2} nodes" in line or f"in {PROCESSES} nodes" in line
                              for line in rule_lines), rule_lines
    assert any(line.startswith("    ... and ") and line.endswith("more nodes (all of them: --format json)")
               for line in lines), drifted.stdout
    # per rule its first nodes (a name and a change each) and a count; not 150 nodes' worth
    screenful = (2 * report.PROCESSES_SHOWN + 3) * len(rule_lines) + 12
    assert len(lines) <= screenful, drifted.stdout
    markdown = cli.read("summary.md")  # the pull-request comment, cut the same way
    assert "more nodes (all of them: --format json)" in markdown
    assert len(markdown.splitlines()) <= screenful, markdown
    github = cli("check", "big.system.yaml", "--format", "github", timeout=600)
    assert github.returncode == 1, github
    annotations = github.stdout.splitlines()
    assert len(annotations) <= (report.PROCESSES_SHOWN * report.FINDINGS_SHOWN + 1) * len(rule_lines), github.stdout
    assert any("more change(s) of this rule not annotated" in line for line in annotations), github.stdout
    everything = cli("check", "big.system.yaml", "--format", "json", timeout=600)
    assert len({item["node"] for item in json.loads(everything.stdout)}) == PROCESSES  # JSON lists all
