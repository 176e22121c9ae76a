"""The pure part of a warm start: whether a command can start warm, and which server it needs.

* :func:`plan` decides whether a command can start warm: ``python SCRIPT``, ``python -m MODULE``
  and executables whose ``#!`` line names this same interpreter (an ament Python executable, a
  console script) can; compiled programs, other interpreters, interpreter options and anything
  else start cold, and the reason is kept (``Capture.start_note``);
* :func:`server_key` is the part of the environment that changes what a process imports or how
  (``PYTHON*``, ``LD_*``, ``AMENT_PREFIX_PATH``, locale, ...): one server per key, and targets whose
  environment differs there get (or start) another server.

Nothing here starts a process or opens a socket (:mod:`.client` does): it reads a command, the
first bytes of the files it names, and an environment.
"""

from __future__ import annotations

import os
import re
import sys
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

#: exact names of environment variables a server is keyed on (besides the prefixes below)
KEY_NAMES = frozenset({
    "AMENT_PREFIX_PATH", "RMW_IMPLEMENTATION", "_ROS_WHEELS_BOOTSTRAP_COMPLETE",
    "LANG", "LANGUAGE", "TZ", "HOME", "TMPDIR",
})
#: prefixes of environment variables a server is keyed on: the interpreter's own (``PYTHON*``),
#: the dynamic loader's (``LD_PRELOAD``, ``LD_LIBRARY_PATH``, ...), ROS logging set-up, locale,
#: and numpy's BLAS threads
KEY_PREFIXES = ("PYTHON", "LD_", "RCUTILS_", "LC_", "OPENBLAS_", "OMP_", "MKL_", "NUMPY_", "NPY_", "GOTO_")
_ZIP_MAGIC = b"PK\x03\x04"
_PYTHON_NAME = re.compile(r"python[0-9.]*")
_ELF_MAGIC = b"\x7fELF"


# ---------------------------------------------------------------------------------- the plan


@dataclass(frozen=True)
class Plan:
    """How a command starts warm: what the child runs and the ``sys`` values a cold start has."""

    kind: str  # "script" or "module"
    target: str  # the script (as in argv) or the module name
    argv: tuple[str, ...]  # sys.argv
    orig_argv: tuple[str, ...]  # sys.orig_argv
    executable: str  # sys.executable


def same_interpreter(path: str, python: str | None = None) -> bool:
    """Whether ``path`` starts this interpreter with this environment's prefix: the same file, in
    the same directory (a venv's ``python``/``python3``; not the base interpreter a venv links to)."""
    python = os.path.abspath(python or sys.executable)
    candidate = os.path.abspath(path)
    if candidate == python:
        return True
    return (os.path.dirname(candidate) == os.path.dirname(python)
            and os.path.realpath(candidate) == os.path.realpath(python))


def _python_command(interpreter: str, args: Sequence[str], shown: str) -> Plan | str:
    """``interpreter args...`` (the interpreter already known to be this one) as a plan, or why not."""
    if not args:
        return "no script or module to run"
    if args[0] == "-m" and len(args) >= 2 and args[1] and not args[1].startswith("-"):
        return Plan("module", args[1], ("-m", *args[2:]), (shown, *args), interpreter)
    if args[0].startswith("-"):
        return f"interpreter option {args[0]!r}"
    script = args[0]
    if os.path.isdir(script):
        return "the script is a directory"
    try:
        with open(script, "rb") as f:
            head = f.read(4)
    except OSError as exc:
        return f"cannot read the script ({exc.strerror})"
    if head == _ZIP_MAGIC or (len(head) == 4 and head[2:4] == b"\r\n"):
        return "the script is a zip archive or compiled Python"
    return Plan("script", script, tuple(args), (shown, *args), interpreter)


def _shebang(path: str) -> tuple[bytes, list[str]] | None:
    try:
        with open(path, "rb") as f:
            head = f.read(256)
    except OSError:
        return None
    if not head.startswith(b"#!"):
        return head[:4], []
    line = head[2:].split(b"\n", 1)[0].decode("utf-8", "replace").strip()
    return b"#!", line.split()


def plan(argv: Sequence[str], env: Mapping[str, str], python: str | None = None) -> Plan | str:
    """How ``argv`` (a target's full command) starts warm with the interpreter ``python``
    (default: this one), or the reason it starts cold."""
    import socket  # (here: `capture` starts without it, tests/unit/test_layering.py)

    if not hasattr(os, "fork") or not hasattr(socket, "send_fds") or sys.platform != "linux":
        return "warm starts need Linux"
    if not argv:
        return "empty command"
    program = argv[0]
    if same_interpreter(program, python):
        return _python_command(os.path.abspath(program), list(argv[1:]), program)
    if _PYTHON_NAME.fullmatch(os.path.basename(program)):
        return f"another Python interpreter ({program})"
    found = _shebang(program)
    if found is None:
        return f"cannot read {program}"
    magic, words = found
    if magic == _ELF_MAGIC:
        return "a compiled executable"
    if not words:
        return "not a Python program (no #! line)"
    interpreter, options = words[0], words[1:]
    shown = interpreter
    if os.path.basename(interpreter) == "env" and len(options) == 1 and not options[0].startswith("-"):
        shown = options[0]
        resolved = _which(shown, env.get("PATH", ""))
        if resolved is None:
            return f"its #! line names {shown}, which is not on PATH"
        interpreter, options = resolved, []
    if options:
        return f"its #! line passes options to the interpreter ({' '.join(options)})"
    if not same_interpreter(interpreter, python):
        return f"its #! line names another interpreter ({interpreter})"
    # the kernel runs `interpreter program args...`
    result = _python_command(os.path.abspath(interpreter), [program, *argv[1:]], shown)
    return result


def _which(name: str, path: str) -> str | None:
    for directory in path.split(os.pathsep):
        candidate = os.path.join(directory or ".", name)
        if os.path.isfile(candidate) and os.access(candidate, os.X_OK):
            return candidate
    return None


# ---------------------------------------------------------------------------------- keys


def server_environment(env: Mapping[str, str]) -> dict[str, str]:
    """The variables of a target's environment that a server is started with and keyed on."""
    return {k: v for k, v in env.items() if k in KEY_NAMES or k.startswith(KEY_PREFIXES)}


def server_key(env: Mapping[str, str], cwd: str, python: str | None = None) -> tuple[Any, ...]:
    """Targets with equal keys can share a server."""
    keyed = server_environment(env)
    relative = any(p and not os.path.isabs(p) for p in keyed.get("PYTHONPATH", "").split(os.pathsep))
    # relative PYTHONPATH entries are made absolute against the working directory at start-up
    return (os.path.abspath(python or sys.executable), tuple(sorted(keyed.items())), cwd if relative else None)
