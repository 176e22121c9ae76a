"""The headless Chromium that the browser tests drive (the graph drawing, the documentation site),
from the system packages (`apt-get install chromium`; scripts/install-test-tools.sh, which
.ci/run runs). A test without one is skipped, saying so."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")


def browser() -> str:
    for name in BROWSERS:
        found = shutil.which(name)
        if found:
            return found
    pytest.skip("no Chromium installed: `apt-get install -y chromium` (scripts/install-test-tools.sh; .ci/run installs it)")


def headless_command(profile: Path, *args: str) -> list[str]:
    """Chromium without a window, a sandbox, a GPU or any traffic of its own, with ``profile`` as
    its user data directory and ``args`` (the page and what to do with it) after."""
    return [browser(), "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
            "--disable-background-networking", "--disable-component-update", "--disable-sync",
            f"--user-data-dir={profile}", *args]
