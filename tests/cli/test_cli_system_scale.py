"""A system of 150 processes (issue 42): `check` of its contract starts them warm like
`capture --launch` does, and a passing check says how many nodes in how many processes matched
(their names with -v), not 150 names on one line."""

from __future__ import annotations

import json

from sample_systems import many_processes, node_names

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
