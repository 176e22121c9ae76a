"""pytest entry point of pytest-rmw-introspect (``pytest11``): the hooks, and the fixtures
they register. Everything else lives in the modules next to it:

* ``session``: command-line and ini options, the session's option layers, goldens written;
* ``marker``: the ``interfaces`` marker (contract, target and options of a test);
* ``fixtures``: ``interfaces``, ``rmw_capture``, ``rmw_introspect_ros``, ``rmw_introspect_library``;
* ``items``: contract files collected as test items;
* ``verdict``: an outcome (``check.outcome``) as a pytest outcome;
* ``assertions``: ``check_compatible``.

Usage::

    @pytest.mark.interfaces("contracts/talker.yaml", script="nodes/talker.py")
    def test_talker(interfaces):
        assert "/talker" in interfaces          # the test may assert more

Problems the user can cause (no target, a malformed contract, a target that crashes,
hangs or creates no node, ROS 2 or the middleware missing) fail the test with a message
that says what to do; they are never internal errors.

Precedence of comparison options: marker > contract ``options:`` > command line > ini.
Precedence of target options: marker > contract ``target:`` > command line > ini
(``timeout``/``settle``/``horizon``/``cold_start``/``lifecycle``/``read_parameters`` only on the command line
and in the ini file).
"""

from __future__ import annotations

import os
from collections.abc import Generator
from pathlib import Path
from typing import Any

import pytest

from ..errors import RmwIntrospectError, SetupError
from ..run import runner, warm
from . import items, lookahead, marker, session, system_marker
from . import session as session_module
from .fixtures import interfaces, rmw_capture, rmw_introspect_library, rmw_introspect_marker_check, rmw_introspect_ros
from .system_marker import rmw_introspect_system_marker_check, system_capture

__all__ = [
    "interfaces",
    "rmw_capture",
    "rmw_introspect_library",
    "rmw_introspect_ros",
    "rmw_introspect_marker_check",
    "rmw_introspect_system_marker_check",
    "system_capture",
]


def pytest_addoption(parser: pytest.Parser) -> None:
    session.addoption(parser)


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line("markers", marker.MARKER_DOC)
    config.addinivalue_line("markers", system_marker.MARKER_DOC)
    session_state = session.configure(config)
    config.stash[session.SESSION] = session_state
    config.pluginmanager.register(session.GoldenReporter(session_state), "rmw-introspect-golden-reporter")
    workerinput = getattr(config, "workerinput", None)
    if workerinput is not None:
        # pytest-xdist workers of one run share their warm start servers (the parent is the
        # controller: a run that reuses --testrunuid still gets servers of its own)
        warm.POOL.share_within(f"{workerinput.get('testrunuid', '')}-{os.getppid()}")


def pytest_report_header(config: pytest.Config) -> list[str] | None:
    session_state = config.stash.get(session.SESSION, None)
    if session_state is not None and session_state.update:
        return ["rmw-introspect: --update-golden: drifted and missing golden contracts will be written"]
    return None


@pytest.hookimpl(wrapper=True)
def pytest_runtest_call(item: pytest.Item) -> Generator[None, Any, Any]:
    st = item.stash.get(marker.ITEM, None)
    if st is not None and st.error is not None:
        pytest.fail(str(st.error), pytrace=False)
    system_st = item.stash.get(system_marker.ITEM, None)
    if system_st is not None and system_st.error is not None:
        pytest.fail(str(system_st.error), pytrace=False)
    try:
        result = yield
    except RmwIntrospectError as exc:
        # raised in the test body (e.g. by rmw_capture): a failure with the message, no traceback
        pytest.fail(str(exc), pytrace=False)
    if st is not None and st.capture is not None:
        marker.check(item, st, session.state(item.config))
    if system_st is not None and system_st.capture is not None:
        system_marker.check(item, system_st, session.state(item.config))
    return result


@pytest.hookimpl(tryfirst=True)
def pytest_runtest_protocol(item: pytest.Item, nextitem: pytest.Item | None) -> None:
    """The captures of the next contract items (``capture_ahead`` of them) start now, beside this
    item: a session or xdist worker keeps several captures going, whose waiting overlaps."""
    if nextitem is None or item.config.option.collectonly:
        return
    session_state = item.config.stash.get(session_module.SESSION, None)
    if session_state is None or session_state.capture_ahead <= 0:
        return
    for upcoming in lookahead.upcoming(item, nextitem, session_state.capture_ahead):
        if isinstance(upcoming, items.ContractItem):
            upcoming.capture_ahead()


def pytest_collection_finish(session: pytest.Session) -> None:
    """When this session (or xdist worker) will capture targets, start the warm start server now,
    in the background: it imports rclpy while the first tests are set up."""
    config = session.config
    if config.option.collectonly or not any(
        isinstance(item, items.ContractItem) or item.get_closest_marker(marker.MARKER) is not None
        for item in session.items
    ):
        return
    session_state = config.stash.get(session_module.SESSION, None)
    if session_state is None:
        return
    try:
        spec = session_state.layers().target()
        if spec.cold_start:
            return
        runner.warm_up(spec, library=session_state.library(), ros=session_state.ros())
    except (SetupError, RmwIntrospectError):
        pass  # the tests themselves report it


def pytest_unconfigure(config: pytest.Config) -> None:
    warm.shutdown()


def pytest_collect_file(file_path: Path, parent: pytest.Collector) -> pytest.File | None:
    """Contract files (``rmw_introspect_contracts``) are test items of their own (``items``;
    system contracts: ``system_marker``)."""
    if items.matches(file_path, parent.config, items.patterns(parent.config)):
        if system_marker.is_system_file(file_path):
            return system_marker.SystemContractFile.from_parent(parent, path=file_path)
        return items.ContractFile.from_parent(parent, path=file_path)
    return None


def pytest_terminal_summary(terminalreporter: pytest.TerminalReporter, exitstatus: int, config: pytest.Config) -> None:
    session.terminal_summary(terminalreporter, config)
