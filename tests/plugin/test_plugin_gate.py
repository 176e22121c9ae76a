"""``pytest --against REF``: the pull-request gate as one item per contract, in a real pytest
session over a git repository with real history."""

from __future__ import annotations

from git_history import GitRepo, endpoint, node_contract
from sample_contracts import talker_contract

TALKER = "contracts/talker.interfaces.yaml"
LISTENER = "contracts/listener.interfaces.yaml"
GONE = "contracts/gone.interfaces.yaml"


def _history(project) -> GitRepo:
    repo = GitRepo(project.path)
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter"), version="1.2.0"))
    repo.write(LISTENER, node_contract("/listener", subscriptions=endpoint("/chatter"), version="0.1.0"))
    repo.write(GONE, node_contract("/gone", publishers=endpoint("/gone")))
    repo.commit("three contracts")
    repo.git("checkout", "-q", "-b", "feature")
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter", "std_msgs/msg/Int32"), version="1.3.0"))
    repo.write(LISTENER, node_contract("/listener", subscriptions=endpoint("/chatter", depth=5), version="0.1.1"))
    repo.remove(GONE)
    repo.commit("retype, risky change with its (0.x) bump, a removal")
    return repo


def test_one_item_per_contract_failing_with_the_report(project):
    _history(project)
    result = project.run("--against", "main", "--rmw-introspect-contracts", "none", "-v", "-rA")
    result.assert_outcomes(passed=1, failed=2)
    out = result.stdout.str()
    assert f"{LISTENER}::against:main PASSED" in out
    assert f"{TALKER}::against:main FAILED" in out and f"{GONE}::against:main FAILED" in out
    assert "[INTERFACE_VERSION_BUMP_MISSING]" in out and "write interface_version: 2.0.0" in out
    assert f"{GONE} (removed: everything it promised is gone)" in out
    # the session says what the gate looked at, as `diff --against` does (issue 47)
    assert "rmw-introspect: the gate against main" in out
    assert "Interface changes against main (" in out and "): 3 contracts: 3 marker goldens; 2 changed, 1 removed" in out


def test_items_are_selected_like_any_other(project):
    _history(project)
    result = project.run("--against", "main", "--rmw-introspect-contracts", "none", "-k", "listener")
    result.assert_outcomes(passed=1)


def test_a_ref_that_does_not_exist_is_a_usage_error(project):
    _history(project)
    result = project.run("--against", "nope", "--rmw-introspect-contracts", "none")
    assert result.ret == 4
    assert "--against nope: revision 'nope' does not exist in this repository" in result.stderr.str()


def test_update_golden_keeps_the_interface_version_and_says_which_bump_the_update_needs(project):
    versioned = "interface_version: 2.0.0\n"
    project.write("talker.interfaces.yaml", talker_contract(target=f"script: {project.node('talker.py')}", depth=20,
                                                             header=versioned))
    result = project.run("--update-golden", "-W", "default")
    result.assert_outcomes(passed=1)
    # without --against the update cannot know the base the bump is owed to, and says so (issue 47)
    assert ("talker.interfaces.yaml: interface_version 2.0.0 was not changed: this update holds RISKY change(s), "
            "which need a MINOR bump over the version at the base revision (an update cannot know it): write "
            "interface_version: 2.1.0, unless 2.0.0 already is such a bump over the base") in result.stdout.str()
    assert project.read("talker.interfaces.yaml").startswith(versioned)


def test_finding_1_marker_goldens_named_as_the_readme_names_them_are_gate_items(project):
    """Issue 47: `pytest --against main` printed `2 passed` with no gate item for goldens named
    `test/contracts/driver.yaml` (no `target:`, no contract suffix)."""
    repo = GitRepo(project.path)
    repo.write("test/contracts/driver.yaml", node_contract("/driver", publishers=endpoint("/scan")))
    repo.write("config/params.yaml", "driver:\n  ros__parameters:\n    rate: 10\n")
    repo.commit("golden")
    repo.git("checkout", "-q", "-b", "rename-scan")
    repo.write("test/contracts/driver.yaml", node_contract("/driver", publishers=endpoint("/scan_raw")))
    repo.commit("rename /scan")
    result = project.run("--against", "main", "--rmw-introspect-contracts", "none", "-v")
    result.assert_outcomes(failed=1)
    assert "test/contracts/driver.yaml::against:main FAILED" in result.stdout.str()
    # what it looked at, in the terminal summary; under xdist too, where the controller collects nothing
    for run in (result, project.run("--against", "main", "--rmw-introspect-contracts", "none", "-n", "2")):
        out = run.stdout.str()
        assert "1 contract: 1 marker golden; 1 changed" in out, out
        assert "not contracts (no top-level contract_version:, system_version: or nodl_version: key): " \
               "1 tracked YAML file: config/params.yaml" in out, out


def test_a_gate_with_no_contract_is_a_usage_error(project):
    repo = GitRepo(project.path)
    repo.write("config/params.yaml", "driver:\n  ros__parameters:\n    rate: 10\n")
    repo.commit("no contract")
    result = project.run("--against", "main", "--rmw-introspect-contracts", "none")
    assert result.ret == 4
    err = result.stderr.str()
    assert "--against main: no contract to compare: git tracks no contract under" in err, err
    assert "it passed over 1 tracked YAML file: config/params.yaml" in err, err


def test_finding_5_update_golden_with_against_gives_the_advice_of_the_gate_against_that_base(project):
    """Issue 47: on a branch already bumped to 2.0.0, --update-golden warned "write
    interface_version: 2.1.0" (over the branch's own version) while the gate against main accepts
    2.0.0. With --against main the advice is the gate's against main."""
    repo = GitRepo(project.path)
    target = f"script: {project.node('talker.py')}"
    project.write("talker.interfaces.yaml", talker_contract(target=target, depth=20, header="interface_version: 1.0.0\n"))
    repo.commit("1.0.0")
    repo.git("checkout", "-q", "-b", "bumped")
    project.write("talker.interfaces.yaml", talker_contract(target=target, depth=20, header="interface_version: 2.0.0\n"))
    repo.commit("2.0.0")
    result = project.run("--update-golden", "--against", "main", "-W", "default", "talker.interfaces.yaml")
    result.assert_outcomes(passed=2)  # the contract, written; its gate item against main
    out = result.stdout.str()
    assert ("talker.interfaces.yaml: against main: interface_version 1.0.0 → 2.0.0 covers the changes since main: "
            "it stays as it is") in out, out
    assert "write interface_version" not in out, out
