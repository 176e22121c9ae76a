"""Fixtures of the middleware every end-to-end directory uses (registered for the whole suite
by ``pytest_plugins`` in tests/conftest.py; pytest's ``pythonpath`` puts this directory on
``sys.path``)."""

from __future__ import annotations

from pathlib import Path

import pytest

from pytest_rmw_introspect.errors import SetupError


@pytest.fixture(scope="session")
def middleware_library() -> Path:
    """librmw_introspect_cpp.so to preload, as the plugin gets it (RMW_INTROSPECT_LIBRARY, an
    installed package, or the cached build of the bundled sources), built once for the whole
    run; child processes and pytest sessions reuse it through RMW_INTROSPECT_LIBRARY. A build
    that fails is the test's failure, with the build's own message."""
    from pytest_rmw_introspect.run import middleware

    try:
        return Path(middleware.ensure_library())
    except SetupError as exc:
        pytest.fail(str(exc), pytrace=False)
