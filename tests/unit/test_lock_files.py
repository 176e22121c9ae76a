"""The lock files and the venv check that `make bootstrap` relies on (scripts/lock_status.py).

requirements/jazzy.txt is what the README's two commands install; requirements/lowest.txt what
`make lowest` installs; requirements/docs.txt what `make docs` builds the site with. All are
written by `make lock`; these tests fail when pyproject.toml names a dependency the locks do not
pin, pins one outside its range, or a floor pyproject.toml claims is not the version the lowest
lock tests, and when the documentation's lock needs ROS 2 or differs from jazzy.txt.
"""

from __future__ import annotations

import importlib.util
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
from packaging.requirements import Requirement
from packaging.utils import canonicalize_name
from packaging.version import Version

ROOT = Path(__file__).resolve().parents[2]
LOCK = ROOT / "requirements" / "jazzy.txt"
LOWEST = ROOT / "requirements" / "lowest.txt"
DOCS = ROOT / "requirements" / "docs.txt"


def _lock_status():
    spec = importlib.util.spec_from_file_location("lock_status", ROOT / "scripts" / "lock_status.py")
    assert spec and spec.loader
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


lock_status = _lock_status()


def _declared() -> list[Requirement]:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    extras = project["optional-dependencies"]
    return [Requirement(r) for r in [*project["dependencies"], *extras["ros-wheels"], *extras["test"]]]


# ---------------------------------------------------------------------------- the lock files


@pytest.mark.parametrize("lock", [LOCK, LOWEST], ids=["jazzy", "lowest"])
def test_every_declared_dependency_is_pinned_within_its_range(lock):
    pins = lock_status.read_lock(lock)
    for requirement in _declared():
        name = canonicalize_name(requirement.name)
        assert name in pins, f"{lock.name} does not pin {requirement} from pyproject.toml: run `make lock`"
        assert requirement.specifier.contains(pins[name], prereleases=True), \
            f"{lock.name} pins {name}=={pins[name]}, outside pyproject.toml's {requirement}: run `make lock`"


@pytest.mark.parametrize("lock", [LOCK, LOWEST, DOCS], ids=["jazzy", "lowest", "docs"])
def test_every_pin_has_hashes_and_the_build_tools_are_locked(lock):
    text = lock.read_text()
    blocks = [b for b in text.split("\n") if b and not b.startswith((" ", "#"))]
    assert blocks, lock
    for block in blocks:
        assert "==" in block and block.endswith("\\"), f"{lock.name}: {block!r} is not a pin with hashes"
    pins = lock_status.read_lock(lock)
    # the editable install runs without build isolation, so its backend comes from the lock too
    for tool in ("pip", "setuptools", "wheel"):
        assert tool in pins, f"{lock.name} does not pin {tool}"


def test_the_lowest_lock_tests_the_floors_pyproject_claims():
    pins = lock_status.read_lock(LOWEST)
    for requirement in _declared():
        floors = [s.version for s in requirement.specifier if s.operator == ">="]
        if floors:
            name = canonicalize_name(requirement.name)
            assert Version(pins[name]) == Version(floors[0]), (
                f"pyproject.toml claims {requirement}, but requirements/lowest.txt tests "
                f"{name}=={pins[name]}: run `make lock`, or raise the floor to what works")


def test_both_locks_have_the_same_ros_distribution():
    ros = {n: v for n, v in lock_status.read_lock(LOCK).items() if n.startswith("ros-")}
    lowest = {n: v for n, v in lock_status.read_lock(LOWEST).items() if n.startswith("ros-")}
    assert ros == lowest
    assert ros["ros-jazzy-rclpy"].startswith("7."), "the Jazzy lock pins a Jazzy rclpy"


def test_the_docs_lock_builds_the_site_without_ros_with_the_versions_of_the_jazzy_lock():
    docs, jazzy = lock_status.read_lock(DOCS), lock_status.read_lock(LOCK)
    # what requirements/docs.in asks for, and what the reference pages import: the package's own
    # dependencies (not its extras), each within pyproject.toml's range
    wanted = [Requirement(line) for line in (ROOT / "requirements" / "docs.in").read_text().splitlines()
              if line.strip() and not line.startswith(("#", "-r"))]
    assert {canonicalize_name(r.name) for r in wanted} == {"mkdocs", "mkdocs-material"}
    for requirement in wanted:
        assert canonicalize_name(requirement.name) in docs, f"docs.txt does not pin {requirement}: run `make lock`"
    dependencies = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["dependencies"]
    for requirement in map(Requirement, dependencies):
        name = canonicalize_name(requirement.name)
        assert name in docs and requirement.specifier.contains(docs[name], prereleases=True), \
            f"docs.txt pins {name}=={docs.get(name)}, not pyproject.toml's {requirement}: run `make lock`"
    # no ROS 2: `make docs` needs neither the wheels nor the middleware
    assert [name for name in docs if name.startswith(("ros-", "catkin"))] == []
    # the site of `make docs` (.venv-docs) is the site tests/docs builds (.venv)
    differing = {name: (version, jazzy[name]) for name, version in docs.items() if name in jazzy and jazzy[name] != version}
    assert differing == {}, f"docs.txt and jazzy.txt pin different versions (docs, jazzy): {differing}: run `make lock`"


# ---------------------------------------------------------------------------- lock_status


def test_read_lock_reads_pins_with_extras_markers_and_hashes_and_normalizes_names(tmp_path):
    lock = tmp_path / "lock.txt"
    lock.write_text(
        "# comment\n"
        "PyYAML==6.0.4 \\\n    --hash=sha256:aa\n"
        "ros-jazzy-rclpy[fastrtps]==7.1.6 \\\n    --hash=sha256:bb\n"
        "catkin_pkg==1.1.1 ; python_version >= '3.8' \\\n    --hash=sha256:cc\n"
        "    # via pytest\n")
    assert lock_status.read_lock(lock) == {"pyyaml": "6.0.4", "ros-jazzy-rclpy": "7.1.6", "catkin-pkg": "1.1.1"}


def test_read_lock_refuses_a_file_that_pins_nothing(tmp_path):
    lock = tmp_path / "lock.txt"
    lock.write_text("pyyaml>=6\n")
    with pytest.raises(ValueError, match="pins no package"):
        lock_status.read_lock(lock)


def test_differences_name_missing_changed_extra_and_required_packages():
    lock = {"pyyaml": "6.0.4", "pytest": "9.2.0", "deepdiff": "9.1.0"}
    present = {
        "pyyaml": ("6.0.3", True),           # upgraded or downgraded by hand
        "pytest": ("9.2.0", True),
        "six": ("1.17.0", True),             # installed by hand
        "rmw-introspect-examples": ("0.1", False),  # CMake's egg-info: not pip's to remove
        "local-tool": ("1.0", True),
    }
    assert lock_status.differences(lock, present, {"local-tool"}, {"pytest-rmw-introspect"}) == [
        "missing deepdiff==9.1.0",
        "missing pytest-rmw-introspect",
        "differs pyyaml 6.0.3 -> 6.0.4",
        "extra six==1.17.0",
    ]
    assert lock_status.differences(lock, {n: (v, True) for n, v in lock.items()}, set()) == []


def test_the_command_exits_1_with_the_differences_and_2_for_a_bad_lock(tmp_path):
    lock = tmp_path / "lock.txt"
    lock.write_text("surely-not-installed-package==1.0 \\\n    --hash=sha256:00\n")
    script = ROOT / "scripts" / "lock_status.py"
    run = subprocess.run([sys.executable, str(script), str(lock)], capture_output=True, text=True, timeout=60)
    assert run.returncode == 1
    assert "missing surely-not-installed-package==1.0" in run.stdout.splitlines()
    lock.write_text("nothing pinned here\n")
    run = subprocess.run([sys.executable, str(script), str(lock)], capture_output=True, text=True, timeout=60)
    assert run.returncode == 2 and "pins no package" in run.stderr

