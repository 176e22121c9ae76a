"""scripts/conformance/run.py: the suite's build is keyed by what it is built from, not by where
(issue 48 item 5): a fresh clone's new venv of the same lock reuses it; other wheels do not."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from types import ModuleType

import pytest

RUN = Path(__file__).resolve().parents[2] / "scripts" / "conformance" / "run.py"


@pytest.fixture(scope="module")
def run() -> Iterator[ModuleType]:
    spec = importlib.util.spec_from_file_location("conformance_run", RUN)
    assert spec and spec.loader
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up there
    try:
        spec.loader.exec_module(module)
        yield module
    finally:
        del sys.modules[spec.name]


def _venv(where: Path, wheels: list[str]) -> Path:
    site = where / "lib" / "python3.11" / "site-packages"
    for wheel in wheels:
        (site / f"{wheel}.dist-info").mkdir(parents=True)
    return where


def _checkout(where: Path) -> Path:
    where.mkdir()
    subprocess.run(["git", "init", "-q", str(where)], check=True)
    (where / "a.txt").write_text("a\n")
    subprocess.run(["git", "-C", str(where), "add", "a.txt"], check=True)
    subprocess.run(["git", "-C", str(where), "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", "a"],
                   check=True)
    return where


def test_the_key_follows_content_not_paths(run: ModuleType, tmp_path: Path) -> None:
    tests, tools = _checkout(tmp_path / "tests"), _checkout(tmp_path / "tools")
    wheels = ["ros_rmw-7.3.2", "ros_rcl-9.2.8"]
    first = run.build_key(tests, tools, _venv(tmp_path / "clone1" / ".venv", wheels))
    assert run.build_key(tests, tools, _venv(tmp_path / "clone2" / ".venv", wheels)) == first
    other = _venv(tmp_path / "clone3" / ".venv", ["ros_rmw-7.3.3", "ros_rcl-9.2.8"])
    assert run.build_key(tests, tools, other) != first
    (tests / "a.txt").write_text("changed\n")  # an uncommitted change of the sources
    assert run.build_key(tests, tools, tmp_path / "clone1" / ".venv") != first


def test_a_build_tree_of_another_clone_is_recognised(run: ModuleType, tmp_path: Path) -> None:
    tree = tmp_path / "build"
    assert run._configured_source(tree) is None
    tree.mkdir()
    (tree / "CMakeCache.txt").write_text("FOO:BOOL=ON\nCMAKE_HOME_DIRECTORY:INTERNAL=/old/clone/scripts/conformance\n")
    assert run._configured_source(tree) == "/old/clone/scripts/conformance"
