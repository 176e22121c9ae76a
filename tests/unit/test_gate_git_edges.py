"""Issue 50, the gate's edges (N19-N24): what is read from git is read as git stores it. Each test
is a user's repository in a temporary git repository, the file that broke the gate on fbec52c and
the command; nothing is run but git. A file the gate cannot read is an error of its own (exit 2,
the file named, what to do), never drift (exit 1), never a traceback, a hang or a silent skip."""

from __future__ import annotations

import os
import threading

import pytest
from git_history import GitRepo, endpoint, node_contract, run_gate

SCAN = "sensor_msgs/msg/LaserScan"


def _contract(topic: str = "/scan", version: str | None = None) -> str:
    return node_contract("/driver", publishers=endpoint(topic, SCAN), version=version)


@pytest.fixture
def repo(tmp_path, monkeypatch) -> GitRepo:
    """``main`` holds one marker golden, ``contracts/driver.yaml``; the work tree is on ``main``."""
    repo = GitRepo(tmp_path / "robot")
    repo.write("contracts/driver.yaml", _contract())
    repo.commit("the golden")
    monkeypatch.chdir(repo.path)
    return repo


def _no_hang(target, *args):
    """``target(*args)`` in a thread that must end within 20 s (a FIFO that blocks fails the test)."""
    out: list = []
    thread = threading.Thread(target=lambda: out.append(target(*args)), daemon=True)
    thread.start()
    thread.join(20)
    assert not thread.is_alive(), "blocked"
    return out[0]


def test_n21_an_interface_version_of_5000_digits_is_an_invalid_contract_not_a_traceback(repo, capsys):
    repo.write("contracts/driver.yaml", _contract("/scan_raw", version="1" * 5000 + ".0.0"))
    status, out, err = run_gate(capsys, "main")
    assert status == 2, out + err
    assert "contracts/driver.yaml:2" in err and "at most 18 digits" in err
    assert len(err) < 2000  # the value is cut, not printed whole


def test_n22_a_baseline_that_is_a_fifo_is_refused_at_once(repo, capsys):
    os.mkfifo(repo.path / "baseline.json")
    status, out, err = _no_hang(run_gate, capsys, "main", "--baseline", "baseline.json")
    assert status == 2, out + err
    assert "baseline.json" in err and "FIFO" in err


def test_n22_a_summary_that_is_a_fifo_nobody_reads_is_refused_at_once(repo, capsys):
    os.mkfifo(repo.path / "summary.md")
    status, out, err = _no_hang(run_gate, capsys, "main", "--summary", "summary.md")
    assert status == 2, out + err
    assert "--summary summary.md" in err and "FIFO" in err
