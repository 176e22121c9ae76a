"""The ``interfaces`` marker tests that name a golden, found in the test files around it.

A marker test's golden written before ``--update-golden`` wrote the marker's target into it has
no ``target:`` block: ``rmw-introspect check`` and a contract item cannot run it by itself. The
one command that makes it checkable is that test under ``--update-golden`` (which writes the
target); this module finds the test, so that the message can name it. It reads only the test
files (``test_*.py``, ``*_test.py``) of the package around the golden that mention the golden's
file name, parses those (no import, nothing runs), and is asked only on that error path.
"""

from __future__ import annotations

import ast
import os
from pathlib import Path

#: directories never searched (builds, installs, environments, caches)
_SKIPPED_DIRS = frozenset({"build", "install", "log", "node_modules", "__pycache__", "site", "dist", "venv"})
#: what marks the root of the package (or repository) around a golden
_ROOT_FILES = ("package.xml", "pyproject.toml", "setup.py", "setup.cfg", ".git")
#: at most this many test files are read, in at most this many directories
MAX_FILES = 2000
MAX_DIRECTORIES = 5000
#: how far above the golden's directory the package root is looked for
MAX_LEVELS = 4


def search_root(golden: Path) -> Path:
    """The package (or repository) directory around ``golden``: the nearest directory above it
    holding a package.xml, pyproject.toml, setup.py, setup.cfg or .git (at most MAX_LEVELS up);
    else its parent's parent."""
    start = golden.absolute().parent
    for directory in (start, *start.parents[:MAX_LEVELS]):
        if any((directory / name).exists() for name in _ROOT_FILES):
            return directory
    return start.parent


def _test_files(root: Path) -> list[Path]:
    found: list[Path] = []
    for visited, (directory, subdirs, files) in enumerate(os.walk(root)):
        if visited >= MAX_DIRECTORIES:
            break
        subdirs[:] = sorted(d for d in subdirs if not d.startswith(".") and d not in _SKIPPED_DIRS)
        for name in sorted(files):
            if name.endswith(".py") and (name.startswith("test_") or name.endswith("_test.py")):
                found.append(Path(directory, name))
                if len(found) >= MAX_FILES:
                    return found
    return found


def _marker_contract(decorator: ast.expr) -> str | None:
    """The contract path of an ``@pytest.mark.interfaces("...")`` decorator, or None."""
    if not (isinstance(decorator, ast.Call) and isinstance(decorator.func, ast.Attribute)
            and decorator.func.attr == "interfaces"):
        return None
    args = [*decorator.args[:1], *(k.value for k in decorator.keywords if k.arg == "contract")]
    if args and isinstance(args[0], ast.Constant) and isinstance(args[0].value, str):
        return args[0].value
    return None


def _tests_in(tree: ast.Module) -> list[tuple[str, ast.FunctionDef | ast.AsyncFunctionDef, list[ast.expr]]]:
    """``(name, function, decorators)`` of every test function, in classes too (the class's
    decorators apply to its methods)."""
    out: list[tuple[str, ast.FunctionDef | ast.AsyncFunctionDef, list[ast.expr]]] = []
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            out.append((node.name, node, list(node.decorator_list)))
        elif isinstance(node, ast.ClassDef):
            for member in node.body:
                if isinstance(member, (ast.FunctionDef, ast.AsyncFunctionDef)):
                    out.append((f"{node.name}::{member.name}", member,
                                [*node.decorator_list, *member.decorator_list]))
    return out


def marker_tests(golden: str | Path, *, cwd: Path | None = None) -> list[str]:
    """The node ids (test file relative to ``cwd``, default the current directory) of the
    ``interfaces`` marker tests whose marker names ``golden`` (a path relative to the test file,
    or absolute). Empty when none is found."""
    golden = Path(golden)
    wanted = os.path.realpath(golden)
    cwd = cwd or Path.cwd()
    found: list[str] = []
    for test_file in _test_files(search_root(golden)):
        try:
            text = test_file.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError):
            continue
        if golden.name not in text:
            continue
        try:
            tree = ast.parse(text, filename=str(test_file))
        except (SyntaxError, ValueError):
            continue
        for name, _function, decorators in _tests_in(tree):
            for decorator in decorators:
                contract = _marker_contract(decorator)
                if contract is None:
                    continue
                path = Path(os.path.expanduser(contract))
                if os.path.realpath(path if path.is_absolute() else test_file.parent / path) == wanted:
                    found.append(f"{os.path.relpath(test_file, cwd)}::{name}")
    return found


def how_to_check(golden: str | Path, shown: str, *, cwd: Path | None = None) -> str | None:
    """For a node contract ``golden`` (``shown`` as messages name it) with no ``target:`` block:
    the one command that writes its marker test's target into it; None when no marker test found
    around it names it."""
    tests = marker_tests(golden, cwd=cwd)
    if not tests:
        return None
    return (f"{shown} is the golden of the marker test {tests[0]}, whose marker names the target, and it has no "
            f"`target:` block of its own. Make it checkable by itself (rmw-introspect check, pytest {shown}, the "
            f"GitHub action) with:\n  pytest --update-golden {tests[0]}\n"
            "which writes the marker's target into the file's `target:` block.")
