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
    assert ("talker.interfaces.yaml: interface_version 2.0.0 was not changed: this update holds RISKY change(s), "
            "which need a MINOR bump: write interface_version: 2.1.0") in result.stdout.str()
    assert project.read("talker.interfaces.yaml").startswith(versioned)
