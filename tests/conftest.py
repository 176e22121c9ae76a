"""Shared test configuration.

``pytester`` and the shared fixtures of tests/support/middleware_fixtures.py are enabled here
(a top-level conftest), and so is ``cost_report`` (what each test costs: `make test-cost`, off
unless RMWI_TEST_COST is set), because pytest only honours ``pytest_plugins`` in conftest files it
loads at start-up.
"""

pytest_plugins = ["pytester", "middleware_fixtures", "cost_report", "dimensions"]


# ---------------------------------------------------------------------------- tiers
# Tests are marked by where they live, so a new test file lands in the right tier by itself:
#   e2e     real nodes on the real middleware (tests/middleware, tests/cli, tests/cmake, tests/precision, the
#           example package),
#           and the documentation site built and opened in a real browser (tests/docs)
#   plugin  pytest run in a subprocess by pytester (tests/plugin)
#   overlay the C++ and launch overlay (tests/overlay): rclcpp nodes, RMW_IMPLEMENTATION, colcon;
#           end-to-end too, and skipped with one line where no overlay was built (`make overlay`)
#   slow    the wheels of `make dist` installed into fresh venvs, a new user's first hour (tests/dist),
#           and other tests marked `slow` (a forced middleware build): minutes each, so they run only
#           when asked for by name (`-m slow`, `make test-slow`, a block of their own in .ci/run) and
#           are deselected from every other run
# Everything else (tests/unit) is the fast tier: `make test-fast` = pytest -m "not e2e and not plugin".
import signal  # noqa: E402

import pytest  # noqa: E402

# ---------------------------------------------------------------------------- SIGINT and SIGQUIT
# A shell without job control starts a background command (`make test &`, `(cmd &)` in a script)
# with SIGINT and SIGQUIT ignored, and an ignored signal stays ignored in every process started
# after: the runner passes it on to its targets, on purpose (tests/middleware/test_ignored_signals.py
# tests that, in processes that ignore them by themselves). The other tests of a stop (its grace
# periods, an interrupted capture, the setpriv wrapper, which a runner that ignores a signal does
# without) expect what a terminal gives: the run takes Python's own dispositions back. (Three runs
# started that way failed on it: `ci-run` and both coverage runs of 2026-12-07.)
if signal.getsignal(signal.SIGINT) == signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)
if signal.getsignal(signal.SIGQUIT) == signal.SIG_IGN:
    signal.signal(signal.SIGQUIT, signal.SIG_DFL)

_TIERS = {"middleware": ("e2e",), "cli": ("e2e",), "cmake": ("e2e",), "docs": ("e2e",), "precision": ("e2e",),
          "plugin": ("plugin",), "overlay": ("e2e", "overlay"), "dist": ("slow",)}


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    root = config.rootpath
    for item in items:
        try:
            parts = item.path.relative_to(root).parts
        except ValueError:
            continue
        if parts[:1] == ("examples",):
            item.add_marker(pytest.mark.e2e)
        elif parts[:1] == ("tests",) and len(parts) > 1 and parts[1] in _TIERS:
            for tier in _TIERS[parts[1]]:
                item.add_marker(getattr(pytest.mark, tier))
    if "slow" not in (config.option.markexpr or ""):
        slow = [item for item in items if item.get_closest_marker("slow") is not None]
        if slow:
            config.hook.pytest_deselected(items=slow)
            items[:] = [item for item in items if item.get_closest_marker("slow") is None]


# ---------------------------------------------------------------------------- warm start servers
def pytest_sessionstart(session: pytest.Session) -> None:
    """This suite's own xdist workers would share their warm start servers (the plugin does that
    in every worker, and starts one after collecting): the warm start tests look at, kill and end
    the servers of their process, so each test process keeps servers of its own, from before
    its collection (sharing is tested in processes of its own, tests/middleware/
    test_warm_shared.py and tests/plugin/test_plugin_warm.py)."""
    from pytest_rmw_introspect.run.warm import client as warm

    warm.POOL.share_within(None)
