"""What to do next, for a target that ran but could not import a module, could not load the
middleware, or created no node.

The runner adds these hints to its ``TargetExited`` and ``NoNodeCreated`` errors: a module the
target could not import (:func:`missing_module_hint`, from its stderr), a middleware library
the dynamic loader refused (:func:`preload_hint`, from its stderr), and a ``module`` target
whose file defines ``main`` but never calls it (:func:`no_node_hint`: asked only after the
target created no node, because finding the module's file starts an interpreter).
"""

from __future__ import annotations

import os
import re
import subprocess
from collections.abc import Mapping
from pathlib import Path

_MISSING_MODULE = re.compile(r"ModuleNotFoundError: No module named '([^']+)'")


def missing_module_hint(stderr: str) -> str | None:
    """What to do when the target could not import a module, or None."""
    missing = _MISSING_MODULE.findall(stderr)
    if not missing:
        return None
    return (
        f"Hint: the target could not import {missing[-1]!r}. It runs with the environment of the process "
        "that checks it plus the target's `env:`, and a contract records only what `env:` lists: if the "
        "module comes from a workspace or another virtual environment, give PYTHONPATH (or "
        "AMENT_PREFIX_PATH) in the target's `env:`, or run the check where the node's environment is set up."
    )


_NOT_PRELOADED = re.compile(r"ld\.so: object '([^']*librmw_introspect_cpp\.so)' from LD_PRELOAD cannot be preloaded "
                            r"\(([^)]*)\)")


def exit_hint(stderr: str) -> str | None:
    """The hints for a target that exited before it settled, told from its stderr (a middleware
    the loader refused, a module it could not import), or None."""
    hints = [hint for hint in (preload_hint(stderr), missing_module_hint(stderr)) if hint]
    return "\n".join(hints) or None


def preload_hint(stderr: str) -> str | None:
    """What to do when the dynamic loader could not load the recording middleware (a damaged
    or truncated library: the target then runs on another middleware and rcl exits with status
    102), or None."""
    found = _NOT_PRELOADED.search(stderr)
    if found is None:
        return None
    library, why = found.groups()
    return (
        f"Hint: the dynamic loader could not load the recording middleware {library} ({why}), so the target ran "
        "without it. The file is damaged or truncated: delete it (a build in the cache, "
        "~/.cache/pytest-rmw-introspect/ or RMW_INTROSPECT_CACHE: delete its directory and the next run builds it "
        "again), or point RMW_INTROSPECT_LIBRARY at a whole build."
    )


def no_node_hint(module: str | None, python: str, own_env: Mapping[str, str], cwd: Path | None) -> str | None:
    """Why the ``module`` target (None: not a module target) run by ``python`` with its own
    ``env:`` in ``cwd`` may have created no node, or None."""
    if module is None:
        return None
    return module_main_hint(module, module_origin(python, module, own_env, cwd))


def module_origin(python: str, module: str, own_env: Mapping[str, str], cwd: Path | None) -> Path | None:
    """The file ``python -m <module>`` ran, as the target's interpreter and environment find it
    (editable installs have their own finders)."""
    code = "import importlib.util, sys\ns = importlib.util.find_spec(sys.argv[1])\nprint(s.origin if s and s.origin else '')"
    try:
        found = subprocess.run([python, "-c", code, module], env={**os.environ, **own_env},
                               cwd=str(cwd) if cwd else None, capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.TimeoutExpired):
        return None
    origin = found.stdout.strip()
    return Path(origin) if found.returncode == 0 and origin else None


def module_main_hint(module: str, origin: Path | None) -> str | None:
    """Why ``python -m module`` may have run nothing: the module's file (``origin``) defines
    ``main`` but has no ``if __name__ == "__main__":`` block. None when that is not the case."""
    if origin is None or not origin.is_file():
        return None
    try:
        text = origin.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return None
    if not re.search(r"^def main\(", text, flags=re.M) or "__main__" in text:
        return None
    return (
        f"{origin} defines main() but has no `if __name__ == \"__main__\":` block, so `python -m {module}` "
        f"defines the node and returns without running it. Name the function instead: "
        f"`entry_point: {module}:main` (what a console script calls)."
    )
