"""The precision suite: correct systems modelled on public robot bring-ups (tests/precision/systems,
described in precision_suite.py) pass the default system gate with no finding, and each of their
seeded bugs fails it, named by the rule that should name it. What every system and bug came to
is recorded in results.json, from which docs/drift-rules.md's precision table is written
(`make precision-table`): a test here fails when a run differs from the record, so the table
cannot go stale silently."""

from __future__ import annotations

import os
import shutil
from pathlib import Path
from typing import Any

import precision_suite as suite
import pytest

SYSTEMS = {system.name: system for system in suite.systems()}
RECORDED = (suite.load_results().get("systems") or {})
STALE = "the recorded results differ: run `make precision-table` and review the change of docs/drift-rules.md"


@pytest.fixture(scope="session")
def environment(middleware_library: Path) -> dict[str, str]:
    return dict(os.environ, RMW_INTROSPECT_LIBRARY=str(middleware_library))


@pytest.fixture(scope="module", params=sorted(SYSTEMS))
def correct(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory,
            environment: dict[str, str]) -> dict[str, Any]:
    """A correct system installed, its contract written by `capture --launch` with its outside world
    declared, and checked (once per system and test process)."""
    system = SYSTEMS[request.param]
    workdir = tmp_path_factory.mktemp(system.name)
    prefix = suite.install(system, workdir / "prefix")
    contract = suite.capture_contract(system, prefix, workdir, environment)
    run, findings = suite.check(contract, prefix, environment)
    return {"system": system, "prefix": prefix, "contract": contract, "run": run, "findings": findings}


def test_the_correct_system_passes_the_default_gate_with_no_finding(correct):
    system, run, findings = correct["system"], correct["run"], correct["findings"]
    assert run.returncode == 0 and findings == [], f"{system.name}: {run}"
    assert run.stdout.strip() == "[]", run
    assert RECORDED.get(system.name, {}).get("correct") == [], STALE


@pytest.mark.parametrize("kind", list(suite.MUTATION_KINDS))
def test_each_seeded_bug_fails_the_default_gate_naming_it(correct, kind, tmp_path, environment):
    system = correct["system"]
    mutation = system.mutations[kind]
    mutant = tmp_path / "prefix"
    shutil.copytree(correct["prefix"], mutant, symlinks=True)
    suite.mutate(system, mutant, mutation)
    run, findings = suite.check(correct["contract"], mutant, environment)
    failing = {f.rule for f in findings if f.system and f.severity == suite.FAILING}
    assert run.returncode == 1 and set(mutation.expect) <= failing, f"{system.name} / {kind}: {run}"
    recorded = RECORDED.get(system.name, {}).get("mutations", {}).get(kind)
    assert recorded == {"expect": sorted(mutation.expect),
                        "found": suite.observed(findings, system_only=True)}, STALE


def test_every_system_seeds_every_kind_of_bug_where_it_applies(tmp_path):
    """Every system has each kind of seeded bug, each applies to its installed files (text found
    exactly once, the deleted file installed), and every system is in the record."""
    assert len(SYSTEMS) >= 12
    for system in SYSTEMS.values():
        assert set(system.mutations) == set(suite.MUTATION_KINDS), system.name
        prefix = suite.install(system, tmp_path / system.name)
        for mutation in system.mutations.values():
            assert mutation.expect, f"{system.name} / {mutation.kind} names no rule"
            suite.mutate(system, prefix, mutation)
    assert set(RECORDED) == set(SYSTEMS), STALE
