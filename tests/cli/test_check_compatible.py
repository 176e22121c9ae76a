"""`pytest_rmw_introspect.check_compatible`: the system check as a pytest helper (pytester; no target runs)."""

from __future__ import annotations

import pytest

PUB = """\
contract_version: 1
nodes:
  /driver:
    publishers:
      - name: /scan
        type: sensor_msgs/msg/LaserScan
        qos: {reliability}
"""
SUB = """\
contract_version: 1
nodes:
  /planner:
    subscriptions:
      - name: /scan
        type: sensor_msgs/msg/LaserScan
        qos: default
      - name: /map
        type: nav_msgs/msg/OccupancyGrid
        qos: default
"""
TEST = """\
import pytest_rmw_introspect

def test_system():
    result = pytest_rmw_introspect.check_compatible(
        "contracts/driver.yaml", "contracts/planner.yaml", {kwargs})
    assert [item.rule for item in result.items] == {expected}
"""


@pytest.fixture
def system(pytester: pytest.Pytester, monkeypatch: pytest.MonkeyPatch):
    monkeypatch.delenv("CI", raising=False)
    monkeypatch.delenv("PYTEST_ADDOPTS", raising=False)
    pytester.makeini("[pytest]\n")

    def run(reliability: str, kwargs: str = "", expected: str = "[]") -> pytest.RunResult:
        (pytester.path / "tests" / "contracts").mkdir(parents=True, exist_ok=True)
        (pytester.path / "tests" / "contracts" / "driver.yaml").write_text(PUB.format(reliability=reliability))
        (pytester.path / "tests" / "contracts" / "planner.yaml").write_text(SUB)
        (pytester.path / "tests" / "test_system.py").write_text(TEST.format(kwargs=kwargs, expected=expected))
        # run from elsewhere: contract paths are relative to the test file, like the marker's
        return pytester.runpytest_subprocess("-p", "no:cacheprovider", "tests/test_system.py")

    return run


def test_incompatible_qos_fails_the_test_with_the_system_report(system):
    result = system("sensor_data")  # BEST_EFFORT publisher, RELIABLE subscription
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines([
        "*Compatibility check of 2 contract(s): 2 problems (1 breaking, 1 risky, 0 safe)",
        "Result: FAIL (fail on: breaking)",
        "*/scan",
        "*[[]QOS_INCOMPATIBLE[]] publisher of /driver (*driver.yaml) -> subscription of /planner (*planner.yaml)*",
    ])
    assert "Traceback" not in result.stdout.str()


def test_a_missing_publisher_is_risky_and_fails_only_below_breaking(system):
    system("default", expected="['SUBSCRIPTION_WITHOUT_PUBLISHER']").assert_outcomes(passed=1)
    failed = system("default", kwargs='fail_on="risky"')
    failed.assert_outcomes(failed=1)
    failed.stdout.fnmatch_lines(["*[[]SUBSCRIPTION_WITHOUT_PUBLISHER[]] subscription of /planner*no publisher*"])


def test_a_broken_contract_fails_with_the_loader_message(system, pytester):
    result = system("{reliability: sometimes}")
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(["*invalid contract *driver.yaml*nodes./driver.publishers[[]0[]].qos*"])
