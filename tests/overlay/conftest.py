"""Fixtures of the overlay tier (marker ``overlay``): tests that need the C++ and launch overlay
(``make overlay``) find it in the cache, and are skipped with one line elsewhere."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

import overlay_support  # noqa: E402


@pytest.fixture(scope="session")
def overlay() -> overlay_support.Overlay:
    found = overlay_support.find_overlay()
    if found is None:
        pytest.skip(overlay_support.BUILD_HINT)
    overlay_support.build_middleware(found)
    return found


@pytest.fixture(scope="session")
def cpp_examples(overlay: overlay_support.Overlay) -> Path:
    """The install prefix of rmw_introspect_examples_cpp built over the overlay."""
    return overlay_support.build_cpp_examples(overlay)


@pytest.fixture(scope="session")
def c_node(overlay: overlay_support.Overlay) -> Path:
    """The rcl C node of tests/middleware/c_node built over the overlay."""
    return overlay_support.build_c_node(overlay)
