"""The precision suite: correct systems modelled on public robot bring-ups (tests/precision/systems,
described in precision_suite.py) pass the default system gate with no finding, and each of their
seeded bugs fails it, named by the rule that should name it. What every system and bug came to
is recorded in results.json, from which docs/drift-rules.md's precision table is written
(`make precision-table`): a test here fails when a run differs from the record, so the table
cannot go stale silently."""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path
from typing import Any

import precision_suite as suite
import pytest
from cli_process import Result
from filelock import FileLock

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
    declared, and checked: once per run, shared by the xdist workers (the first one to need a
    system captures it under a file lock, the others read what it left)."""
    system = SYSTEMS[request.param]
    shared = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        shared = shared.parent
    workdir = shared / f"precision-{system.name}"
    with FileLock(str(workdir) + ".lock"):
        done = workdir / "check.json"
        if not done.is_file():
            workdir.mkdir(exist_ok=True)
            prefix = suite.install(system, workdir / "prefix")
            contract = suite.capture_contract(system, prefix, workdir, environment)
            run, _ = suite.check(contract, prefix, environment)
            done.write_text(json.dumps(vars(run)), encoding="utf-8")
    run = Result(**json.loads(done.read_text(encoding="utf-8")))
    return {"system": system, "prefix": workdir / "prefix", "contract": workdir / suite.CONTRACT, "run": run,
            "findings": suite.findings(run)}


def test_the_correct_system_passes_the_default_gate_with_no_finding(correct):
    """No finding at all but notes (a device the capture machine lacks, any finding of the level
    NOTE: listed in the record, never failing). Where a rule is known to
    fail this correct system (``known_false_findings`` of its system.yaml, each with the reason),
    exactly those rules' findings are expected, as a strict xfail: it turns into a failure the
    day the rule no longer fails the system, so the entry is removed."""
    system, run, findings = correct["system"], correct["run"], correct["findings"]
    assert RECORDED.get(system.name, {}).get("correct") == suite.observed(findings, system_only=False), STALE
    problems = sorted({f.rule for f in findings if not suite.is_note(f.rule, f.severity)})
    known = sorted(system.known_false_findings)
    if known:
        assert problems == known, (f"{system.name}: the rules known to fail it are {known}, the check found "
                                   f"{problems} (update known_false_findings in its system.yaml)\n{run}")
        pytest.xfail("; ".join(f"{rule}: {why}" for rule, why in system.known_false_findings.items()))
    assert problems == [] and run.returncode == 0, f"{system.name}: {run}"


@pytest.mark.parametrize("correct", ["zenoh_mobile_base"], indirect=True)
def test_a_zenoh_robot_passes_and_notes_each_pair_a_dds_middleware_would_refuse(correct):
    """issue 49 item 3: its launch file selects rmw_zenoh_cpp, which connects any QoS; the two pairs
    DDS would refuse (BEST_EFFORT scans to a RELIABLE subscriber, a VOLATILE map to a
    TRANSIENT_LOCAL one) are notes, and its `moved_off_zenoh` bug makes them QOS_INCOMPATIBLE."""
    run = correct["run"]
    assert run.returncode == 0 and correct["findings"] == []
    assert run.stderr.count("a DDS middleware would refuse the match") == 2, run.stderr


@pytest.mark.parametrize("kind", list(suite.ALL_MUTATION_KINDS))
def test_each_seeded_bug_fails_the_default_gate_naming_it(correct, kind, tmp_path, environment):
    system = correct["system"]
    if kind not in system.mutations:  # an optional kind this system does not seed
        pytest.skip(f"{system.name} seeds no {kind}")
    mutation = system.mutations[kind]
    mutant = tmp_path / "prefix"
    shutil.copytree(correct["prefix"], mutant, symlinks=True)
    suite.mutate(system, mutant, mutation)
    run, findings = suite.check(correct["contract"], mutant, environment)
    seeded = suite.seeded_findings(suite.observed(correct["findings"], system_only=False),
                                   suite.observed(findings, system_only=True))
    failing = {rule for rule, severity, _ in seeded if severity == suite.FAILING}
    assert run.returncode == 1 and set(mutation.expect) <= failing, f"{system.name} / {kind}: {run}"
    recorded = RECORDED.get(system.name, {}).get("mutations", {}).get(kind)
    assert recorded == {"expect": sorted(mutation.expect),
                        "found": suite.observed(findings, system_only=True)}, STALE


def test_every_system_seeds_every_kind_of_bug_where_it_applies(tmp_path):
    """Every system has each kind of seeded bug, each applies to its installed files (text found
    exactly once, the deleted file installed), and every system is in the record; a mutation
    that does not apply is an error naming the system, the mutation and the file."""
    assert len(SYSTEMS) >= 15
    for system in SYSTEMS.values():
        assert set(suite.MUTATION_KINDS) <= set(system.mutations) <= set(suite.ALL_MUTATION_KINDS), system.name
        prefix = suite.install(system, tmp_path / system.name)
        for mutation in system.mutations.values():
            assert mutation.expect, f"{system.name} / {mutation.kind} names no rule"
            mutant = tmp_path / f"{system.name}-{mutation.kind}"
            shutil.copytree(prefix, mutant, symlinks=True)
            suite.mutate(system, mutant, mutation)
    assert set(RECORDED) == set(SYSTEMS), STALE


def test_a_mutation_that_does_not_apply_says_where(tmp_path):
    system = SYSTEMS["velodyne_slam"]
    prefix = suite.install(system, tmp_path / "prefix")
    wrong = suite.Mutation(kind="retyped_topic", file="velodyne_laserscan/standins.yaml", old="no such text",
                           expect=["TYPE_MISMATCH"])
    with pytest.raises(suite.SuiteError, match="velodyne_slam: mutation retyped_topic: 'no such text' occurs 0 times "
                                               "in velodyne_laserscan/standins.yaml"):
        suite.mutate(system, prefix, wrong)
    with pytest.raises(suite.SuiteError, match="names velodyne_laserscan/missing.yaml, which is not installed"):
        suite.mutate(system, prefix, suite.Mutation(kind="missing_calibration", file="velodyne_laserscan/missing.yaml"))
