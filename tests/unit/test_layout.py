"""The maps are true (issue 28 item 1): every module of the package is named in its subpackage's
docstring and in docs/design.md, and every test directory in docs/design.md. A module or a test
directory added without being named there fails here, with what to add where."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import pytest_rmw_introspect

PACKAGE = Path(pytest_rmw_introspect.__file__).parent
REPO = Path(__file__).resolve().parents[2]
DESIGN = REPO / "docs" / "design.md"


def _packages() -> list[Path]:
    """The package and every subpackage of it (the middleware's bundled sources are not Python)."""
    return sorted(init.parent for init in PACKAGE.rglob("__init__.py") if "rmw_introspect_cpp" not in init.parts)


def _members(package: Path) -> list[str]:
    """The modules and subpackages directly inside ``package``."""
    modules = [p.stem for p in package.glob("*.py") if p.stem != "__init__"]
    subpackages = [p.name for p in package.iterdir() if (p / "__init__.py").is_file()]
    return sorted(modules + subpackages)


def _docstring(package: Path) -> str:
    return ast.get_docstring(ast.parse((package / "__init__.py").read_text(encoding="utf-8"))) or ""


def test_the_probe_sees_the_real_layout():
    names = {str(p.relative_to(PACKAGE)) for p in _packages()}
    assert {".", "model", "launch", "run", "run/warm", "check", "cli"} <= names
    assert "pipeline" in _members(PACKAGE / "check") and "warm" in _members(PACKAGE / "run")


@pytest.mark.parametrize("package", _packages(), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_every_module_is_named_in_its_subpackage_docstring(package):
    doc = _docstring(package)
    missing = [m for m in _members(package) if f"``{m}``" not in doc]
    assert missing == [], (f"{package.relative_to(PACKAGE.parent)}/__init__.py: name each module in the docstring, "
                           f"one line each (``name``: what it is for): {missing}")


@pytest.mark.parametrize("package", _packages(), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_every_module_is_shown_in_the_design_page(package):
    text = DESIGN.read_text(encoding="utf-8")
    rel = package.relative_to(PACKAGE)
    modules = [m for m in _members(package) if (package / f"{m}.py").is_file()]
    if str(rel) == ".":
        missing = [m for m in modules if f"`{m}" not in text]
    else:
        missing = [f"{rel}/{m}.py" for m in modules if f"`{rel}/{m}.py`" not in text]
    assert missing == [], f"docs/design.md: add a row for each module to the module table: {missing}"


def test_every_test_directory_is_shown_in_the_design_page():
    text = DESIGN.read_text(encoding="utf-8")
    directories = sorted(p.name for p in (REPO / "tests").iterdir()
                         if p.is_dir() and not p.name.startswith((".", "__")))
    assert "unit" in directories  # the probe reads the real tree
    missing = [f"tests/{d}" for d in directories if f"`tests/{d}`" not in text]
    assert missing == [], f"docs/design.md: add each test directory to the table of test directories: {missing}"


def _tracked_directories() -> list[str]:
    """The repository's top-level directories that hold tracked files (build outputs, venvs and
    the built site are untracked), from git when there is a checkout."""
    import subprocess

    listed = subprocess.run(["git", "-C", str(REPO), "ls-files"], capture_output=True, text=True)
    if listed.returncode != 0:
        pytest.skip("not a git checkout: the tracked directories are unknown")
    return sorted({line.split("/", 1)[0] for line in listed.stdout.splitlines() if "/" in line})


def test_the_repository_layout_table_names_every_directory():
    """docs/development.md's layout table (the README links to it) names each top-level
    directory and each test directory."""
    text = (REPO / "docs" / "development.md").read_text(encoding="utf-8")
    table = text.split("## Repository layout", 1)[1].split("\n## ", 1)[0]
    directories = _tracked_directories()
    assert "tests" in directories and "pytest_rmw_introspect" in directories
    missing = [f"{d}/" for d in directories if f"`{d}/`" not in table]
    tests = sorted(p.name for p in (REPO / "tests").iterdir() if p.is_dir() and not p.name.startswith((".", "__")))
    missing += [f"tests/{d}/" for d in tests if f"`{d}/`" not in table]
    assert missing == [], f"docs/development.md, \"Repository layout\": add a row or a mention for {missing}"


def test_test_files_have_unique_basenames() -> None:
    """pytest imports the suite's test files by their basename (no ``__init__.py``, the prepend
    import mode): two files of one name in different tiers make the second an "import file
    mismatch" error at collection (it stopped CI's unit tier once)."""
    seen: dict[str, list[str]] = {}
    for path in sorted((REPO / "tests").rglob("test_*.py")):
        if ".venv" in path.parts or "site-packages" in path.parts:
            continue
        seen.setdefault(path.name, []).append(str(path.relative_to(REPO)))
    assert {name: paths for name, paths in seen.items() if len(paths) > 1} == {}
