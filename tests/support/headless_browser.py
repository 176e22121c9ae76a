"""The headless Chromium that the browser tests drive (the graph drawing, the documentation site),
from the system packages (`apt-get install chromium`; scripts/install-test-tools.sh, which
.ci/run runs). A test without one is skipped, saying so."""

from __future__ import annotations

import html
import json
import os
import re
import shutil
import subprocess
from pathlib import Path
from typing import Any

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


#: where a probe script writes what it measured (a `<pre>` it appends to the page's body)
PROBE_OUTPUT = "rmwi-check"


def probe(page: Path, script: str, profile: Path, *, window: str = "1400,1000") -> dict[str, Any]:
    """Open a copy of ``page`` from disk (file://) with ``script`` added at the end of its body,
    and return what the script measured: the script runs in the rendered page and ends by calling
    ``rmwiReport(value)`` (defined here), which puts ``value`` as JSON into the page, and Chromium
    prints the page as it is then (``--dump-dom``)."""
    reporter = ("<script>function rmwiReport(value) { const pre = document.createElement('pre'); "
                f"pre.id = '{PROBE_OUTPUT}'; pre.textContent = JSON.stringify(value); "
                "document.body.appendChild(pre); }</script>")
    copy = page.with_name(page.stem + ".probe.html")
    copy.write_text(page.read_text(encoding="utf-8").replace("</body>", f"{reporter}<script>{script}</script></body>"),
                    encoding="utf-8")
    command = headless_command(profile, "--allow-file-access-from-files", f"--window-size={window}",
                               "--virtual-time-budget=10000", "--dump-dom", copy.as_uri())
    proc = subprocess.run(command, capture_output=True, text=True, timeout=120, check=False,
                          env={**os.environ, "HOME": str(profile)})
    assert proc.returncode == 0, f"chromium failed ({proc.returncode}):\n{proc.stderr[-3000:]}"
    found = re.search(rf'<pre id="{PROBE_OUTPUT}">(.*?)</pre>', proc.stdout, re.S)
    assert found, f"the probe in {copy} never reported (did the page load?):\n" + proc.stdout[-2000:]
    return json.loads(html.unescape(found.group(1)))
