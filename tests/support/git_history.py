"""Temporary git repositories with real history, for the gate of ``diff --against REF``
(tests/unit/test_gate.py, tests/plugin/test_plugin_gate.py, tests/cli/test_cli_action.py and
bench/bench_gate.py): commits, branches, renames and shallow clones made by git itself."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path
from typing import Any

#: a fixed identity and dates: the tests never read the user's git configuration
GIT_ENV = {
    "GIT_AUTHOR_NAME": "gate test", "GIT_AUTHOR_EMAIL": "gate@example.invalid",
    "GIT_COMMITTER_NAME": "gate test", "GIT_COMMITTER_EMAIL": "gate@example.invalid",
    "GIT_AUTHOR_DATE": "2026-01-01T00:00:00Z", "GIT_COMMITTER_DATE": "2026-01-01T00:00:00Z",
    "GIT_CONFIG_NOSYSTEM": "1", "GIT_CONFIG_GLOBAL": os.devnull,
}


class GitRepo:
    """A repository in ``path`` (created with a ``main`` branch)."""

    def __init__(self, path: Path, *, init: bool = True) -> None:
        self.path = path
        if init:
            path.mkdir(parents=True, exist_ok=True)
            self.git("init", "-q", "-b", "main")

    def git(self, *args: str) -> str:
        result = subprocess.run(["git", *args], cwd=self.path, capture_output=True, text=True,
                                env={**os.environ, **GIT_ENV}, check=False, timeout=60)
        assert result.returncode == 0, f"git {' '.join(args)}: {result.stderr}"
        return result.stdout

    def write(self, name: str, text: str) -> Path:
        path = self.path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
        return path

    def commit(self, message: str) -> str:
        self.git("add", "-A")
        self.git("commit", "-q", "--allow-empty", "-m", message)
        return self.git("rev-parse", "HEAD").strip()

    def move(self, old: str, new: str) -> None:
        (self.path / new).parent.mkdir(parents=True, exist_ok=True)
        self.git("mv", old, new)

    def remove(self, name: str) -> None:
        self.git("rm", "-q", name)

    def shallow_clone(self, into: Path, *, branch: str = "main", depth: int = 1) -> GitRepo:
        """A clone holding the last ``depth`` commits of ``branch`` only (as CI checks out)."""
        subprocess.run(["git", "clone", "-q", f"--depth={depth}", "--branch", branch, "--single-branch",
                        self.path.as_uri(), str(into)], check=True, capture_output=True,
                       env={**os.environ, **GIT_ENV}, timeout=60)
        return GitRepo(into, init=False)


def endpoint(name: str, type_name: str = "std_msgs/msg/String", *, reliability: str = "RELIABLE",
             depth: int = 10, durability: str = "VOLATILE") -> str:
    return (f"      - name: {name}\n        type: {type_name}\n"
            f"        qos: {{history: KEEP_LAST, depth: {depth}, reliability: {reliability}, "
            f"durability: {durability}}}\n")


def node_contract(node: str = "/talker", *, publishers: str = "", subscriptions: str = "",
                  version: str | None = None, header: str = "") -> str:
    """A node contract of one node with these ``publishers`` / ``subscriptions`` entries
    (:func:`endpoint`) and, when given, its ``interface_version``."""
    text = header + "contract_version: 1\n"
    if version is not None:
        text += f"interface_version: {version}\n"
    text += f"nodes:\n  {node}:\n"
    text += "    publishers:\n" + publishers if publishers else "    publishers: []\n"
    text += "    subscriptions:\n" + subscriptions if subscriptions else "    subscriptions: []\n"
    return text


def system_contract(nodes: dict[str, tuple[str, str]], *, version: str | None = None) -> str:
    """A system contract whose nodes have these (publishers, subscriptions) entries, one process each."""
    text = "system_version: 1\n"
    if version is not None:
        text += f"interface_version: {version}\n"
    text += "launch: {path: robot.launch.xml}\nprocesses:\n"
    for node in nodes:
        text += f"  - {{package: robot, executable: {node.strip('/')}, name: {node}, nodes: [{node}]}}\n"
    text += "nodes:\n"
    for node, (publishers, subscriptions) in nodes.items():
        text += f"  {node}:\n"
        text += "    publishers:\n" + publishers if publishers else "    publishers: []\n"
        text += "    subscriptions:\n" + subscriptions if subscriptions else "    subscriptions: []\n"
    return text


def run_gate(capsys: Any, *args: str) -> tuple[int, str, str]:
    """``rmw-introspect diff --against ARGS...`` in this process: its exit status, stdout and stderr."""
    from pytest_rmw_introspect.cli import main

    status = main(["diff", "--against", *args])
    out, err = capsys.readouterr()
    return status, out, err
