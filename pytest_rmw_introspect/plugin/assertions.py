"""Assertions a test calls directly: :func:`check_compatible` (a compatibility check that fails the
calling test)."""

from __future__ import annotations

import inspect
import os
from pathlib import Path

import pytest

from ..check import system_pipeline
from ..check.pipeline import CompatibilityResult
from ..errors import RmwIntrospectError


def check_compatible(
    *contract_paths: str | Path,
    fail_on: str = "breaking",
    strict_system_default: bool = False,
    base_dir: str | Path | None = None,
    rmw: str | None = None,
) -> CompatibilityResult:
    """Fail the calling test unless the nodes of the given contracts fit together.

    ::

        def test_robot_system():
            pytest_rmw_introspect.check_compatible(
                "contracts/driver.interfaces.yaml", "contracts/planner.interfaces.yaml",
                fail_on="risky")

    The contracts are node contracts or system contracts (``system_pipeline.load_any``, as
    ``rmw-introspect compat`` reads them). Every subscription, service client and action client
    is matched with the publishers / servers of the same name in all contracts (type, type hash, QoS compatibility; requesters
    without a provider are RISKY). ``fail_on`` (``any``, ``risky``, ``breaking``; default
    ``breaking``) is the least severe problem that fails; the failure message is the system
    check report (``report.render_compat_text``). Relative paths are relative to ``base_dir``,
    by default the directory of the calling test file (like the ``interfaces`` marker).
    ``rmw``: the middleware whose QoS rules judge contracts that do not say which one they run
    on (``rmw_zenoh_cpp``, ...; docs/drift-rules.md, "QoS per middleware").
    Returns the :class:`CompatibilityResult` when the test does not fail, so it can assert more.
    A contract that cannot be loaded fails the test with the loader's message.
    """
    if base_dir is None:
        caller = inspect.stack()[1].filename
        base_dir = Path(caller).parent if caller and os.path.exists(caller) else None
    try:
        result = system_pipeline.check_contracts(contract_paths, fail_on=fail_on,
                                                 strict_system_default=strict_system_default, base_dir=base_dir,
                                                 rmw=rmw)
    except RmwIntrospectError as exc:
        pytest.fail(str(exc), pytrace=False)
    if result.failed:
        pytest.fail(result.render_text(), pytrace=False)
    return result
