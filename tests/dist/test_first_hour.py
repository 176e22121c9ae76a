"""A new user's first hour (issue 40, item 5), as docs/getting-started/ament-python.md tells it:
the package made from the page's own code blocks, in a fresh venv with the built wheel, the
marker test run with --update-golden, run again (green), the node changed, the failure read.
Each step asserts what the user sees. The time from `pip install` finishing to the first green
test is printed (docs/performance.md records it; never asserted: a shared machine)."""

from __future__ import annotations

import re
import subprocess
import time
from pathlib import Path

import pytest

#: the wheel is built and installed by the first test that needs it (minutes on a loaded machine)
pytestmark = [pytest.mark.slow, pytest.mark.timeout(1200)]  # marked here too: `-m slow` selects before the tier hook runs

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "getting-started" / "ament-python.md"

#: a fenced block (its language, its text), with the file it is when a paragraph that is only the
#: file's name (`` `setup.py`: ``) comes right before it
BLOCK = re.compile(r"(?:^`([^`\n]+)`:\n\n)?^```(\w*)\n(.*?)^```$", re.M | re.S)


def page_blocks(text: str) -> list[tuple[str | None, str, str]]:
    """The page's code blocks in order: (the file it is or None, its language, its text)."""
    return [(match.group(1), match.group(2), match.group(3)) for match in BLOCK.finditer(text)]


def shell_lines(blocks: list[tuple[str | None, str, str]]) -> list[str]:
    """The commands of the page's ``sh`` blocks, comments removed."""
    return [line.split("#", 1)[0].strip() for _, lang, text in blocks if lang == "sh"
            for line in text.splitlines() if line.split("#", 1)[0].strip()]


def test_the_page_has_the_whole_package_and_the_commands():
    blocks = page_blocks(PAGE.read_text())
    files = {title for title, _, _ in blocks if title}
    assert {"my_pkg/talker.py", "setup.py", "package.xml", "test/test_interfaces.py"} <= files
    commands = shell_lines(blocks)
    assert "pip install -e ." in commands
    assert "pytest test/test_interfaces.py --update-golden" in commands and "pytest test/" in commands
    assert "rmw-introspect check test/contracts/talker.interfaces.yaml" in commands  # the golden checks alone


def _run(cmd: str, cwd: Path, env: dict[str, str], timeout: float = 300) -> subprocess.CompletedProcess[str]:
    return subprocess.run(["bash", "-c", cmd], cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)


def test_a_new_package_from_the_getting_started_page_to_a_drift_report(installed_wheel, tmp_path: Path):
    blocks = page_blocks(PAGE.read_text())
    commands = shell_lines(blocks)
    env = installed_wheel.env(RMW_INTROSPECT_CACHE=str(tmp_path / "cache"))
    began = installed_wheel.installed_at  # `pip install 'pytest-rmw-introspect[jazzy]'` just finished
    started = time.monotonic()

    # 0. the package: the page's mkdir/touch line, then its files
    made = _run(" && ".join(c for c in commands if c.startswith(("mkdir ", "touch "))), tmp_path, env)
    assert made.returncode == 0, made.stderr
    package = tmp_path / "my_pkg"
    for title, _, text in blocks:
        if title:
            (package / title).parent.mkdir(parents=True, exist_ok=True)
            (package / title).write_text(text)

    # 1. the page's `pip install -e .` (the wheel itself is installed: the fixture)
    before_pip = time.monotonic()
    installed = _run("pip install --disable-pip-version-check -e .", package, env)
    assert installed.returncode == 0, installed.stdout + installed.stderr
    after_pip = time.monotonic()

    # 3. the golden contract written: one line says so, and no middleware is built
    update = _run(next(c for c in commands if c.endswith("--update-golden") and c.startswith("pytest ")), package, env)
    assert update.returncode == 0, update.stdout + update.stderr
    after_update = time.monotonic()
    assert "1 passed" in update.stdout
    assert "test/contracts/talker.interfaces.yaml" in update.stdout and "1 golden contract(s) written" in update.stdout
    assert "building the recording middleware" not in update.stdout + update.stderr
    golden = (package / "test" / "contracts" / "talker.interfaces.yaml").read_text()
    assert "/talker:" in golden and "name: /chatter" in golden and "std_msgs/msg/String" in golden

    # 4. run again: green, nothing written
    run_tests = next(c for c in commands if c == "pytest test/")
    green = _run(run_tests, package, env)
    first_green = time.monotonic()
    assert green.returncode == 0, green.stdout + green.stderr
    assert re.search(r"\b1 passed\b", green.stdout) and "written" not in green.stdout
    assert (package / "test" / "contracts" / "talker.interfaces.yaml").read_text() == golden
    # the same golden from the command line (issue 47: it names the marker's target)
    checked = _run(next(c for c in commands if c.startswith("rmw-introspect check ")), package, env)
    assert checked.returncode == 0, checked.stdout + checked.stderr

    # the node changes (its topic is renamed): the test fails and says what drifted and what to do
    talker = package / "my_pkg" / "talker.py"
    talker.write_text(talker.read_text().replace('"chatter"', '"chat"'))
    drift = _run(run_tests, package, env)
    assert drift.returncode == 1, drift.stdout + drift.stderr
    report = drift.stdout
    assert "1 failed" in report
    assert "/chatter" in report and "/chat" in report and "/talker" in report
    assert re.search(r"PUB_(REMOVED|RENAMED)", report), report
    assert "--update-golden" in report, "the failure does not say how to accept the change"
    assert "Traceback" not in report

    print(f"\nfirst hour: pip install of the wheel took {installed_wheel.install_seconds:.1f} s; "
          f"from its end to the first green test {first_green - began:.1f} s, of which this test's own steps "
          f"{first_green - started:.1f} s: `pip install -e .` {after_pip - before_pip:.1f} s, pytest --update-golden "
          f"{after_update - after_pip:.1f} s, the green run {first_green - after_update:.1f} s")
