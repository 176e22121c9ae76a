"""The wheel ships what an installed plugin needs to build the middleware and check contracts."""

from __future__ import annotations

import re
import subprocess
import sys
import zipfile
from pathlib import Path

from pytest_rmw_introspect import __version__

REPO = Path(__file__).resolve().parents[2]


def test_wheel_carries_the_middleware_sources_and_both_schemas(tmp_path):
    subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", "--disable-pip-version-check",
         "-w", str(tmp_path), str(REPO)],
        check=True, capture_output=True,
    )
    (wheel,) = tmp_path.glob("pytest_rmw_introspect-*.whl")
    names = set(zipfile.ZipFile(wheel).namelist())

    sources = {
        p.relative_to(REPO / "rmw_introspect_cpp").as_posix()
        for p in (REPO / "rmw_introspect_cpp").rglob("*")
        if p.is_file() and "__pycache__" not in p.parts
    }
    missing = sorted(s for s in sources if f"pytest_rmw_introspect/rmw_introspect_cpp/{s}" not in names)
    assert not missing, f"middleware files left out of the wheel: {missing}"
    assert "pytest_rmw_introspect/schema/contract.schema.json" in names
    assert "pytest_rmw_introspect/rmw_introspect_cpp/schema/capture.schema.json" in names
    entry_points = next(n for n in names if n.endswith(".dist-info/entry_points.txt"))
    text = zipfile.ZipFile(wheel).read(entry_points).decode()
    assert "rmw_introspect = pytest_rmw_introspect.plugin" in text
    assert "rmw-introspect = pytest_rmw_introspect.cli:main" in text

    package = REPO / "pytest_rmw_introspect"
    modules = sorted(p.relative_to(REPO).as_posix() for p in package.rglob("*.py") if "rmw_introspect_cpp" not in p.parts)
    assert [m for m in modules if m not in names] == [], "Python modules left out of the wheel"
    assert "pytest_rmw_introspect/py.typed" in names
    # find_package(pytest_rmw_introspect) after a wheel install: <prefix>/share/pytest_rmw_introspect/cmake
    assert f"pytest_rmw_introspect-{__version__}.data/data/share/pytest_rmw_introspect/cmake/pytest_rmw_introspectConfig.cmake" in names
    assert "pytest_rmw_introspect/cmake/pytest_rmw_introspectConfig.cmake" in names
    assert wheel.name.startswith(f"pytest_rmw_introspect-{__version__}-")


def test_one_version_everywhere():
    """pyproject reads the version from _version.py; both ament packages must carry the same."""
    pyproject = (REPO / "pyproject.toml").read_text()
    assert 'dynamic = ["version"]' in pyproject
    assert 'version = {attr = "pytest_rmw_introspect._version.__version__"}' in pyproject
    for package_xml in (REPO / "rmw_introspect_cpp" / "package.xml",
                        REPO / "examples" / "rmw_introspect_examples" / "package.xml"):
        found = re.search(r"<version>([^<]+)</version>", package_xml.read_text())
        assert found and found.group(1) == __version__, f"{package_xml}: version {found and found.group(1)}, " \
                                                        f"pytest_rmw_introspect/_version.py says {__version__}"
    assert re.search(rf"^## \[{re.escape(__version__)}\]", (REPO / "CHANGELOG.md").read_text(), flags=re.M)
