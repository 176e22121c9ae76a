"""The version of pytest-rmw-introspect and of rmw_introspect_cpp: the one place it is written
(pyproject.toml reads it; package.xml files must match, which tests/unit/test_packaging.py checks)."""

__version__ = "0.1.0"
