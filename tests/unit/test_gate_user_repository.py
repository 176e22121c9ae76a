"""Issue 47, the gate side: a user's repository as the trial made it (an ament_python package
whose marker goldens are named as the README names them, ``test/contracts/driver.yaml``, with no
``target:``; a parameters file and a launch file beside them), a branch that renames ``/scan``
and makes ``/cmd_vel`` BEST_EFFORT with the goldens updated. Each test reproduces one finding
(it failed on fbec52c) in a temporary git repository; nothing is run but git."""

from __future__ import annotations

import json

import pytest
from git_history import GitRepo, endpoint, node_contract, run_gate

from pytest_rmw_introspect.check import gate as gate_module
from pytest_rmw_introspect.compare.drift import DriftItem
from pytest_rmw_introspect.model import interface_version
from pytest_rmw_introspect.model.vocabulary import Severity

DRIVER = "test/contracts/driver.yaml"
PLANNER = "test/contracts/planner.yaml"
NAMED = "test/contracts/driver.interfaces.yaml"
SCAN, TWIST = "sensor_msgs/msg/LaserScan", "geometry_msgs/msg/Twist"


def _driver(scan: str = "/scan", version: str | None = None) -> str:
    return node_contract("/driver", publishers=endpoint(scan, SCAN), subscriptions=endpoint("/cmd_vel", TWIST),
                         version=version)


def _planner(scan: str = "/scan", reliability: str = "RELIABLE") -> str:
    return node_contract("/planner", publishers=endpoint("/cmd_vel", TWIST, reliability=reliability),
                         subscriptions=endpoint(scan, SCAN))


@pytest.fixture
def user_repo(tmp_path, monkeypatch) -> GitRepo:
    """``main`` holds the two goldens and two YAML files that are not contracts; the branch
    ``rename-scan`` renames /scan and weakens /cmd_vel, goldens updated and committed."""
    repo = GitRepo(tmp_path / "robot")
    repo.write("package.xml", "<package format=\"3\"><name>robot</name></package>\n")
    repo.write("config/params.yaml", "driver:\n  ros__parameters:\n    rate: 10\n")
    repo.write("launch/robot.launch.yaml", "launch:\n  - node: {pkg: robot, exec: driver}\n")
    repo.write(DRIVER, _driver())
    repo.write(PLANNER, _planner())
    repo.commit("the goldens pytest --update-golden wrote")
    repo.git("checkout", "-q", "-b", "rename-scan")
    repo.write(DRIVER, _driver("/scan_raw"))
    repo.write(PLANNER, _planner("/scan_raw", "BEST_EFFORT"))
    repo.commit("rename /scan, /cmd_vel best effort; goldens updated")
    monkeypatch.chdir(repo.path)
    return repo

gate = run_gate


def test_finding_1_the_gate_finds_marker_goldens_by_their_content(user_repo, capsys):
    """fbec52c: `0 contract(s)`, exit 0 (only *.interfaces.yaml and *.system.yaml were looked at)."""
    status, out, err = gate(capsys, "main")
    assert status == 1, out + err
    first, second = out.splitlines()[:2]
    assert first.endswith(": 2 contracts: 2 marker goldens; 2 changed"), first
    assert second == ("not contracts (no top-level contract_version:, system_version: or nodl_version: key): "
                      "2 tracked YAML files: config/params.yaml, launch/robot.launch.yaml")
    assert "[PUB_RENAMED]" in out and "[SUB_RENAMED]" in out and "[QOS_RELIABILITY_WEAKENED]" in out
    status, out, _ = gate(capsys, "main", "--format", "json")
    report = json.loads(out)
    assert (report["contracts"], report["kinds"]) == (2, {"marker golden": 2})
    assert report["not_contracts"] == ["config/params.yaml", "launch/robot.launch.yaml"]
    assert {item["contract"] for item in report["items"]} == {DRIVER, PLANNER}
    status, out, _ = gate(capsys, "main", "--format", "markdown")
    assert out.splitlines()[2] == "2 contracts: 2 marker goldens; 2 changed  ", out
    assert "2 of 2 failing" in out.splitlines()[0]


def test_finding_1_from_the_package_s_test_directory_and_renamed_goldens(user_repo, capsys, monkeypatch):
    user_repo.move(DRIVER, "test/contracts/lidar_driver.yaml")
    user_repo.commit("rename the golden")
    monkeypatch.chdir(user_repo.path / "test")
    status, out, err = gate(capsys, "main")
    assert status == 1, out + err
    assert out.splitlines()[0].endswith(": 2 contracts: 2 marker goldens; 1 changed, 1 renamed"), out
    assert "contracts/lidar_driver.yaml (renamed from main:contracts/driver.yaml)" in out


def test_finding_2_a_named_file_that_exists_at_ref_is_compared_with_it(user_repo, capsys):
    """fbec52c: "2 contract(s): 2 added ... Result: pass", exit 0."""
    status, out, err = gate(capsys, "main", DRIVER, PLANNER)
    assert status == 1, out + err
    assert "added" not in out.splitlines()[0] and out.splitlines()[0].endswith("; 2 changed"), out
    assert "not contracts" not in out  # the user named the files: the others are not listed
    assert f"against main:{DRIVER}" in out and "[PUB_RENAMED]" in out


def test_finding_5_a_version_new_on_the_branch_gets_one_note_that_agrees_with_the_verdict(user_repo, capsys):
    """fbec52c said both "2.0.0 is new here" and "state interface_version ... for the gate to judge it"
    (the file has the suffix fbec52c looked for, so that this test fails there for this finding)."""
    user_repo.git("checkout", "-q", "main")
    user_repo.write(NAMED, _driver())
    user_repo.commit("a contract named as docs/ci.md names them")
    user_repo.git("checkout", "-q", "-b", "versioned")
    user_repo.write(NAMED, _driver("/scan_raw", version="2.0.0"))
    user_repo.commit("2.0.0 on the branch only")
    status, out, _ = gate(capsys, "main", NAMED)
    assert status == 1  # no version at main: judged as `diff` judges it, as docs/ci.md says
    notes = [line for line in out.splitlines() if line.strip().startswith("note:")]
    assert notes == ["  note: interface_version 2.0.0 is new here (none at main): these BREAKING change(s) judged "
                     "without a version, as `diff` judges them; the next change is judged against 2.0.0"], out


def test_finding_5_an_update_on_a_bumped_branch_follows_the_gate_against_the_base(user_repo, capsys):
    """fbec52c: a second breaking change under --update-golden on a branch already at 2.0.0 warned
    "write interface_version: 3.0.0" while the gate against main accepted 2.0.0."""
    breaking = [DriftItem("/driver", "subscriptions", "/cmd_vel", "removed", None, None, "SUB_REMOVED",
                          Severity.BREAKING, "m")]
    unknown = interface_version.advice(breaking, "2.0.0")  # the update alone cannot know the base
    assert unknown is not None and "an update cannot know it" in unknown and "unless 2.0.0 already is" in unknown
    user_repo.git("checkout", "-q", "main")
    user_repo.write(DRIVER, _driver(version="1.0.0"))
    user_repo.commit("1.0.0")
    user_repo.git("checkout", "-q", "-b", "bumped")
    user_repo.write(DRIVER, _driver("/scan_raw", version="2.0.0"))
    user_repo.commit("rename /scan: 2.0.0")
    # what --update-golden writes for a second breaking change (the version is never changed by it)
    user_repo.write(DRIVER, node_contract("/driver", publishers=endpoint("/scan_raw", SCAN), version="2.0.0"))
    advice = gate_module.update_advice("main", DRIVER)
    assert advice == (f"{DRIVER}: against main: interface_version 1.0.0 → 2.0.0 covers the changes since main: "
                      "it stays as it is")
    assert gate(capsys, "main")[0] == 0  # and the gate agrees
    user_repo.git("checkout", "-q", "-f", "main")
    user_repo.write(DRIVER, _driver("/scan_raw", version="1.0.0"))
    advice = gate_module.update_advice("main", DRIVER)
    assert advice is not None and "write interface_version: 2.0.0" in advice and "3.0.0" not in advice


# ---------------------------------------------------------------------------- zero contracts is an error


def test_a_gate_with_no_contract_is_an_error_that_says_where_it_looked_and_what_it_skipped(user_repo, capsys,
                                                                                             monkeypatch, tmp_path):
    monkeypatch.chdir(user_repo.path / "config")
    summary = tmp_path / "summary.md"
    status, out, err = gate(capsys, "main", "--summary", str(summary), "--format", "github")
    assert status == 2
    message = err.strip()
    assert message.startswith(f"rmw-introspect: no contract to compare: git tracks no contract under "
                              f"{user_repo.path / 'config'} (config/ of the repository at {user_repo.path}), "
                              "neither in the work tree nor at main ("), message
    assert "it passed over 1 tracked YAML file: params.yaml (no top-level contract_version:" in message
    assert out.startswith("::error title=rmw-introspect gate::no contract to compare"), out
    assert "error (exit 2)" in summary.read_text() and "params.yaml" in summary.read_text()
    with pytest.raises(gate_module.NoContracts):
        gate_module.run("main")


def test_a_repository_with_no_yaml_at_all(tmp_path, monkeypatch, capsys):
    repo = GitRepo(tmp_path / "empty")
    repo.write("README.md", "nothing here\n")
    repo.commit("readme")
    monkeypatch.chdir(repo.path)
    status, _, err = gate(capsys, "main")
    assert status == 2 and "git tracks no YAML file there" in err, err


def test_the_first_line_counts_each_kind(tmp_path, monkeypatch, capsys):
    from git_history import system_contract

    repo = GitRepo(tmp_path / "kinds")
    repo.write("a.interfaces.yaml", "target: {script: a.py}\n" + node_contract("/a"))
    repo.write("contracts/b.yaml", "target: {script: b.py}\n" + node_contract("/b"))
    repo.write("test/golden.yaml", node_contract("/g"))
    repo.write("robot.yaml", system_contract({"/a": ("", "")}))
    repo.write("notes.yml", "- just a list\n")
    repo.commit("four kinds of file")
    monkeypatch.chdir(repo.path)
    status, out, err = gate(capsys, "main")
    assert status == 0, out + err
    assert out.splitlines()[0].endswith(
        ": 4 contracts: 2 node contracts, 1 marker golden, 1 system contract; 4 unchanged"), out
    assert out.splitlines()[1].endswith(": 1 tracked YAML file: notes.yml"), out


# ---------------------------------------------------------------------------- listing contracts by content


def test_contracts_under_a_directory_by_content(user_repo, tmp_path, monkeypatch):
    from pytest_rmw_introspect.check import contract_files
    from pytest_rmw_introspect.model.contract_kind import Kind

    user_repo.write("test/contracts/new.yaml", node_contract("/new"))  # not added yet: still found
    user_repo.write(".gitignore", "build/\n")
    user_repo.write("build/robot/test/contracts/driver.yaml", _driver())  # ignored: not found
    listing = contract_files.find_contracts(user_repo.path)
    assert listing.contracts == {DRIVER: Kind.GOLDEN, PLANNER: Kind.GOLDEN, "test/contracts/new.yaml": Kind.GOLDEN}
    assert listing.skipped == ["config/params.yaml", "launch/robot.launch.yaml"]
    plain = tmp_path / "plain"
    (plain / "build").mkdir(parents=True)
    (plain / "build" / "x.yaml").write_text(_driver())
    (plain / "driver.yaml").write_text(_driver())
    monkeypatch.setenv("GIT_CEILING_DIRECTORIES", str(tmp_path))
    listing = contract_files.find_contracts(plain)
    assert listing.contracts == {"driver.yaml": Kind.GOLDEN} and "not a git repository" in listing.how
