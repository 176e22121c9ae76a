"""The hooks and fixtures of pytest-rmw-introspect that run tests: contract files collected as
items, the ``interfaces`` and ``system_capture`` markers checked after the test body, the next
contract items capturing ahead, the warm start server (started by the first contract file
collected, or after collection for ``interfaces`` tests; ended with the session), and the
fixtures. Registered by the entry point (``plugin/__init__``) in ``pytest_configure`` in every
process that runs tests: not in a pytest-xdist controller, which only distributes them (so it
starts its workers sooner). The pipelines (contract comparison, system contracts and launch
files) are imported by the first test that needs them (``items``, ``marker``, ``system_marker``):
a session without contract tests never loads them."""

from __future__ import annotations

import os
from collections.abc import Generator
from pathlib import Path
from typing import Any

import pytest

from ..errors import RmwIntrospectError, SetupError
from ..model import contract_kind
from ..run import prewarm
from ..run.warm import client as warm
from . import items, lookahead, marker, marker_goldens, session, system_marker, verdict
from . import items as items_module
from . import session as session_module
from .fixtures import interfaces, rmw_capture, rmw_introspect_library, rmw_introspect_marker_check, rmw_introspect_ros
from .live_fixtures import live_system
from .system_marker import rmw_introspect_system_marker_check, system_capture

__all__ = [
    "interfaces",
    "live_system",
    "rmw_capture",
    "rmw_introspect_library",
    "rmw_introspect_ros",
    "rmw_introspect_marker_check",
    "rmw_introspect_system_marker_check",
    "system_capture",
]


def pytest_configure(config: pytest.Config) -> None:
    """Called when the entry point registers this module (``pytest_configure`` is historic)."""
    config.addinivalue_line("markers", marker.MARKER_DOC)
    config.addinivalue_line("markers", system_marker.MARKER_DOC)
    workerinput = getattr(config, "workerinput", None)
    if workerinput is not None:
        # pytest-xdist workers of one run share their warm start servers (the parent is the
        # controller: a run that reuses --testrunuid still gets servers of its own)
        warm.POOL.share_within(f"{workerinput.get('testrunuid', '')}-{os.getppid()}")


@pytest.hookimpl(wrapper=True)
def pytest_runtest_call(item: pytest.Item) -> Generator[None, Any, Any]:
    st = item.stash.get(marker.ITEM, None)
    if st is not None and st.error is not None:
        verdict.fail_with(item, st.error)
    system_st = item.stash.get(system_marker.ITEM, None)
    if system_st is not None and system_st.error is not None:
        verdict.fail_with(item, system_st.error)
    try:
        result = yield
    except RmwIntrospectError as exc:
        # raised in the test body (e.g. by rmw_capture): a failure with the message, no traceback
        verdict.fail_with(item, exc)
    if st is not None and st.capture is not None:
        marker.check_marker_item(item, st, session.state(item.config))
    if system_st is not None and system_st.capture is not None:
        system_marker.check_system_marker_item(item, system_st, session.state(item.config))
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


@pytest.hookimpl(trylast=True)  # after -k/-m deselected: only the items that stay count
def pytest_collection_modifyitems(session: pytest.Session, config: pytest.Config, items: list[pytest.Item]) -> None:
    """``--rmw-introspect-shard I/N``: keep this job's share of the contract-file items (node
    ids sorted and dealt round-robin); the others are deselected. Then a contract file that a
    marker test of this session names as its golden is checked by that test; its own item is
    skipped, naming the test (``marker_goldens``)."""
    shard = session_module.state(config).shard
    if shard is not None:
        contract_items = [i for i in items if isinstance(i, (items_module.ContractItem, system_marker.SystemContractItem))]
        mine = set(map(id, shard.select(contract_items, lambda item: item.nodeid)))
        deselected = [i for i in contract_items if id(i) not in mine]
        if deselected:
            config.hook.pytest_deselected(items=deselected)
            gone = set(map(id, deselected))
            items[:] = [i for i in items if id(i) not in gone]
    marker_goldens.skip_checked_contract_items(items)


def pytest_collection_finish(session: pytest.Session) -> None:
    """When this session (or xdist worker) will capture targets for ``interfaces`` or
    ``system_contract`` tests, start the warm start server now (contract files started it when
    they were collected)."""
    if any(item.get_closest_marker(name) is not None for item in session.items
           for name in (marker.MARKER, system_marker.MARKER)):
        _warm_up(session.config)


#: the warm start server of this session was asked for already
_WARMED_UP = pytest.StashKey[bool]()


def _warm_up(config: pytest.Config) -> None:
    """Start the warm start server in the background (or attach to the xdist run's): it imports
    rclpy while the session goes on collecting and setting up, so it is ready for the first
    capture. Once per session; not for ``--collect-only`` nor ``cold_start``."""
    if config.stash.get(_WARMED_UP, False) or config.option.collectonly:
        return
    config.stash[_WARMED_UP] = True
    session_state = config.stash.get(session_module.SESSION, None)
    if session_state is None:
        return
    try:
        spec = session_state.layers().target()
        if spec.cold_start:
            return
        prewarm.warm_up(spec, library=session_state.library(), ros=session_state.ros())
    except (SetupError, RmwIntrospectError):
        pass  # the tests themselves report it


def pytest_unconfigure(config: pytest.Config) -> None:
    warm.shutdown()


def pytest_collect_file(file_path: Path, parent: pytest.Collector) -> pytest.File | None:
    """Contract files (by their content, or the globs of ``rmw_introspect_contracts``) are test
    items of their own (``items``; system contracts: ``system_marker``)."""
    if items.collects(file_path, parent.config):
        # the first contract file of a session starts the warm start server, which then imports
        # rclpy while the rest is collected (a `-k` that deselects every contract item wastes it);
        # a system contract's processes start warm from it too (issue 42)
        _warm_up(parent.config)
        if contract_kind.is_system_file(file_path):
            return system_marker.SystemContractFile.from_parent(parent, path=file_path)
        return items.ContractFile.from_parent(parent, path=file_path)
    return None
