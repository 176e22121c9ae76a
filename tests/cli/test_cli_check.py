"""`rmw-introspect check` on real rclpy nodes: pass, drift, errors, json, target overrides, --update."""

from __future__ import annotations

import json

from cli_helpers import NODES
from sample_contracts import talker_contract, talker_depth_drift

from pytest_rmw_introspect.run import ros_env

TALKER = f"script: {NODES / 'talker.py'}"


def test_check_passes_when_the_capture_matches(cli):
    # a directory is every contract under it, found by its content whatever its name (issue 47)
    cli.write("contracts/talker.yaml", talker_contract(target=TALKER))
    cli.write("contracts/params.yaml", "/talker:\n  ros__parameters: {rate: 1.0}\n")
    result = cli("check", "contracts")
    assert result.returncode == 0, result
    assert result.stdout == "contracts/talker.yaml: matches (/talker)\n"
    assert "contracts: 1 contract (1 node contract); not contracts" in result.stderr, result
    assert "1 YAML file: params.yaml" in result.stderr, result
    (cli.path / "empty").mkdir()
    cli.write("empty/params.yaml", "/talker:\n  ros__parameters: {rate: 1.0}\n")
    nothing = cli("check", "empty")
    assert nothing.returncode == 2, nothing
    assert "check empty: no contract to check under it" in nothing.stderr and "params.yaml" in nothing.stderr, nothing


def test_check_reports_drift_with_exit_1_and_the_accept_command(cli):
    cli.write("talker.interfaces.yaml", talker_contract(target=TALKER, depth=3))
    result = cli("check", "talker.interfaces.yaml", "--param", "reliability:=best_effort")
    assert result.returncode == 1, result
    out = result.stdout
    assert out.startswith(f"Interface drift of script {NODES / 'talker.py'} against talker.interfaces.yaml: "
                          "3 changes (1 breaking, 1 risky, 1 safe)\nResult: FAIL (fail on: any)\n")
    assert "[QOS_RELIABILITY_WEAKENED] publisher offers weaker reliability RELIABLE -> BEST_EFFORT" in out
    assert "[QOS_DEPTH_INCREASED] depth 3 -> 10" in out
    # the contract lists the parameter's value under its target; -p changed it
    assert ("    parameter reliability\n      [PARAM_DEFAULT_CHANGED] default value 'reliable' -> 'best_effort'"
            in out)
    assert ("To accept these changes as the new contract, run:\n"
            "  rmw-introspect check --update --param reliability:=best_effort talker.interfaces.yaml\n") in out

    # below the threshold: reported, not failing
    safe_only = cli("check", "talker.interfaces.yaml", "--fail-on", "breaking")
    assert safe_only.returncode == 0, safe_only
    assert "Result: pass (fail on: breaking)" in safe_only.stdout
    assert "SAFE (1) - below the fail threshold (breaking), not failing" in safe_only.stdout


def test_check_json_has_one_object_per_drift_item(cli):
    cli.write("a.interfaces.yaml", talker_contract(target=TALKER, depth=3))
    cli.write("b.interfaces.yaml", talker_contract(target=TALKER))
    result = cli("check", "--format", "json", "a.interfaces.yaml", "b.interfaces.yaml")
    assert result.returncode == 1, result
    assert json.loads(result.stdout) == [talker_depth_drift("a.interfaces.yaml")]


def test_command_line_target_options_override_the_contract_target(cli):
    # the contract describes the talker run with depth 5 on /speech; its target block does not say so
    contract = talker_contract(target=TALKER, depth=5).replace("/chatter", "/speech")
    contract = contract.replace("      - name: depth\n        type: integer\n        default_value: 10\n",
                                "      - name: depth\n        type: integer\n        default_value: 5\n")
    cli.write("talker.interfaces.yaml", contract)
    assert cli("check", "talker.interfaces.yaml").returncode == 1
    result = cli("check", "talker.interfaces.yaml", "--param", "depth:=5", "--remap", "chatter:=speech")
    assert result.returncode == 0, result


def test_comparison_flags(cli):
    # the contract lists neither the subscription nor the real hash, and the wrong depth
    contract = talker_contract(target=TALKER + "\nparameters: {listen: /orders}", depth=3)
    contract = contract.replace("RIHS01_df66", "RIHS01_0000")
    cli.write("talker.interfaces.yaml", contract)
    drift = cli("check", "--format", "json", "talker.interfaces.yaml")
    assert drift.returncode == 1, drift
    assert {item["rule"] for item in json.loads(drift.stdout)} == {
        "SUB_ADDED", "TYPE_HASH_CHANGED", "QOS_DEPTH_INCREASED", "PARAM_DEFAULT_CHANGED"}, drift.stdout
    quiet = cli("check", "talker.interfaces.yaml", "--allow-extra", "--ignore-type-hash", "--ignore-qos", "depth",
                "--ignore-parameter-values", "listen")
    assert quiet.returncode == 0, quiet
    assert cli("check", "talker.interfaces.yaml", "--allow-extra", "--ignore-type-hash", "--ignore-qos", "depth",
               "--ignore-parameters", "lis*,other").returncode == 0


def test_check_update_rewrites_the_drifted_contract_and_keeps_its_header(cli):
    header = "# Owned by team demo.\n"
    cli.write("talker.interfaces.yaml", talker_contract(target=TALKER, depth=3, header=header))
    refused = cli("check", "--update", "talker.interfaces.yaml", env={"CI": "true"})
    assert refused.returncode == 2, refused
    assert "--update refuses to write golden contracts in CI" in refused.stderr
    assert cli.read("talker.interfaces.yaml") == talker_contract(target=TALKER, depth=3, header=header)

    (cli.path / "talker.interfaces.yaml").chmod(0o444)  # read-only: refused, not replaced
    read_only = cli("check", "--update", "talker.interfaces.yaml")
    assert read_only.returncode == 2, read_only
    assert "cannot write talker.interfaces.yaml: it is read-only (mode 0444" in read_only.stderr, read_only
    assert cli.read("talker.interfaces.yaml") == talker_contract(target=TALKER, depth=3, header=header)
    (cli.path / "talker.interfaces.yaml").chmod(0o644)

    updated = cli("check", "--update", "talker.interfaces.yaml")
    assert updated.returncode == 0, updated
    assert "updated talker.interfaces.yaml" in updated.stderr
    assert cli.read("talker.interfaces.yaml") == talker_contract(target=TALKER, depth=10, header=header)
    # a file that records its distribution has it kept up to date: the nodes were captured here
    distribution = ros_env.detect().distro
    cli.write("talker.interfaces.yaml", talker_contract(target=TALKER, depth=3, header=header, distribution="rolling"))
    assert cli("check", "--update", "talker.interfaces.yaml").returncode == 0
    assert cli.read("talker.interfaces.yaml") == talker_contract(target=TALKER, depth=10, header=header,
                                                                 distribution=distribution)
    assert cli("check", "talker.interfaces.yaml").returncode == 0


def test_check_update_creates_a_missing_contract_with_a_target_block(cli):
    result = cli("check", "--update", "--script", NODES / "talker.py", "new.interfaces.yaml")
    assert result.returncode == 0, result
    assert "created new.interfaces.yaml" in result.stderr
    text = cli.read("new.interfaces.yaml")
    assert f"target:\n  script: {NODES / 'talker.py'}\n" in text
    again = cli("check", "new.interfaces.yaml")
    assert again.returncode == 0, again


def test_check_errors_exit_2_with_a_message(cli):
    cli.write("bad.interfaces.yaml", "contract_version: 1\nnodes: [\n")
    cli.write("notarget.interfaces.yaml", talker_contract())
    cli.write("crash.interfaces.yaml", talker_contract(target=f"script: {NODES / 'crashing_node.py'}"))
    cli.write("badkey.interfaces.yaml", talker_contract(target="scrpt: x.py"))
    cases = {
        "missing.interfaces.yaml": "invalid contract missing.interfaces.yaml: the file does not exist",
        "bad.interfaces.yaml": "invalid contract bad.interfaces.yaml:3: YAML syntax error",
        "notarget.interfaces.yaml": "notarget.interfaces.yaml has no `target:` block naming what to run",
        "crash.interfaces.yaml": "crashed: it exited with status 1 while it was captured",
        "badkey.interfaces.yaml": "invalid contract badkey.interfaces.yaml",
    }
    for name, message in cases.items():
        result = cli("check", name)
        assert result.returncode == 2, (name, str(result))
        assert message in result.stderr, (name, str(result))
        assert "Traceback (most recent call last):\n  File \"/work" not in result.stderr.split("Last lines")[0]
        assert result.stdout == "", (name, str(result))
    assert cli("check", "--fail-on", "sometimes", "x.yaml").returncode == 2


def test_an_error_in_one_contract_wins_over_drift_in_another(cli):
    cli.write("drift.interfaces.yaml", talker_contract(target=TALKER, depth=3))
    result = cli("check", "missing.interfaces.yaml", "drift.interfaces.yaml")
    assert result.returncode == 2, result
    assert "missing.interfaces.yaml: the file does not exist" in result.stderr
    assert "[QOS_DEPTH_INCREASED]" in result.stdout  # the other contract was still checked


def test_include_ros_infra_round_trip(cli):
    captured = cli("capture", "--include-ros-infra", "--script", NODES / "talker.py", "-o", "infra.interfaces.yaml")
    assert captured.returncode == 0, captured
    assert "/rosout" in cli.read("infra.interfaces.yaml")
    # the contract says include_infrastructure: true, so the check captures the infrastructure too
    assert cli("check", "infra.interfaces.yaml").returncode == 0

    cli.write("plain.interfaces.yaml", talker_contract(target=TALKER))
    result = cli("check", "--format", "json", "--include-ros-infra", "plain.interfaces.yaml")
    assert result.returncode == 1, result
    added = {(i["kind"], i["name"]) for i in json.loads(result.stdout) if i["change"] == "added"}
    assert ("publishers", "/rosout") in added
    assert ("service_servers", "/talker/get_parameters") in added


def test_a_setup_error_is_exit_2_with_its_message(cli):
    cli.write("talker.interfaces.yaml", talker_contract(target=TALKER))
    broken = {"RMW_INTROSPECT_LIBRARY": str(cli.path / "missing" / "librmw_introspect_cpp.so")}
    for args in (("check", "talker.interfaces.yaml"), ("capture", "--script", NODES / "talker.py")):
        result = cli(*args, env=broken)
        assert result.returncode == 2, result
        assert "RMW_INTROSPECT_LIBRARY points at" in result.stderr, result
        assert "Traceback" not in result.stderr


def test_check_in_the_ci_formats(cli):
    cli.write("talker.interfaces.yaml", talker_contract(target=TALKER, depth=3))
    cli.write("good.interfaces.yaml", talker_contract(target=TALKER))
    cli.write("broken.interfaces.yaml", "contract_version: 1\nnodes: {talker: {}}\n")
    contracts = ("talker.interfaces.yaml", "good.interfaces.yaml", "broken.interfaces.yaml")
    md = cli("check", *contracts, "--format", "markdown")
    assert md.returncode == 2, md  # an error wins over drift
    assert md.stdout.startswith("## Interface contracts: 2 of 3 failing\n"), md
    assert "| `talker.interfaces.yaml` | `/talker` | ❌ 0 breaking, 0 risky, 1 safe |" in md.stdout
    assert "| `good.interfaces.yaml` | `/talker` | ✅ matches |" in md.stdout
    assert "| `broken.interfaces.yaml` | - | 🛑 error: invalid contract broken.interfaces.yaml:2: " in md.stdout
    gh = cli("check", "talker.interfaces.yaml", "--format", "github", "--fail-on", "breaking")
    assert gh.returncode == 0, gh
    assert gh.stdout == ("::notice file=talker.interfaces.yaml,line=7,title=QOS_DEPTH_INCREASED (SAFE)::"
                         "/talker publisher /chatter: depth 3 -> 10: more samples are queued; matching is unaffected\n"), gh
    sarif = cli("check", *contracts, "--format", "sarif", "--fail-on", "breaking")
    assert sarif.returncode == 2, sarif
    results = json.loads(sarif.stdout)["runs"][0]["results"]
    assert [(r["ruleId"], r["level"], r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"])
            for r in results] == [("QOS_DEPTH_INCREASED", "note", "talker.interfaces.yaml"),
                                  ("CONTRACT_NOT_CHECKED", "error", "broken.interfaces.yaml")]
    assert results[0]["locations"][0]["physicalLocation"]["region"] == {"startLine": 7}


def test_accepted_drift_passes_and_says_so_and_a_stale_entry_is_reported(cli):
    accept = ("accept:\n"
              "  - rule: QOS_DEPTH_INCREASED\n    name: /chatter\n    reason: the queue grew on purpose (issue 12)\n")
    cli.write("talker.interfaces.yaml", talker_contract(target=TALKER, depth=3, header=accept))
    result = cli("check", "talker.interfaces.yaml")
    assert result.returncode == 0, result
    assert result.stdout == "talker.interfaces.yaml: matches (/talker); 1 finding(s) accepted in the contract\n"
    as_json = json.loads(cli("check", "talker.interfaces.yaml", "--format", "json").stdout)
    assert [(i["rule"], i["accepted"]["reason"]) for i in as_json] == [
        ("QOS_DEPTH_INCREASED", "the queue grew on purpose (issue 12)")]
    # the drift is gone (depth 10 again): the entry is stale, reported but not failing
    cli.write("talker.interfaces.yaml", talker_contract(target=TALKER, header=accept))
    stale = cli("check", "talker.interfaces.yaml")
    assert stale.returncode == 0, stale
    assert "STALE ACCEPTANCES (1)" in stale.stdout
    assert "talker.interfaces.yaml:2: QOS_DEPTH_INCREASED name /chatter" in stale.stdout
    # a typo in a rule id is an error naming the entry
    cli.write("talker.interfaces.yaml", talker_contract(target=TALKER, header=accept.replace("INCREASED", "INCRAESED")))
    typo = cli("check", "talker.interfaces.yaml")
    assert typo.returncode == 2 and "talker.interfaces.yaml:2" in typo.stderr and "unknown rule" in typo.stderr, typo


def test_check_with_a_baseline_fails_only_on_new_drift(cli):
    cli.write("talker.interfaces.yaml", talker_contract(target=TALKER, depth=3))
    written = cli("check", "talker.interfaces.yaml", "--write-baseline", "interfaces.baseline.json")
    assert written.returncode == 0, written
    assert "wrote the baseline interfaces.baseline.json (1 finding(s))" in written.stderr
    known = cli("check", "talker.interfaces.yaml", "--baseline", "interfaces.baseline.json")
    assert known.returncode == 0, known
    assert known.stdout == "talker.interfaces.yaml: matches (/talker); 1 finding(s) in the baseline\n"
    new = cli("check", "talker.interfaces.yaml", "--baseline", "interfaces.baseline.json",
              "--param", "reliability:=best_effort")
    assert new.returncode == 1, new
    failing = new.stdout.split("ACCEPTED")[0]
    assert "QOS_RELIABILITY_WEAKENED" in failing and "QOS_DEPTH_INCREASED" not in failing


def test_the_shards_of_a_check_together_are_the_unsharded_check(cli):
    names = [f"t{i}.interfaces.yaml" for i in range(3)]
    for i, name in enumerate(names):  # each drifts in its own way: depth 1, 2, 3 against the node's 10
        cli.write(name, talker_contract(target=TALKER, depth=i + 1))
    whole = cli("check", *names, "--format", "json", timeout=180)
    assert whole.returncode == 1, whole
    shards = [cli("check", *reversed(names), "--shard", f"{i}/2", "--format", "json", timeout=180) for i in (1, 2)]
    assert [s.stderr.count("shard ") for s in shards] == [1, 1]
    assert "shard 1/2: 2 of 3 contract(s)" in shards[0].stderr and "shard 2/2: 1 of 3 contract(s)" in shards[1].stderr
    def key(item):
        return json.dumps(item, sort_keys=True)
    union = sorted((i for s in shards for i in json.loads(s.stdout)), key=key)
    assert union == sorted(json.loads(whole.stdout), key=key)
    assert {i["contract"] for i in json.loads(shards[1].stdout)} == {"t1.interfaces.yaml"}
    bad = cli("check", *names, "--shard", "3/2")
    assert bad.returncode == 2 and "--shard 3/2: I must be between 1 and N" in bad.stderr, bad
    partial = cli("check", *names, "--shard", "1/2", "--write-baseline", "b.json")
    assert partial.returncode == 2 and "write the baseline from a run over every contract" in partial.stderr, partial


def test_check_update_never_changes_the_interface_version_but_says_which_bump_it_needs(cli):
    versioned = "# versioned\ninterface_version: 1.4.2\n"
    cli.write("talker.interfaces.yaml", talker_contract(target=TALKER, depth=20, header=versioned))
    updated = cli("check", "--update", "talker.interfaces.yaml")
    assert updated.returncode == 0, updated
    assert ("note: talker.interfaces.yaml: interface_version 1.4.2 was not changed: this update holds RISKY "
            "change(s), which need a MINOR bump over the version at the base revision (an update cannot know it): "
            "write interface_version: 1.5.0, unless 1.4.2 already is such a bump over the base") in updated.stderr, \
        updated.stderr
    assert cli.read("talker.interfaces.yaml") == talker_contract(target=TALKER, depth=10, header=versioned)


def test_the_project_sets_the_level_of_a_rule(cli):
    """Issue 49: `rules:` in the contract's options and `--rule RULE=LEVEL` (stronger, key by key):
    a level the project set is said with the finding, `off` is counted, and a rule id that does
    not exist is an error naming where it was set and the closest id."""
    options = "options:\n  rules: {QOS_DEPTH_*: note}\n"
    cli.write("talker.interfaces.yaml", talker_contract(target=TALKER, depth=3).replace("nodes:", options + "nodes:", 1))
    noted = cli("check", "talker.interfaces.yaml")
    assert noted.returncode == 0, noted
    assert "talker.interfaces.yaml: 1 change (0 breaking, 0 risky, 0 safe, 1 note)" in noted.stdout, noted
    assert "NOTE (1) - notes, never failing" in noted.stdout
    assert ("[QOS_DEPTH_INCREASED] depth 3 -> 10: more samples are queued; matching is unaffected (NOTE, set by "
            "rules `QOS_DEPTH_*`: in talker.interfaces.yaml: options)") in noted.stdout, noted

    off = cli("check", "talker.interfaces.yaml", "--rule", "QOS_DEPTH_INCREASED=off", "--rule", "SUB_ADDED=breaking",
              "--format", "json")
    assert off.returncode == 0 and json.loads(off.stdout) == [], off
    said = cli("check", "talker.interfaces.yaml", "--rule", "QOS_DEPTH_INCREASED=off")
    assert said.stdout == ("talker.interfaces.yaml: matches (/talker); 1 finding turned off by the project's "
                           "rules\n"), said
    risky = cli("check", "talker.interfaces.yaml", "--rule", "QOS_DEPTH_INCREASED=risky", "--format", "json")
    assert risky.returncode == 1, risky
    [item] = json.loads(risky.stdout)
    assert (item["severity"], item["level_set_by"]) == ("RISKY", "set by rules: in command line"), item

    unknown = cli("check", "talker.interfaces.yaml", "--rule", "QOS_DEPTH_INCREASD=off")
    assert unknown.returncode == 2, unknown
    assert ("command line: `rules`: unknown rule id QOS_DEPTH_INCREASD; the closest known rule id is "
            "QOS_DEPTH_INCREASED") in unknown.stderr, unknown
    cli.write("bad.interfaces.yaml", talker_contract(target=TALKER).replace(
        "nodes:", "options:\n  rules: {QOS_DEPTH_INCREASED: loud}\nnodes:", 1))
    bad = cli("check", "bad.interfaces.yaml")
    assert bad.returncode == 2, bad
    assert ("invalid contract bad.interfaces.yaml:5: at options.rules.QOS_DEPTH_INCREASED: 'loud' is not one of: "
            "off, note, safe, risky, breaking") in bad.stderr and "Traceback" not in bad.stderr, bad
