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


def test_n19_a_tracked_file_whose_name_is_not_utf8_is_one_name_not_a_traceback(repo, capsys):
    (repo.path / os.fsdecode(b"config/params\xff.yaml")).parent.mkdir()
    (repo.path / os.fsdecode(b"config/params\xff.yaml")).write_text("rate: 10\n")
    (repo.path / os.fsdecode(b"notes\xfe.txt")).write_text("x\n")
    repo.write("contracts/driver.yaml", _contract("/scan_raw"))
    repo.commit("a file name in Latin-1")
    repo.write("contracts/driver.yaml", _contract("/scan_raw2"))
    (repo.path / os.fsdecode(b"contracts/\xe9t\xe9.yaml")).write_text(_contract("/scan_raw2"))
    repo.git("add", "-A")
    status, out, err = run_gate(capsys, "HEAD")
    assert status == 1, out + err  # the drift of driver.yaml, nothing else
    assert "[PUB_RENAMED]" in out
    assert out.splitlines()[0].endswith("2 contracts: 2 marker goldens; 1 changed, 1 added"), out
    assert "config/params\\xff.yaml" in out.splitlines()[1]  # passed over, shown escaped


def test_n20_a_file_name_with_a_newline_at_the_base_does_not_shift_the_texts(repo, capsys):
    repo.write("contracts/a\nb.yaml", node_contract("/weird", publishers=endpoint("/w", SCAN)))
    repo.write("contracts/z.yaml", node_contract("/zeta", publishers=endpoint("/z", SCAN)))
    repo.commit("a name with a newline")
    repo.write("contracts/a\nb.yaml", node_contract("/weird", publishers=endpoint("/w2", SCAN)))
    repo.write("contracts/driver.yaml", _contract("/scan_raw"))
    status, out, err = run_gate(capsys, "main", "--format", "json")
    assert status == 1, out + err
    import json

    report = json.loads(out)
    assert report["kinds"] == {"marker golden": 3}
    renamed = {(item["contract"], item["node"], item["rule"]) for item in report["items"]}
    assert renamed == {("contracts/a\\nb.yaml", "/weird", "PUB_RENAMED"),
                       ("contracts/driver.yaml", "/driver", "PUB_RENAMED")}, renamed
    assert "error" not in out


def test_n23_the_size_limit_applies_at_the_base_revision(repo, capsys, monkeypatch):
    repo.write("contracts/driver.yaml", _contract() + "# padding\n" * 200)
    repo.commit("a large contract")
    repo.write("contracts/driver.yaml", _contract("/scan_raw"))
    monkeypatch.setattr("pytest_rmw_introspect.model.untrusted.MAX_FILE_BYTES", 1000)
    status, out, err = run_gate(capsys, "main")
    assert status == 2, out + err
    assert "main:contracts/driver.yaml is 2," in err and "more than the 1,000 bytes a contract may be" in err


def test_n23_a_contract_that_is_a_fifo_now_is_unreadable_not_removed(repo, capsys):
    (repo.path / "contracts/driver.yaml").unlink()
    os.mkfifo(repo.path / "contracts/driver.yaml")
    status, out, err = _no_hang(run_gate, capsys, "main")
    assert status == 2, out + err
    assert "removed" not in out
    assert "contracts/driver.yaml cannot be read: it is a FIFO (named pipe)" in err


LFS = "version https://git-lfs.github.com/spec/v1\noid sha256:{}\nsize 1234\n".format("0" * 64)


def test_n24_a_contract_kept_in_lfs_at_the_base_is_named_as_an_lfs_pointer(repo, capsys):
    repo.write("contracts/driver.yaml", LFS)
    repo.commit("the golden in LFS (what git stores)")
    repo.write("contracts/driver.yaml", _contract("/scan_raw"))  # as `git lfs pull` leaves it
    status, out, err = run_gate(capsys, "main")
    assert status == 2, out + err
    assert "main:contracts/driver.yaml is a git LFS pointer" in err and "at main" in err
    assert "keep contracts out of LFS" in err and "a str, not a mapping" not in err


def test_n24_lfs_pointers_in_the_work_tree_say_git_lfs_pull(repo, capsys):
    repo.write("contracts/driver.yaml", LFS)  # changed, and not pulled: the gate cannot tell what it is
    status, out, err = run_gate(capsys, "main")
    assert status == 2, out + err
    assert "contracts/driver.yaml is a git LFS pointer" in err and "git lfs pull" in err
    repo.commit("committed as a pointer")  # unchanged and unread: no contract left, the error says why
    status, out, err = run_gate(capsys, "HEAD")
    assert status == 2 and "no contract to compare" in err and "git LFS pointer" in err, out + err


def test_n24_a_symlink_out_of_the_repository_is_not_followed(repo, capsys, tmp_path):
    outside = tmp_path / "outside.yaml"
    outside.write_text(_contract("/scan_raw"))
    (repo.path / "contracts/driver.yaml").unlink()
    (repo.path / "contracts/driver.yaml").symlink_to(outside)
    status, out, err = run_gate(capsys, "main")
    assert status == 2, out + err
    assert "contracts/driver.yaml is a symbolic link to" in err and "outside the repository: not followed" in err
    repo.commit("the link committed")
    (repo.path / "contracts/driver.yaml").unlink()
    repo.write("contracts/driver.yaml", _contract("/scan_raw"))
    status, out, err = run_gate(capsys, "main", "contracts/driver.yaml")  # at the base it is the link
    assert status == 2, out + err
    assert "main:contracts/driver.yaml is a symbolic link at main to " in err and "not followed" in err


def test_a_symlink_at_the_base_is_followed_inside_the_repository_only(repo, capsys):
    os.symlink("driver.yaml", repo.path / "contracts/current.yaml")
    os.symlink("/etc/hostname", repo.path / "contracts/host.yaml")
    repo.commit("two links")
    repo.write("contracts/driver.yaml", _contract("/scan_raw"))
    (repo.path / "contracts/host.yaml").unlink()
    repo.write("contracts/host.yaml", _contract())
    status, out, err = run_gate(capsys, "main")
    assert status == 2, out + err
    assert out.count("[PUB_RENAMED]") == 2  # driver.yaml and the link to it, both sides followed
    assert "main:contracts/host.yaml is a symbolic link at main to /etc/hostname, outside the repository" in err


def test_contracts_lists_names_as_bytes_and_says_what_it_could_not_read(repo, capfdbinary):
    """`rmw-introspect contracts` (the action's check step) reads the work tree as the gate does: a
    name that is not UTF-8 is listed as the file system spells it, a link out of the repository and
    an LFS pointer are not read and are said."""
    from pytest_rmw_introspect.cli import main

    odd = os.fsdecode(b"contracts/\xe9t\xe9.yaml")
    (repo.path / odd).write_text(_contract())
    (repo.path / "contracts/out.yaml").symlink_to("/etc/hostname")
    repo.write("contracts/big.yaml", LFS)
    repo.git("add", "-A")
    assert main(["contracts", "-0"]) == 0
    out, raw_err = capfdbinary.readouterr()
    err = raw_err.decode()
    assert out.split(b"\0")[:-1] == [b"contracts/driver.yaml", b"contracts/\xe9t\xe9.yaml"]
    assert "contracts/out.yaml is a symbolic link to " in err and "contracts/big.yaml is a git LFS pointer" in err


def test_n19_a_repository_whose_own_path_is_not_utf8(tmp_path, monkeypatch, capsys):
    repo = GitRepo(tmp_path / os.fsdecode(b"robot\xff"))
    repo.write("contracts/driver.yaml", _contract())
    repo.commit("the golden")
    repo.write("contracts/driver.yaml", _contract("/scan_raw"))
    monkeypatch.chdir(repo.path)
    status, out, err = run_gate(capsys, "main")
    assert status == 1 and "[PUB_RENAMED]" in out, out + err


def test_a_baseline_whose_findings_are_not_a_list_is_a_baseline_error(repo, capsys):
    """Found by the baseline fuzzer (issue 50 item 5): `"findings": 1.5` was a TypeError traceback."""
    repo.write("baseline.json", '{"format": "rmw_introspect_baseline", "version": 1, "findings": 1.5}')
    status, out, err = run_gate(capsys, "main", "--baseline", "baseline.json")
    assert status == 2 and "baseline.json" in err and "not a list" in err, out + err
