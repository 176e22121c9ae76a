"""The fast tier starts no warm start server (a process that imports rclpy): the runner's tests
here run their fake targets cold. Warm starts are tested end to end (tests/middleware/test_warm_*)."""

from __future__ import annotations

import pytest

from pytest_rmw_introspect.run.warm import client as warm


@pytest.fixture(autouse=True)
def _cold_starts_only(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(warm.POOL, "disabled", "the fast test tier starts targets cold")
