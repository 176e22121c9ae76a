"""The wheel ships what an installed plugin needs to build the middleware and check contracts."""

from __future__ import annotations

import subprocess
import sys
import zipfile
from pathlib import Path

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
