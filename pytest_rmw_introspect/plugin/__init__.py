"""pytest entry point of pytest-rmw-introspect (``pytest11``): the options, the session's
state and its summary. Everything else lives in the modules next to it:

* ``hooks``: the hooks that collect and run tests, and the fixtures; registered here in every
  process that runs tests (not in a pytest-xdist controller, which only distributes them: it
  starts its workers sooner without the hooks' ~50 ms of imports); the pipelines themselves
  are imported by the first contract test that runs;
* ``session``: command-line and ini options, the session's option layers, goldens written;
* ``option_flags``: the pytest options and ini keys of the option tables (``model.option_tables``);
* ``marker``: the ``interfaces`` marker (contract, target and options of a test);
* ``fixtures``: ``interfaces``, ``rmw_capture``, ``rmw_introspect_ros``, ``rmw_introspect_library``;
* ``items``: contract files collected as test items;
* ``marker_goldens``: the items of contract files that a marker test checks are skipped;
* ``verdict``: an outcome (``check.outcome``) as a pytest outcome;
* ``assertions``: ``check_compatible``;
* ``system_marker``: the ``system_contract`` marker, the ``system_capture`` fixture, system contract items;
* ``live_fixtures``: the ``live_system`` fixture and ``system_contract(..., live=True)``: a launch
  file brought up on the real middleware and checked live (issue 52);
* ``lookahead``: which items run next, for capturing ahead;
* ``gate_items``: ``--against REF``, the pull-request gate: one item per contract.
* ``notices``: the progress lines of slow steps (a middleware build) on the terminal.

Usage::

    @pytest.mark.interfaces("contracts/talker.yaml", script="nodes/talker.py")
    def test_talker(interfaces):
        assert "/talker" in interfaces          # the test may assert more

Problems the user can cause (no target, a malformed contract, a target that crashes,
hangs or creates no node, ROS 2 or the middleware missing) fail the test with a message
that says what to do; they are never internal errors.

Precedence of comparison and target options: marker > contract ``options:`` / ``target:`` >
command line > ini (``model.option_tables.PRECEDENCE``; which options the command line and the
ini file take, the tables say).
"""

from __future__ import annotations

import pytest

from . import gate_items, notices, session

HOOKS_PLUGIN = "rmw-introspect-hooks"
GATE_PLUGIN = "rmw-introspect-gate"


def pytest_addoption(parser: pytest.Parser) -> None:
    session.addoption(parser)
    gate_items.addoption(parser)


def pytest_configure(config: pytest.Config) -> None:
    session_state = session.configure(config)
    config.stash[session.SESSION] = session_state
    config.pluginmanager.register(session.SessionReporter(session_state), "rmw-introspect-session-reporter")
    notices.install(config)
    if not _xdist_controller(config):
        from . import hooks  # ~50 ms (the target options, the runner): only where tests run

        config.pluginmanager.register(hooks, HOOKS_PLUGIN)
        config.pluginmanager.register(gate_items, GATE_PLUGIN)


def _xdist_controller(config: pytest.Config) -> bool:
    """pytest-xdist's controller process: it starts the workers and shows their reports, and
    never collects or runs a test itself (xdist's own rule for starting its ``DSession``).
    ``--markers`` and ``--fixtures`` list ours there too."""
    listing = any(config.getoption(name, False) for name in ("markers", "showfixtures", "show_fixtures_per_test"))
    return (getattr(config.option, "dist", "no") != "no" and not config.getoption("collectonly", False)
            and not hasattr(config, "workerinput") and not listing)


def pytest_unconfigure(config: pytest.Config) -> None:
    notices.uninstall(config)


def pytest_report_header(config: pytest.Config) -> list[str] | None:
    session_state = config.stash.get(session.SESSION, None)
    if session_state is not None and session_state.update:
        return ["rmw-introspect: --update-golden: drifted and missing golden contracts will be written"]
    return None


def pytest_terminal_summary(terminalreporter: pytest.TerminalReporter, exitstatus: int, config: pytest.Config) -> None:
    session.terminal_summary(terminalreporter, config)
    gate_items.terminal_summary(terminalreporter, config)

