"""mypy checks the model and check layers as ``mypy --strict`` does (issue 28 item 5): every flag
that ``--strict`` sets is set for them in pyproject.toml (``make typecheck`` runs mypy with it)."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

try:
    from mypy.main import define_options
except ImportError:  # older mypy (requirements/lowest.txt) keeps it elsewhere; the development lock's mypy has it
    define_options = None

PYPROJECT = Path(__file__).resolve().parents[2] / "pyproject.toml"
STRICT_LAYERS = ("pytest_rmw_introspect.model.*", "pytest_rmw_introspect.check.*")


def test_the_model_and_check_layers_are_checked_strictly():
    if define_options is None:
        pytest.skip("this mypy has no mypy.main.define_options to list what --strict sets (the lock's mypy has)")
    _parser, _flags, strict_assignments = define_options()  # what `mypy --strict` sets, from mypy itself
    config = tomllib.loads(PYPROJECT.read_text(encoding="utf-8"))["tool"]["mypy"]
    overrides = [o for o in config.get("overrides", []) if set(STRICT_LAYERS) <= set(o["module"])]
    assert len(overrides) == 1, f"pyproject.toml: one [[tool.mypy.overrides]] for {STRICT_LAYERS}"
    settings = {**config, **overrides[0]}
    missing = {name: value for name, value in strict_assignments if settings.get(name) != value}
    assert missing == {}, f"pyproject.toml: [[tool.mypy.overrides]] for {STRICT_LAYERS} lacks these --strict settings"


def test_the_ros_environment_is_typed_where_it_is_passed():
    """issue 51 item 5: a ``ros`` parameter is a ``RosEnvironment`` (or a callable making one), never
    ``Any``: eight signatures once took ``ros: Any``."""
    import ast

    package = PYPROJECT.parent / "pytest_rmw_introspect"
    untyped = []
    for path in sorted(package.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                arguments = node.args
                for arg in (*arguments.posonlyargs, *arguments.args, *arguments.kwonlyargs):
                    if arg.arg == "ros" and (arg.annotation is None or ast.unparse(arg.annotation) == "Any"):
                        untyped.append(f"{path.relative_to(package)}:{node.lineno} {node.name}")
    assert not untyped, f"type `ros` as ros_env.RosEnvironment: {untyped}"
