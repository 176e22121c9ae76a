"""The test-cost counter (issue 48, item 2; docs/development.md, "What a test costs"): the package
appends one line per target started (``model.tally``, ``run.runner``) only when
``RMW_INTROSPECT_TALLY`` names a file, and tests/support/cost_report.py attributes the lines to the
test that wrote them, its subprocesses' included, and reports per tier."""

from __future__ import annotations

import json
import os
import textwrap
from pathlib import Path

import cost_report
import pytest

from pytest_rmw_introspect.model import tally
from pytest_rmw_introspect.run import runner
from pytest_rmw_introspect.run.ros_env import RosEnvironment
from pytest_rmw_introspect.run.target import TargetSpec

CAPTURE = {"format": "rmw_introspect_capture", "format_version": 1, "rmw_implementation": "rmw_introspect_cpp",
           "pid": 1, "argv": [], "state": "settled", "settle_ms": 10, "time_to_settle_ms": 1.0, "elapsed_ms": 1.0,
           "nodes": [{"id": 1, "seq": 1, "name": "fake", "namespace": "/", "fqn": "/fake", "enclave": "/",
                      "destroyed": False}], "endpoints": []}


@pytest.fixture
def tally_file(tmp_path, monkeypatch):
    monkeypatch.setattr(tally, "_seen", set())
    path = tmp_path / "t.tally"
    monkeypatch.setenv(tally.ENV, str(path))
    return path


def test_nothing_is_written_without_the_variable(tmp_path, monkeypatch):
    monkeypatch.delenv(tally.ENV, raising=False)
    monkeypatch.chdir(tmp_path)
    tally.note("start", "cold")
    assert list(tmp_path.iterdir()) == []


def test_every_start_is_a_line_and_the_rest_once_per_process(tally_file):
    for _ in range(2):
        tally.note("start", "cold")
        tally.note("rule", "PUB_REMOVED")
    assert tally_file.read_text().splitlines() == ["start\tcold", "rule\tPUB_REMOVED", "start\tcold"]


def test_the_runner_counts_a_cold_start(tmp_path, tally_file):
    prefix = tmp_path / "ros"
    (prefix / "lib").mkdir(parents=True)
    ros = RosEnvironment(kind="system", prefix=prefix, distro="jazzy", ament_prefixes=(prefix,), library_dirs=())
    library = tmp_path / "librmw_introspect_cpp.so"
    library.write_bytes(b"")
    script = tmp_path / "fake_node.py"
    script.write_text(textwrap.dedent(f"""
        import json, os
        doc = json.loads({json.dumps(json.dumps(CAPTURE))})
        doc['pid'] = os.getpid()
        out = os.environ['RMW_INTROSPECT_OUTPUT'].replace('<pid>', str(os.getpid()))
        open(out + '.tmp', 'w').write(json.dumps(doc))
        os.rename(out + '.tmp', out)
    """))
    cap = runner.run(TargetSpec.from_mapping({"script": str(script), "cold_start": True}), library=library, ros=ros)
    assert cap.node_names == ["/fake"]
    assert tally_file.read_text() == "start\tcold\n"


def test_read_tally_counts_starts_by_how_and_collects_the_rest():
    got = cost_report.read_tally("start\tcold\nstart\twarm\nstart\tcold\nstart\tdirect\nrule\tA\nrule\tA\ncommand\tcheck\n")
    assert got == {"starts": 4, "cold": 2, "warm": 1, "direct": 1, "exercised": {"command": ["check"], "rule": ["A"]}}


@pytest.mark.parametrize("markers, tier", [({"e2e", "overlay"}, "overlay"), ({"e2e"}, "e2e"), ({"plugin"}, "plugin"),
                                           ({"slow", "plugin"}, "slow"), (set(), "unit"), ({"parametrize"}, "unit")])
def test_the_tier_of_a_test(markers, tier):
    assert cost_report.tier_of(markers) == tier


def _rec(nodeid, tier, seconds, starts=0, **exercised):
    return {"nodeid": nodeid, "tier": tier, "seconds": seconds, "starts": starts, "cold": starts, "warm": 0,
            "direct": 0, "exercised": exercised}


def test_the_report_has_totals_and_the_slowest_per_tier_and_the_end_to_end_set():
    records = [_rec(f"t{i}", "e2e", float(i), i % 3, rule=[f"R{i % 2}"]) for i in range(40)]
    records += [_rec("u", "unit", 0.5, rule=["UNIT_ONLY"], command=["diff"])]
    report = cost_report.summarize(records, top=30)
    assert report["tiers"] == {"e2e": {"tests": 40, "seconds": 780.0, "starts": 39},
                               "unit": {"tests": 1, "seconds": 0.5, "starts": 0}}
    top = report["top"]["e2e"]
    assert len(top) == 30 and top[0]["nodeid"] == "t39" and top[-1]["nodeid"] == "t10"
    assert report["exercised"] == {"e2e": {"rule": ["R0", "R1"]}, "unit": {"command": ["diff"], "rule": ["UNIT_ONLY"]}}
    text = cost_report.format_report(report)
    assert "e2e" in text and "  39.00    0 (0+0+0)  t39" in text and "2 rule(s)" in text


def test_the_plugin_attributes_each_start_to_the_test_that_caused_it_and_its_subprocesses(pytester, monkeypatch):
    monkeypatch.setenv(tally.ENV, "restored-after-the-test")
    monkeypatch.delenv(tally.ENV)
    monkeypatch.setattr(tally, "_seen", set())
    monkeypatch.delenv(cost_report.RUN, raising=False)
    directory = pytester.path / "cost"
    monkeypatch.setenv(cost_report.ENV, str(directory))
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(Path(cost_report.__file__).parent),
                                                      os.environ.get("PYTHONPATH", "")]))
    pytester.makepyfile(test_nested="def test_inner():\n    pass\n")
    pytester.makepyfile(test_cost_plugin=textwrap.dedent("""
        import os, subprocess, sys
        from pytest_rmw_introspect.model import tally

        def test_none():
            pass

        def test_two_here_and_one_in_a_subprocess():
            tally.note("start", "cold")
            tally.note("start", "warm")
            subprocess.run([sys.executable, "-c", "from pytest_rmw_introspect.model import tally; "
                            "tally.note('start', 'cold'); tally.note('command', 'check')"], check=True)

        def test_a_pytest_of_its_own_with_the_tally_dropped():
            # as the overlay tier's subprocesses: RMW_INTROSPECT_* gone, RMWI_TEST_COST kept
            env = {k: v for k, v in os.environ.items() if not k.startswith("RMW_INTROSPECT_")}
            subprocess.run([sys.executable, "-m", "pytest", "-p", "cost_report", "-p", "no:cacheprovider", "-q",
                            "test_nested.py"], env=env, check=True)
    """))
    result = pytester.runpytest("-p", "cost_report", "-p", "no:cacheprovider", "test_cost_plugin.py")
    result.assert_outcomes(passed=3)
    report = json.loads((directory / "report.json").read_text())
    starts = {t["nodeid"].split("::")[1]: (t["starts"], t["cold"], t["warm"]) for t in report["tests"]}
    # the nested pytest neither reset the run's records nor added its own
    assert starts == {"test_none": (0, 0, 0), "test_two_here_and_one_in_a_subprocess": (3, 2, 1),
                      "test_a_pytest_of_its_own_with_the_tally_dropped": (0, 0, 0)}
    assert report["tiers"]["unit"]["starts"] == 3
    assert report["exercised"]["unit"] == {"command": ["check"]}
    result.stdout.fnmatch_lines(["*test cost*", "unit*3*3*"])
