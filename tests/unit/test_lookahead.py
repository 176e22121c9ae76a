"""Which items run next (plugin.lookahead) and how many capture ahead (plugin.session)."""

from __future__ import annotations

import types

import execnet
import pytest
from xdist.remote import Marker
from xdist.remote import TestQueue as WorkerQueue

from pytest_rmw_introspect.plugin import lookahead
from pytest_rmw_introspect.plugin.session import DEFAULT_CAPTURE_AHEAD, MAX_CAPTURE_AHEAD, capture_ahead_count


class _PluginManager:
    def __init__(self, plugins):
        self.plugins = plugins

    def get_plugins(self):
        return list(self.plugins)


def _session(count: int, *, worker_queue: WorkerQueue | None = None):
    """A session of ``count`` items (plain objects standing for pytest items), as a plain
    session or, with ``worker_queue``, an xdist worker whose interactor holds that queue."""
    config = types.SimpleNamespace(stash=pytest.Stash(), pluginmanager=_PluginManager([object()]))
    if worker_queue is not None:
        config.workerinput = {"workerid": "gw0"}
        interactor = types.SimpleNamespace(torun=worker_queue, nextitem_index=None)
        config.pluginmanager.plugins.append(interactor)
    session = types.SimpleNamespace(items=[], config=config)
    session.items = [types.SimpleNamespace(name=f"item{i}", session=session, config=config) for i in range(count)]
    return session


def _names(found):
    return [item.name for item in found]


def test_a_plain_session_looks_ahead_in_the_order_of_its_items():
    session = _session(6)
    items = session.items
    assert _names(lookahead.upcoming(items[0], items[1], 3)) == ["item1", "item2", "item3"]
    assert _names(lookahead.upcoming(items[3], items[4], 3)) == ["item4", "item5"]  # the end of the session
    assert _names(lookahead.upcoming(items[0], items[1], 1)) == ["item1"]
    assert lookahead.upcoming(items[0], items[1], 0) == []


def test_a_plain_session_follows_items_reordered_after_the_first_look():
    session = _session(4)
    items = session.items
    lookahead.upcoming(items[0], items[1], 2)
    session.items.append(types.SimpleNamespace(name="late", session=session, config=session.config))
    assert _names(lookahead.upcoming(items[2], items[3], 2)) == ["item3", "late"]


def test_an_xdist_worker_looks_at_the_indices_it_has_queued():
    queue = WorkerQueue(execnet.gateway_base.get_execmodel("thread"))
    session = _session(10, worker_queue=queue)
    items = session.items
    for index in (7, 2, 9):  # what the controller sent, in its order (not the session's)
        queue.put(index)
    queue.put(Marker.SHUTDOWN)
    # the worker already took nextitem (item5) out of its queue
    assert _names(lookahead.upcoming(items[4], items[5], 3)) == ["item5", "item7", "item2"]
    assert _names(lookahead.upcoming(items[4], items[5], 10)) == ["item5", "item7", "item2", "item9"]
    with queue.lock() as queued:  # looking does not take anything out of the queue
        assert list(queued) == [7, 2, 9, Marker.SHUTDOWN]


def test_an_xdist_worker_whose_queue_is_not_found_looks_at_nextitem_only():
    session = _session(5)
    session.config.workerinput = {"workerid": "gw0"}
    assert _names(lookahead.upcoming(session.items[0], session.items[1], 3)) == ["item1"]


def test_an_xdist_queue_of_another_shape_looks_at_nextitem_only():
    class Other:
        def lock(self):
            raise RuntimeError("not the queue we know")

    session = _session(5, worker_queue=Other())  # type: ignore[arg-type]
    assert _names(lookahead.upcoming(session.items[0], session.items[1], 3)) == ["item1"]


@pytest.mark.parametrize(("raw", "count"), [
    ("", DEFAULT_CAPTURE_AHEAD), ("true", DEFAULT_CAPTURE_AHEAD), ("True", DEFAULT_CAPTURE_AHEAD),
    ("false", 0), ("off", 0), ("0", 0), ("1", 1), (" 5 ", 5), (str(MAX_CAPTURE_AHEAD), MAX_CAPTURE_AHEAD),
])
def test_capture_ahead_counts(raw, count):
    assert capture_ahead_count(raw, "ini option rmw_introspect_capture_ahead") == count


@pytest.mark.parametrize("raw", ["-1", "two", "1.5", str(MAX_CAPTURE_AHEAD + 1)])
def test_a_bad_capture_ahead_count_says_what_it_takes(raw):
    with pytest.raises(pytest.UsageError) as info:
        capture_ahead_count(raw, "--rmw-introspect-capture-ahead")
    message = str(info.value)
    assert f"--rmw-introspect-capture-ahead = {raw!r}" in message
    assert f"0 to {MAX_CAPTURE_AHEAD}" in message and "0 or false: one capture at a time" in message
