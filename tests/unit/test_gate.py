"""The pull-request gate, ``rmw-introspect diff --against REF``, over temporary git repositories
with real history (git itself makes the commits, renames, branches and shallow clones): what it
finds, how interface versions and consumers judge it, and one clear message, exit 2, for each
way it cannot run."""

from __future__ import annotations

import json

import pytest
from git_history import GitRepo, endpoint, node_contract, run_gate, system_contract

from pytest_rmw_introspect.check import gate as gate_module
from pytest_rmw_introspect.cli import main
from pytest_rmw_introspect.compare import baseline, versioning
from pytest_rmw_introspect.compare.drift import DriftItem
from pytest_rmw_introspect.errors import ContractError
from pytest_rmw_introspect.model import contract, interface_version
from pytest_rmw_introspect.model.interface_version import Bump, Version
from pytest_rmw_introspect.model.vocabulary import Severity

TALKER = "contracts/talker.interfaces.yaml"
#: the rules of the gate, each found by a test here (tests/unit/test_drift.py collects them)
TESTED_RULES = {"INTERFACE_VERSION_BUMP_MISSING", "INTERFACE_VERSION_DECREASED", "CONSUMER_INCOMPATIBLE"}


@pytest.fixture
def repo(tmp_path, monkeypatch):
    """A repository whose ``main`` holds the talker's contract (/chatter, RELIABLE) at 1.2.0."""
    repo = GitRepo(tmp_path / "repo")
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter"), version="1.2.0"))
    repo.commit("talker contract")
    repo.git("checkout", "-q", "-b", "feature")
    monkeypatch.chdir(repo.path)
    return repo

gate = run_gate


def as_json(capsys, *args: str) -> tuple[int, list[dict]]:
    """The exit status and the drift items of the JSON report."""
    status, out, _ = gate(capsys, *args, "--format", "json")
    return status, json.loads(out)["items"]


# ---------------------------------------------------------------------------- what it finds


def test_nothing_changed_passes(repo, capsys):
    status, out, err = gate(capsys, "main")
    assert status == 0, out + err
    assert "1 contract: 1 marker golden; 1 unchanged" in out.splitlines()[0]


def test_a_weakened_qos_without_a_major_bump_fails_and_says_which_version_to_write(repo, capsys):
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter", reliability="BEST_EFFORT"), version="1.3.0"))
    repo.commit("best effort")
    status, items = as_json(capsys, "main")
    assert status == 1
    rules = {item["rule"]: item for item in items}
    assert "QOS_RELIABILITY_WEAKENED" in rules
    bump = rules["INTERFACE_VERSION_BUMP_MISSING"]
    assert bump["severity"] == "BREAKING"
    assert "need a MAJOR bump: write interface_version: 2.0.0 (it is 1.2.0 → 1.3.0 is a MINOR bump)" in bump["message"]
    assert all(item["against"] == f"main:{TALKER}" for item in items)


def test_a_major_bump_accepts_the_breaking_change(repo, capsys):
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter", reliability="BEST_EFFORT"), version="2.0.0"))
    repo.commit("best effort, 2.0.0")
    status, out, err = gate(capsys, "main")
    assert status == 0, out + err
    assert "ACCEPTED (1)" in out and "interface_version 1.2.0 → 2.0.0 (MAJOR bump)" in out
    status, items = as_json(capsys, "main")
    assert [item["rule"] for item in items] == ["QOS_RELIABILITY_WEAKENED"] and items[0]["accepted"]


def test_a_risky_change_needs_a_minor_bump(repo, capsys):
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter", depth=5), version="1.2.1"))
    repo.commit("depth 5")
    status, items = as_json(capsys, "main")
    assert status == 1
    assert [i["rule"] for i in items] == ["INTERFACE_VERSION_BUMP_MISSING", "QOS_DEPTH_DECREASED"]
    assert "1 RISKY change(s) need a MINOR bump: write interface_version: 1.3.0" in items[0]["message"]
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter", depth=5), version="1.3.0"))
    repo.commit("1.3.0")
    assert gate(capsys, "main")[0] == 0


def test_a_retype_is_breaking_and_an_unversioned_contract_fails_on_it(repo, capsys):
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter", "std_msgs/msg/Int32")))
    repo.commit("Int32, no version")
    status, out, _ = gate(capsys, "main")
    assert status == 1
    assert "[TYPE_CHANGED]" in out
    assert ("interface_version 1.2.0 was removed: these BREAKING change(s) judged without it (kept, they would need "
            "interface_version: 2.0.0)") in out
    assert "state `interface_version" not in out


def test_a_bump_without_a_change_is_a_note(repo, capsys):
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter"), version="1.2.1"))
    repo.commit("1.2.1")
    status, out, _ = gate(capsys, "main")
    assert status == 0
    assert "note: interface_version 1.2.0 → 1.2.1 (PATCH bump) with no change of the interface" in out


def test_a_version_that_goes_down_fails(repo, capsys):
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter"), version="1.1.9"))
    repo.commit("down")
    status, items = as_json(capsys, "main")
    assert status == 1 and items[0]["rule"] == "INTERFACE_VERSION_DECREASED"


def test_a_renamed_contract_is_compared_with_its_old_name(repo, capsys):
    repo.move(TALKER, "contracts/renamed/speaker.interfaces.yaml")
    repo.write("contracts/renamed/speaker.interfaces.yaml",
               node_contract(publishers=endpoint("/chatter") + endpoint("/status"), version="1.3.0"))
    repo.commit("rename and add /status")
    status, out, err = gate(capsys, "main")
    assert status == 0, out + err
    assert f"contracts/renamed/speaker.interfaces.yaml (renamed from main:{TALKER})" in out
    assert "[PUB_ADDED]" in out and "removed" not in out.split("renamed")[0]


def test_a_removed_contract_is_the_removal_of_everything_it_promised(repo, capsys):
    repo.remove(TALKER)
    repo.commit("no talker")
    status, out, _ = gate(capsys, "main")
    assert status == 1
    assert f"{TALKER} (removed: everything it promised is gone)" in out
    assert "[NODE_REMOVED]" in out


def test_an_added_contract_adds_its_nodes_and_passes(repo, capsys):
    repo.write("contracts/listener.interfaces.yaml", node_contract("/listener", subscriptions=endpoint("/chatter")))
    repo.commit("listener")
    status, out, _ = gate(capsys, "main")
    assert status == 0
    assert "contracts/listener.interfaces.yaml (added since the base revision)" in out and "[NODE_ADDED]" in out


def test_named_contracts_only(repo, capsys):
    repo.write("contracts/other.interfaces.yaml", node_contract("/other", publishers=endpoint("/x")))
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter", reliability="BEST_EFFORT"), version="2.0.0"))
    repo.commit("two")
    status, items = as_json(capsys, "main", TALKER)
    assert status == 0 and {i["contract"] for i in items} == {TALKER}


def test_the_merge_base_of_a_three_dot_range(repo, capsys):
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter", reliability="BEST_EFFORT"), version="2.0.0"))
    repo.commit("feature: 2.0.0")
    repo.git("checkout", "-q", "main")
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter", "std_msgs/msg/Int32"), version="3.0.0"))
    repo.commit("main moved on")
    repo.git("checkout", "-q", "feature")
    # against main itself the feature branch would go back from 3.0.0; against the merge base it bumped right
    assert as_json(capsys, "main")[1][0]["rule"] == "INTERFACE_VERSION_DECREASED"
    status, out, err = gate(capsys, "main...HEAD")
    assert status == 0, out + err
    assert "interface_version 1.2.0 → 2.0.0 (MAJOR bump)" in out


def test_accept_entries_apply(repo, capsys):
    accept = "accept:\n  - {rule: TYPE_CHANGED, name: /chatter, reason: nobody listens yet}\n"
    repo.write(TALKER, accept + node_contract(publishers=endpoint("/chatter", "std_msgs/msg/Int32")))
    repo.commit("Int32, accepted")
    status, out, _ = gate(capsys, "main")
    assert status == 0 and "nobody listens yet" in out


def test_a_baseline_applies(repo, capsys):
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter", "std_msgs/msg/Int32")))
    repo.commit("Int32, no version")
    (compared,) = gate_module.run("main").contracts
    assert compared.failed
    repo.write("gate.baseline.json", baseline.render([(compared.path, item) for item in compared.items],
                                                     repo.path / "gate.baseline.json"))
    status, out, _ = gate(capsys, "main", "--baseline", "gate.baseline.json")
    assert status == 0, out
    assert "in the baseline" in out


def test_fail_on_from_the_command_line(repo, capsys):
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter") + endpoint("/new")))
    repo.commit("one more publisher, no version")
    assert gate(capsys, "main")[0] == 0
    assert gate(capsys, "main", "--fail-on", "any")[0] == 1


# ---------------------------------------------------------------------------- consumers decide


def test_a_consumer_with_an_incompatible_profile_makes_the_change_breaking_and_is_named(repo, capsys):
    repo.write("robot.system.yaml", system_contract({"/listener": ("", endpoint("/chatter"))}))
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter"), version="1.2.0"))
    repo.commit("the system")
    repo.git("branch", "-f", "base")
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter", reliability="BEST_EFFORT", depth=5),
                                     version="1.2.0"))
    repo.commit("weaker")
    status, items = as_json(capsys, "base")
    assert status == 1
    broken = [i for i in items if i["rule"] == "CONSUMER_INCOMPATIBLE"]
    assert len(broken) == 1 and broken[0]["severity"] == "BREAKING"
    assert "the subscription of /listener in robot.system.yaml no longer fits: [QOS_INCOMPATIBLE]" in broken[0]["message"]
    depth = next(i for i in items if i["rule"] == "QOS_DEPTH_DECREASED")
    assert depth["message"].endswith("(used by the subscription of /listener in robot.system.yaml)")


def test_a_change_nothing_consumes_says_so(repo, capsys):
    repo.write("robot.system.yaml", system_contract({"/listener": ("", endpoint("/other"))}))
    repo.commit("the system")
    repo.git("branch", "-f", "base")
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter", reliability="BEST_EFFORT"), version="1.2.0"))
    repo.commit("weaker")
    status, items = as_json(capsys, "base", "--against-system", "robot.system.yaml", TALKER)
    assert status == 1  # still BREAKING: not silently downgraded
    (weakened,) = [i for i in items if i["rule"] == "QOS_RELIABILITY_WEAKENED"]
    assert weakened["severity"] == "BREAKING" and weakened["message"].endswith("(no consumer in robot.system.yaml)")


def test_removing_the_only_publisher_a_system_subscribes_to_names_the_subscriber(repo, capsys):
    repo.write("robot.system.yaml", system_contract({"/listener": ("", endpoint("/chatter"))}))
    repo.commit("the system")
    repo.git("branch", "-f", "base")
    repo.write(TALKER, node_contract(publishers=endpoint("/other"), version="2.0.0"))
    repo.commit("no /chatter")
    status, items = as_json(capsys, "base")
    broken = [i for i in items if i["rule"] == "CONSUMER_INCOMPATIBLE"]
    assert broken and "the subscription of /listener in robot.system.yaml loses its only publisher" in broken[0]["message"]


def test_system_contracts_are_gated_too(repo, capsys):
    repo.write("robot.system.yaml", system_contract({"/listener": ("", endpoint("/chatter"))}, version="1.0.0"))
    repo.commit("the system")
    repo.git("branch", "-f", "base")
    repo.write("robot.system.yaml", system_contract({"/listener": ("", endpoint("/chatter", "std_msgs/msg/Int32"))},
                                                    version="1.1.0"))
    repo.commit("retyped subscription")
    status, items = as_json(capsys, "base")
    assert status == 1
    assert {i["rule"] for i in items} >= {"TYPE_CHANGED", "INTERFACE_VERSION_BUMP_MISSING"}
    assert {i["contract"] for i in items} == {"robot.system.yaml"}


# ---------------------------------------------------------------------------- the formats


def test_markdown_lists_breaking_changes_first_with_the_bump_they_need(repo, capsys):
    repo.write("contracts/a.interfaces.yaml", node_contract("/a", publishers=endpoint("/a")))
    repo.commit("a")
    repo.git("branch", "-f", "base")
    repo.write("contracts/a.interfaces.yaml", node_contract("/a", publishers=endpoint("/a") + endpoint("/b")))
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter", "std_msgs/msg/Int32"), version="1.3.0"))
    repo.commit("both")
    status, out, _ = gate(capsys, "base", "--format", "markdown")
    assert status == 1
    assert out.startswith("## Interface changes against base (")
    talker, a = out.index(f"### `{TALKER}`"), out.index("### `contracts/a.interfaces.yaml`")
    assert talker < a, out
    section = out[talker:a]
    assert section.index("**BREAKING**") < section.index("INTERFACE_VERSION_BUMP_MISSING")
    assert "write interface_version: 2.0.0" in section


def test_github_annotations_point_at_the_version_line(repo, capsys):
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter", "std_msgs/msg/Int32"), version="1.3.0",
                                     header="# the talker\n"))
    repo.commit("retype")
    status, out, _ = gate(capsys, "main", "--format", "github")
    assert status == 1
    assert f"::error file={TALKER},line=3,title=INTERFACE_VERSION_BUMP_MISSING (BREAKING)::" in out
    status, out, _ = gate(capsys, "main", "--format", "sarif")
    results = json.loads(out)["runs"][0]["results"]
    assert {r["ruleId"] for r in results} == {"INTERFACE_VERSION_BUMP_MISSING", "TYPE_CHANGED"}


def test_summary_appends_the_markdown(repo, capsys, tmp_path):
    summary = tmp_path / "summary.md"
    summary.write_text("# before\n")
    assert gate(capsys, "main", "--summary", str(summary))[0] == 0
    assert summary.read_text().startswith("# before\n## Interface changes against main")


# ---------------------------------------------------------------------------- one message each, exit 2


def test_a_ref_that_does_not_exist(repo, capsys):
    status, out, err = gate(capsys, "no-such-branch")
    assert status == 2 and out == ""
    assert err.startswith("rmw-introspect: revision 'no-such-branch' does not exist in this repository"), err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_a_two_dot_range_is_refused_with_what_to_give_instead(repo, capsys):
    status, _, err = gate(capsys, "main..HEAD")
    assert status == 2 and "give one (`main`), or `main...HEAD` for the merge base of the two" in err, err


def test_not_a_git_repository(tmp_path, monkeypatch, capsys):
    (tmp_path / "plain").mkdir()
    (tmp_path / "plain" / "t.interfaces.yaml").write_text(node_contract())
    monkeypatch.chdir(tmp_path / "plain")
    monkeypatch.setenv("GIT_CEILING_DIRECTORIES", str(tmp_path))
    status, _, err = gate(capsys, "main")
    assert status == 2 and "is not inside a git repository" in err and "diff OLD NEW" in err, err


def test_a_shallow_clone_without_the_base(repo, tmp_path, monkeypatch, capsys):
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter"), version="1.2.1"))
    base = repo.commit("one")
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter"), version="1.2.2"))
    repo.commit("two")
    clone = repo.shallow_clone(tmp_path / "clone", branch="feature")
    monkeypatch.chdir(clone.path)
    status, _, err = gate(capsys, base)
    assert status == 2
    assert "is not in this shallow clone" in err and "fetch-depth: 0" in err, err
    status, _, err = gate(capsys, f"{base}...HEAD")
    assert status == 2 and "shallow clone" in err, err


def test_a_contract_invalid_at_ref(repo, capsys):
    repo.write(TALKER, "contract_version: 1\nnodes:\n  /talker:\n    publishers: [{name: /chatter}]\n")
    repo.commit("broken")
    repo.git("branch", "-f", "broken")
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter")))
    repo.commit("fixed")
    status, _, err = gate(capsys, "broken")
    assert status == 2
    assert err.startswith(f"rmw-introspect: invalid contract broken:{TALKER}:4: "), err
    assert "This is the contract as it was at broken" in err


def test_a_named_file_that_exists_nowhere(repo, capsys):
    status, _, err = gate(capsys, "main", "contracts/nope.interfaces.yaml")
    assert status == 2 and "exists neither in the work tree nor at main" in err


def test_diff_without_against_still_takes_two_files(repo, capsys):
    assert main(["diff", TALKER]) == 2
    assert "diff compares two files, OLD and NEW (1 given)" in capsys.readouterr().err
    assert main(["diff", TALKER, TALKER, "--system", "x.system.yaml"]) == 2
    assert "--against-system go with --against REF" in capsys.readouterr().err
    assert main(["diff", TALKER, TALKER]) == 0


# ---------------------------------------------------------------------------- semantic versioning


def _item(severity: Severity) -> DriftItem:
    return DriftItem("/n", "publishers", "/t", "qos.depth", 1, 2, "R", severity, "m")


@pytest.mark.parametrize(("old", "new", "bump"), [
    ("1.2.3", "2.0.0", Bump.MAJOR), ("1.2.3", "1.3.0", Bump.MINOR), ("1.2.3", "1.2.4", Bump.PATCH),
    ("1.2.3", "1.2.3", Bump.NONE), ("0.3.1", "0.4.0", Bump.MAJOR), ("0.3.1", "0.3.2", Bump.MINOR),
    ("0.3.1", "1.0.0", Bump.MAJOR),
])
def test_the_bump_made(old, new, bump):
    assert interface_version.made(Version.parse(old), Version.parse(new)) is bump


@pytest.mark.parametrize(("version", "bump", "expected"), [
    ("1.2.3", Bump.MAJOR, "2.0.0"), ("1.2.3", Bump.MINOR, "1.3.0"), ("1.2.3", Bump.PATCH, "1.2.4"),
    ("0.3.1", Bump.MAJOR, "0.4.0"), ("0.3.1", Bump.MINOR, "0.3.2"),
])
def test_the_version_to_write(version, bump, expected):
    assert str(Version.parse(version).bumped(bump)) == expected


def test_a_safe_change_without_a_bump_is_a_note_and_a_patch_covers_it():
    judged = versioning.judge([_item(Severity.SAFE)], "1.0.0", "1.0.0", source="c")
    assert judged.findings == [] and judged.kept and "interface_version 1.0.1 would record them" in judged.notes[0]
    judged = versioning.judge([_item(Severity.SAFE)], "1.0.0", "1.0.1", source="c")
    assert not judged.kept and len(judged.accepted) == 1


def test_the_update_advice_says_it_cannot_know_the_base():
    assert interface_version.advice([_item(Severity.BREAKING)], "1.4.2") == (
        "interface_version 1.4.2 was not changed: this update holds BREAKING change(s), which need a MAJOR bump "
        "over the version at the base revision (an update cannot know it): write interface_version: 2.0.0, "
        "unless 1.4.2 already is such a bump over the base; `rmw-introspect diff --against BASE` (pytest --against "
        "BASE) decides (docs/ci.md)")
    assert interface_version.advice([], "1.4.2") is None and interface_version.advice([_item(Severity.SAFE)], None) is None


def test_a_malformed_version_is_refused_by_the_schema(tmp_path):
    with pytest.raises(ContractError, match="interface_version"):
        contract.loads(node_contract(version="1.2"), path="x.interfaces.yaml")
    assert contract.loads(node_contract(version="1.2.0")).interface_version == "1.2.0"


def test_the_project_s_rule_levels_apply_to_the_gate(repo, capsys):
    """Issue 49: `--rule` on `diff --against`: a level set by the project decides the version the
    change needs and is said with the finding; `off` is counted."""
    repo.write(TALKER, node_contract(publishers=endpoint("/chatter", depth=5), version="1.2.1"))
    repo.commit("depth 5")
    status, items = as_json(capsys, "main", "--rule", "QOS_DEPTH_*=note")
    assert status == 0, items
    assert [(i["rule"], i["severity"], i.get("level_set_by")) for i in items] == [
        ("QOS_DEPTH_DECREASED", "NOTE", "set by rules `QOS_DEPTH_*`: in command line")]
    status, out, err = gate(capsys, "main", "--rule", "QOS_DEPTH_DECREASED=off")
    assert status == 0, out + err
    assert "1 finding turned off by the project's rules" in out
    status, items = as_json(capsys, "main", "--rule", "INTERFACE_VERSION_BUMP_MISSING=risky")
    assert status == 0 and {i["rule"]: i["severity"] for i in items} == {
        "INTERFACE_VERSION_BUMP_MISSING": "RISKY", "QOS_DEPTH_DECREASED": "RISKY"}, items
    status, out, err = gate(capsys, "main", "--rule", "QOS_DEPTH_DECREASD=off")
    assert status == 2 and ("`rules`: unknown rule id QOS_DEPTH_DECREASD; the closest known rule id is "
                            "QOS_DEPTH_DECREASED") in err, out + err
