"""Which items this session (or xdist worker) runs after the current one, for capturing ahead.

pytest hands ``pytest_runtest_protocol`` the item it runs and the next one only. Further items:
in a plain session, the order of ``session.items``; in an xdist worker, the indices the
controller has already sent and the worker has queued (``WorkerInteractor.torun``, read under
its lock). The worker's queue is pytest-xdist's internal state: when it is not found or not
shaped as expected, only ``nextitem`` is known, which is what capturing ahead needs at least.
"""

from __future__ import annotations

import itertools
from typing import Any

import pytest

#: an index of session.items by item (plain sessions), built at the first look ahead
_ORDER = pytest.StashKey[dict[int, int]]()
#: the xdist worker's queue of item indices, or None (not found)
_WORKER_QUEUE = pytest.StashKey[Any]()


def upcoming(item: pytest.Item, nextitem: pytest.Item, count: int) -> list[pytest.Item]:
    """Up to ``count`` items that run after ``item``, in order, starting with ``nextitem``."""
    if count <= 0:
        return []
    found = [nextitem]
    if count == 1:
        return found
    session = item.session
    if hasattr(item.config, "workerinput"):  # an xdist worker runs what its controller sends it
        queue = _worker_queue(item.config)
        indices = [] if queue is None else _queued(queue, count - 1)
    else:
        order = _order(item.config, session)
        at = order.get(id(nextitem))
        indices = [] if at is None else list(range(at + 1, min(at + count, len(session.items))))
    found += [session.items[i] for i in indices if 0 <= i < len(session.items)]
    return found


def _order(config: pytest.Config, session: pytest.Session) -> dict[int, int]:
    order = config.stash.get(_ORDER, None)
    if order is None or len(order) != len(session.items):
        order = {id(it): i for i, it in enumerate(session.items)}
        config.stash[_ORDER] = order
    return order


def _worker_queue(config: pytest.Config) -> Any:
    """The queue of item indices of this xdist worker's interactor (None: not found)."""
    if _WORKER_QUEUE not in config.stash:
        queue = None
        for plugin in config.pluginmanager.get_plugins():
            torun = getattr(plugin, "torun", None)
            if torun is not None and callable(getattr(torun, "lock", None)):
                queue = torun
                break
        config.stash[_WORKER_QUEUE] = queue
    return config.stash[_WORKER_QUEUE]


def _queued(torun: Any, count: int) -> list[int]:
    """The first ``count`` item indices of the worker's queue (it ends with a shutdown marker)."""
    try:
        with torun.lock() as queued:
            return list(itertools.islice(itertools.takewhile(lambda i: type(i) is int, queued), count))
    except Exception:  # noqa: BLE001  # another pytest-xdist: look no further than nextitem
        return []
