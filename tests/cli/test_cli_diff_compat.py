"""`rmw-introspect diff` and `compat` on hand-written contracts (nothing is run), and --help."""

from __future__ import annotations

import json

import pytest
from sample_contracts import chatter, talker_contract

LISTENER = "contract_version: 1\nnodes:\n  /listener:\n    subscriptions:\n" + chatter(type_hash=False) + """\
      - name: /orders
        type: std_msgs/msg/String
        qos: default
"""


def test_diff_of_equal_contracts(cli_nodes_only):
    cli = cli_nodes_only
    cli.write("old.yaml", talker_contract())
    cli.write("new.yaml", talker_contract(header="# same nodes, another header\n"))
    result = cli("diff", "old.yaml", "new.yaml")
    assert result.returncode == 0, result
    assert result.stdout == "Interface drift of new.yaml: no drift against old.yaml.\n"


def test_diff_reports_drift_with_the_check_rules(cli_nodes_only):
    cli = cli_nodes_only
    cli.write("old.yaml", talker_contract())
    cli.write("new.yaml", talker_contract(reliability="BEST_EFFORT").replace("/chatter", "/speech"))
    result = cli("diff", "old.yaml", "new.yaml")
    assert result.returncode == 1, result
    # the rename does not hide the weaker reliability of the renamed publisher
    assert "Interface drift of new.yaml against old.yaml: 2 changes (2 breaking, 0 risky, 0 safe)" in result.stdout
    assert "[PUB_RENAMED] publisher /chatter looks renamed to /speech" in result.stdout
    assert "[QOS_RELIABILITY_WEAKENED] publisher offers weaker reliability RELIABLE -> BEST_EFFORT" in result.stdout
    assert "To accept" not in result.stdout

    as_json = cli("diff", "--format", "json", "old.yaml", "new.yaml")
    assert as_json.returncode == 1
    items = json.loads(as_json.stdout)
    assert [(i["rule"], i["severity"], i["name"], i["change"], i["contract"]) for i in items] == [
        ("PUB_RENAMED", "BREAKING", "/chatter", "renamed", "old.yaml"),
        ("QOS_RELIABILITY_WEAKENED", "BREAKING", "/speech", "qos.reliability", "old.yaml"),
    ]
    assert items[0]["new"]["name"] == "/speech"


def test_diff_options(cli_nodes_only):
    cli = cli_nodes_only
    cli.write("old.yaml", talker_contract())
    cli.write("new.yaml", talker_contract(depth=20))
    assert cli("diff", "old.yaml", "new.yaml").returncode == 1
    assert cli("diff", "old.yaml", "new.yaml", "--fail-on", "risky").returncode == 0
    ignored = cli("diff", "old.yaml", "new.yaml", "--ignore-qos", "all")
    assert ignored.returncode == 0
    assert "no drift" in ignored.stdout
    # the old contract's options block applies
    cli.write("old2.yaml", talker_contract().replace("nodes:", "options: {fail_on: breaking}\nnodes:"))
    assert cli("diff", "old2.yaml", "new.yaml").returncode == 0


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("diff", "old.yaml", "missing.yaml"), "invalid contract missing.yaml: the file does not exist"),
        (("diff", "old.yaml", "bad.yaml"), "invalid contract bad.yaml:2"),
        (("diff", "old.yaml"), "diff compares two files, OLD and NEW (1 given)"),
        (("diff", "old.yaml", "old.yaml", "--ignore-qos", "colour"), "names unknown QoS field(s) colour"),
        (("compat", "old.yaml", "missing.yaml"), "invalid contract missing.yaml: the file does not exist"),
        (("compat",), "the following arguments are required: CONTRACT"),
        (("diff", "old.yaml", "old.yaml", "--", "ls"), "`-- COMMAND` is only for capture and check, not diff"),
        (("frobnicate",), "invalid choice: 'frobnicate'"),
        ((), "the following arguments are required: COMMAND"),
    ],
)
def test_bad_input_exits_2_with_a_message(cli_nodes_only, args, message):
    cli = cli_nodes_only
    cli.write("old.yaml", talker_contract())
    cli.write("bad.yaml", "contract_version: 1\nnodes: {/x: [}\n")
    result = cli(*args)
    assert result.returncode == 2, result
    assert message in result.stderr, result
    assert "Traceback" not in result.stderr
    assert result.stdout == ""


def test_compat_finds_incompatible_qos_and_a_missing_publisher(cli_nodes_only):
    cli = cli_nodes_only
    cli.write("talker.yaml", talker_contract(reliability="BEST_EFFORT"))
    cli.write("listener.yaml", LISTENER)
    result = cli("compat", "talker.yaml", "listener.yaml")
    assert result.returncode == 1, result
    out = result.stdout
    assert "Compatibility check of 2 contract(s): 2 problems (1 breaking, 1 risky, 0 safe)" in out
    assert ("[QOS_INCOMPATIBLE] publisher of /talker (talker.yaml) -> subscription of /listener (listener.yaml): "
            in out)
    assert "[SUBSCRIPTION_WITHOUT_PUBLISHER] subscription of /listener (listener.yaml): no publisher" in out

    as_json = cli("compat", "--format", "json", "talker.yaml", "listener.yaml")
    assert as_json.returncode == 1
    items = json.loads(as_json.stdout)
    assert [(i["rule"], i["severity"], i["name"]) for i in items] == [
        ("QOS_INCOMPATIBLE", "BREAKING", "/chatter"),
        ("SUBSCRIPTION_WITHOUT_PUBLISHER", "RISKY", "/orders"),
    ]
    assert items[0]["provider"] == {"label": "talker.yaml", "node": "/talker", "kind": "publishers"}
    assert items[1]["provider"] is None


def test_compat_threshold(cli_nodes_only):
    cli = cli_nodes_only
    cli.write("talker.yaml", talker_contract())  # reliable: compatible with the listener
    cli.write("listener.yaml", LISTENER)
    default = cli("compat", "talker.yaml", "listener.yaml")
    assert default.returncode == 0, default  # only the RISKY missing publisher, default fail-on breaking
    assert "Result: pass (fail on: breaking)" in default.stdout
    assert "[SUBSCRIPTION_WITHOUT_PUBLISHER]" in default.stdout
    assert cli("compat", "--fail-on", "risky", "talker.yaml", "listener.yaml").returncode == 1
    alone = cli("compat", "talker.yaml")
    assert alone.returncode == 0
    assert alone.stdout == "Compatibility check of 1 contract(s): all contracts fit together.\n"


@pytest.mark.parametrize(
    ("command", "expected"),
    [
        (("--help",), ["capture", "check", "diff", "compat", "exit status: 0"]),
        (("capture", "--help"), ["--package P", "--executable E", "--script FILE", "--module M",
                                 "-- COMMAND ARGS", "--namespace", "--node-name", "--remap FROM:=TO",
                                 "--param NAME:=VALUE", "--params-file", "--env K=V", "--settle SECONDS",
                                 "--timeout SECONDS", "{yaml,json,nodl}", "--raw", "--include-ros-infra",
                                 "-o FILE", "NoDL v2"]),
        (("check", "--help"), ["CONTRACT", "--update", "--fail-on {any,risky,breaking}", "--ignore-type-hash",
                               "--ignore-qos FIELDS", "--allow-extra", "--include-ros-infra", "--format {text,json,markdown,github,sarif,junit}",
                               "refused when the CI environment variable is set", "2 errors"]),
        (("diff", "--help"), ["OLD", "NEW", "--fail-on", "--format"]),
        (("compat", "--help"), ["CONTRACT", "--fail-on", "--strict-system-default", "--format"]),
    ],
)
def test_help_documents_every_option(cli_nodes_only, command, expected):
    result = cli_nodes_only(*command)
    assert result.returncode == 0, result
    text = " ".join(result.stdout.split())  # argparse wraps lines
    for word in expected:
        assert " ".join(word.split()) in text, word


def test_diff_and_compat_in_the_ci_formats(cli_nodes_only):
    cli = cli_nodes_only
    cli.write("old.yaml", talker_contract())
    cli.write("new.yaml", talker_contract(depth=5))
    md = cli("diff", "old.yaml", "new.yaml", "--format", "markdown")
    assert md.returncode == 1, md
    assert md.stdout.startswith("## Interface drift of new.yaml: 1 of 1 failing\n")
    assert "| `new.yaml` | `/talker` | ❌ 0 breaking, 1 risky, 0 safe |" in md.stdout
    gh = cli("diff", "old.yaml", "new.yaml", "--format", "github")
    assert gh.returncode == 1, gh
    # the annotation points at the publisher's entry in the file the pull request changed
    assert gh.stdout.startswith("::error file=new.yaml,line=5,title=QOS_DEPTH_DECREASED (RISKY)::/talker publisher /chatter")
    cli.write("listener.yaml", LISTENER)
    compat = cli("compat", "new.yaml", "listener.yaml", "--format", "github", "--fail-on", "risky")
    assert compat.returncode == 1, compat
    assert "::error file=listener.yaml,line=" in compat.stdout and "SUBSCRIPTION_WITHOUT_PUBLISHER" in compat.stdout
    compat_md = cli("compat", "new.yaml", "listener.yaml", "--format", "markdown")
    assert compat_md.stdout.startswith("## Compatibility check of 2 contract(s): pass\n"), compat_md


def test_validate_checks_files_without_running_anything(cli_nodes_only):
    cli = cli_nodes_only
    cli.write("good.interfaces.yaml", talker_contract(target="script: does_not_exist.py"))
    cli.write("bad.interfaces.yaml", "contract_version: 1\nnodes:\n  /talker:\n    publishers: 3\n")
    ok = cli("validate", "good.interfaces.yaml")
    assert (ok.returncode, ok.stdout) == (0, "good.interfaces.yaml: valid (/talker)\n"), ok
    bad = cli("validate", "good.interfaces.yaml", "bad.interfaces.yaml")
    assert bad.returncode == 2, bad
    assert "bad.interfaces.yaml:4" in bad.stderr and "Traceback" not in bad.stderr
    gh = cli("validate", "bad.interfaces.yaml", "--format", "github")
    assert gh.returncode == 2 and gh.stdout.startswith("::error file=bad.interfaces.yaml,line=4,title=invalid contract::"), gh
    cli.write("typo.interfaces.yaml", "accept:\n  - {rule: PUB_RENOVED, reason: r}\n" + talker_contract())
    typo = cli("validate", "typo.interfaces.yaml")
    assert typo.returncode == 2 and "typo.interfaces.yaml:2" in typo.stderr and "unknown rule PUB_RENOVED" in typo.stderr


def test_validate_reads_system_contracts_as_every_other_command_does(cli_nodes_only):
    cli = cli_nodes_only
    cli.write("node.system.yaml", talker_contract())  # a node contract, named as a system contract
    cli.write("broken.system.yaml", "system_version: 1\nlaunch: {path: robot.launch.xml}\nprocesses:\n"
                                    "  - {executable: talker, nodes: [/talker]}\nnodes: {}\n")
    cli.write("sniffed.yaml", "system_version: 1\nlaunch: {path: robot.launch.xml}\nprocesses: []\nnodes: {}\n")
    valid = cli("validate", "sniffed.yaml")
    assert (valid.returncode, valid.stdout) == (0, "sniffed.yaml: valid system contract (0 processes: no nodes)\n"), valid
    misnamed = cli("validate", "node.system.yaml")
    assert misnamed.returncode == 2, misnamed
    said = ("invalid contract node.system.yaml:1: this is a node contract (it says `contract_version`), but a name "
            "ending in .system.yaml marks a system contract: rename it to NAME.interfaces.yaml")
    assert said in misnamed.stderr, misnamed
    assert said in cli("diff", "node.system.yaml", "node.system.yaml").stderr  # the same words as the others
    broken = cli("validate", "broken.system.yaml", "--format", "github")
    assert broken.returncode == 2 and broken.stdout.startswith(
        "::error file=broken.system.yaml,line=4,title=invalid contract::node /talker is not listed under `nodes:`"), broken


def test_every_contract_of_the_repository_passes_the_pre_commit_hook(cli_nodes_only):
    """The hook's `files` pattern over the repository's files (the example package's system
    contract among them), validated as the hook runs it."""
    import pathlib
    import re
    import subprocess

    import yaml

    root = pathlib.Path(__file__).resolve().parents[2]
    (hook,) = yaml.safe_load((root / ".pre-commit-hooks.yaml").read_text())
    files = subprocess.run(["git", "ls-files"], cwd=root, capture_output=True, text=True, check=True).stdout.split()
    contracts = [f for f in files if re.search(hook["files"], f)]
    assert "examples/rmw_introspect_examples/contracts/robot.system.yaml" in contracts
    result = cli_nodes_only(*hook["entry"].split()[1:], *contracts, cwd=root)
    assert result.returncode == 0, result
    assert ("examples/rmw_introspect_examples/contracts/robot.system.yaml: valid system contract (7 processes: "
            "/robot1/lidar, ") in result.stdout


def test_the_pre_commit_hook_runs_validate_on_contract_files():
    import pathlib
    import re

    import yaml

    root = pathlib.Path(__file__).resolve().parents[2]
    (hook,) = yaml.safe_load((root / ".pre-commit-hooks.yaml").read_text())
    assert hook["id"] == "rmw-introspect-validate" and hook["entry"] == "rmw-introspect validate"
    assert hook["language"] == "python"
    pattern = re.compile(hook["files"])
    assert pattern.search("contracts/talker.interfaces.yaml") and pattern.search("robot.system.yaml")
    assert pattern.search("nodl/camera.nodl.yaml")
    assert not pattern.search("params.yaml")
    assert 'rmw-introspect = "pytest_rmw_introspect.cli:main"' in (root / "pyproject.toml").read_text()


def test_diff_compat_and_validate_in_sarif(cli_nodes_only):
    cli = cli_nodes_only
    cli.write("old.yaml", talker_contract())
    cli.write("new.yaml", talker_contract(depth=5))
    cli.write("listener.yaml", LISTENER)
    cli.write("bad.interfaces.yaml", "contract_version: 1\nnodes:\n  /talker:\n    publishers: 3\n")
    diff = cli("diff", "old.yaml", "new.yaml", "--format", "sarif")
    assert diff.returncode == 1, diff
    log = json.loads(diff.stdout)
    assert log["version"] == "2.1.0"
    (result,) = log["runs"][0]["results"]
    assert result["ruleId"] == "QOS_DEPTH_DECREASED" and result["level"] == "error"
    assert result["locations"][0]["physicalLocation"] == {
        "artifactLocation": {"uri": "new.yaml", "uriBaseId": "%SRCROOT%"}, "region": {"startLine": 5}}
    assert log["runs"][0]["originalUriBaseIds"]["%SRCROOT%"]["uri"] == cli.path.as_uri() + "/"
    compat = cli("compat", "new.yaml", "listener.yaml", "--format", "sarif")
    assert compat.returncode == 0, compat  # RISKY problems, below the default threshold
    results = json.loads(compat.stdout)["runs"][0]["results"]
    orders = next(r for r in results if r["ruleId"] == "SUBSCRIPTION_WITHOUT_PUBLISHER")
    assert orders["level"] == "warning"
    assert orders["locations"][0]["physicalLocation"] == {
        "artifactLocation": {"uri": "listener.yaml", "uriBaseId": "%SRCROOT%"}, "region": {"startLine": 8}}
    valid = cli("validate", "new.yaml", "bad.interfaces.yaml", "--format", "sarif")
    assert valid.returncode == 2, valid
    run = json.loads(valid.stdout)["runs"][0]
    (invalid,) = run["results"]
    assert invalid["ruleId"] == "CONTRACT_INVALID" and "publishers" in invalid["message"]["text"]
    assert invalid["locations"][0]["physicalLocation"]["region"] == {"startLine": 4}
    assert run["invocations"] == [{"executionSuccessful": False}]


def test_compat_accepts_what_a_contract_accepts_and_reports_stale_entries(cli_nodes_only):
    cli = cli_nodes_only
    cli.write("talker.yaml", talker_contract())
    cli.write("listener.yaml", "accept:\n"
              "  - {rule: SUBSCRIPTION_WITHOUT_PUBLISHER, name: /orders, reason: 'published by the shop, not launched'}\n"
              "  - {rule: CLIENT_WITHOUT_SERVER, reason: 'no client any more'}\n" + LISTENER)
    result = cli("compat", "talker.yaml", "listener.yaml", "--fail-on", "risky")
    assert result.returncode == 0, result
    assert "ACCEPTED (1)" in result.stdout and "published by the shop, not launched" in result.stdout
    assert "STALE ACCEPTANCES (1)" in result.stdout and "listener.yaml:3: CLIENT_WITHOUT_SERVER" in result.stdout
    sarif_log = json.loads(cli("compat", "talker.yaml", "listener.yaml", "--format", "sarif").stdout)
    results = sarif_log["runs"][0]["results"]
    assert [(r["ruleId"], "suppressions" in r) for r in results] == [
        ("SUBSCRIPTION_WITHOUT_PUBLISHER", True), ("ACCEPTANCE_STALE", False)]
    # without the entry, the same problem fails at risky
    cli.write("listener.yaml", LISTENER)
    assert cli("compat", "talker.yaml", "listener.yaml", "--fail-on", "risky").returncode == 1


def test_compat_with_a_baseline_fails_only_on_new_problems(cli_nodes_only):
    cli = cli_nodes_only
    cli.write("talker.yaml", talker_contract())
    cli.write("listener.yaml", LISTENER)
    written = cli("compat", "talker.yaml", "listener.yaml", "--fail-on", "risky", "--write-baseline", "b.json")
    assert written.returncode == 0, written  # today's problems are what the baseline records
    assert "wrote the baseline b.json (1 finding(s))" in written.stderr
    assert [f["rule"] for f in json.loads(cli.read("b.json"))["findings"]] == ["SUBSCRIPTION_WITHOUT_PUBLISHER"]
    known = cli("compat", "talker.yaml", "listener.yaml", "--fail-on", "risky", "--baseline", "b.json")
    assert known.returncode == 0, known
    assert "ACCEPTED (1)" in known.stdout and "in the baseline" in known.stdout
    cli.write("listener.yaml", LISTENER + "      - name: /refunds\n        type: std_msgs/msg/String\n")
    new = cli("compat", "talker.yaml", "listener.yaml", "--fail-on", "risky", "--baseline", "b.json")
    assert new.returncode == 1, new
    assert new.stdout.split("ACCEPTED")[0].count("SUBSCRIPTION_WITHOUT_PUBLISHER") == 1  # /refunds only
    assert "/refunds" in new.stdout.split("ACCEPTED")[0]
    cli.write("listener.yaml", "contract_version: 1\nnodes:\n  /l:\n    subscriptions:\n"
                               "      - {name: /chatter, type: std_msgs/msg/String}\n")
    fixed = cli("compat", "talker.yaml", "listener.yaml", "--baseline", "b.json")
    assert fixed.returncode == 0 and "note: 1 finding(s) of the baseline b.json are gone" in fixed.stderr, fixed
    both = cli("compat", "talker.yaml", "--baseline", "b.json", "--write-baseline", "b.json")
    assert both.returncode == 2 and "not both" in both.stderr, both
    missing = cli("compat", "talker.yaml", "--baseline", "nowhere.json")
    assert missing.returncode == 2 and "baseline nowhere.json: the file does not exist" in missing.stderr, missing


def test_diff_takes_the_project_s_rule_levels(cli_nodes_only):
    """Issue 49: `diff --rule` and the old contract's `rules:`, as a check takes them."""
    cli = cli_nodes_only
    cli.write("old.yaml", talker_contract().replace("nodes:", "options: {rules: {PUB_RENAMED: risky}}\nnodes:"))
    cli.write("new.yaml", talker_contract(reliability="BEST_EFFORT").replace("/chatter", "/speech"))
    result = cli("diff", "old.yaml", "new.yaml", "--rule", "QOS_RELIABILITY_*=off", "--fail-on", "breaking")
    assert result.returncode == 0, result
    assert "[PUB_RENAMED] publisher /chatter looks renamed to /speech" in result.stdout, result
    assert "stop receiving data (RISKY, set by rules: in old.yaml: options)\n" in result.stdout, result
    assert "1 finding turned off by the project's rules" in result.stdout
    bad = cli("diff", "old.yaml", "new.yaml", "--rule", "QOS_RELIABILITY_WEAKEND=off")
    assert bad.returncode == 2 and ("`rules`: unknown rule id QOS_RELIABILITY_WEAKEND; the closest known rule id "
                                    "is QOS_RELIABILITY_WEAKENED") in bad.stderr, bad
