"""Names that mean one thing (issue 28 item 4): a class name is defined once in the package, no
function is called ``check`` (the package), no two modules are called ``system``, and a public
name that was renamed stays importable under its old name, with a DeprecationWarning."""

from __future__ import annotations

import ast
import warnings
from collections import defaultdict
from pathlib import Path

import pytest

import pytest_rmw_introspect

PACKAGE = Path(pytest_rmw_introspect.__file__).parent
SUBPACKAGES = sorted(p.parent.name for p in PACKAGE.glob("*/__init__.py"))


def _top_level(kind: type) -> dict[str, list[str]]:
    """Public names of top-level definitions of ``kind`` → the modules that define them."""
    found: dict[str, list[str]] = defaultdict(list)
    for path in sorted(PACKAGE.rglob("*.py")):
        for node in ast.parse(path.read_text(encoding="utf-8")).body:
            if isinstance(node, kind) and not node.name.startswith("_"):
                found[node.name].append(str(path.relative_to(PACKAGE)))
    return found


def test_every_class_name_is_defined_once():
    twice = {name: where for name, where in _top_level(ast.ClassDef).items() if len(where) > 1}
    assert twice == {}, f"one name, several classes: rename one of each ({twice})"


def test_check_names_the_package_and_no_function():
    # `run` and `compare` also name functions (runner.run, pipeline.compare): those do what their
    # layer does; the five `check` functions checked five different things
    clashes = _top_level(ast.FunctionDef).get("check", [])
    assert clashes == [], f"name each function for what it checks (check_contract, ...), not `check`: {clashes}"


def test_system_names_one_module_at_most():
    assert "check" in SUBPACKAGES and "launch" in SUBPACKAGES  # the probe reads the real layout
    systems = sorted(str(p.relative_to(PACKAGE)) for p in PACKAGE.rglob("system.py"))
    assert systems == [], f"`system` means system contracts; name each module for its part of them: {systems}"


def test_a_renamed_public_name_still_works_with_a_warning():
    with pytest.warns(DeprecationWarning, match=r"SystemResult is deprecated: use pytest_rmw_introspect\.CompatibilityResult"):
        old = pytest_rmw_introspect.SystemResult
    assert old is pytest_rmw_introspect.CompatibilityResult
    assert "SystemResult" not in pytest_rmw_introspect.__all__  # `import *` gets only the new name
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        from pytest_rmw_introspect import CompatibilityResult  # noqa: F401  (the new name: no warning)
    with pytest.raises(AttributeError, match="no attribute 'NoSuchName'"):
        pytest_rmw_introspect.NoSuchName  # noqa: B018
