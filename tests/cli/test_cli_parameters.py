"""`rmw-introspect` with parameters and lifecycle nodes (issue 10), real rclpy nodes: capture
shows them (yaml, json, nodl), --lifecycle and --no-read-parameters reach the middleware, check
reports a failing transition as an error naming the contract, --update completes contracts
written before parameters were recorded, diff and compat read contracts with parameters."""

from __future__ import annotations

import json
from pathlib import Path

import yaml
from cli_helpers import NODES
from sample_contracts import talker_contract

MIDDLEWARE_NODES = Path(__file__).parent.parent / "middleware" / "nodes"
LC_MANAGED = MIDDLEWARE_NODES / "lc_managed.py"
PARAMS_NODE = MIDDLEWARE_NODES / "params_node.py"


def test_capture_shows_the_lifecycle_state_and_parameters_and_the_options_change_them(cli):
    active = cli("capture", "--format", "json", "--script", LC_MANAGED)
    assert active.returncode == 0, active
    node = json.loads(active.stdout)["/managed"]
    assert node["lifecycle"] == "active"
    assert [p["name"] for p in node["publishers"]] == ["/late_status", "/status"]
    assert {p["name"]: p.get("declared_in") for p in node["parameters"]} == {
        "depth": "configure", "rate": None, "topic": "configure"}

    inactive = cli("capture", "--lifecycle", "inactive", "--no-read-parameters", "-o", "managed.interfaces.yaml",
                   "--script", LC_MANAGED)
    assert inactive.returncode == 0, inactive
    doc = yaml.safe_load(cli.read("managed.interfaces.yaml"))
    assert doc["target"] == {"script": str(LC_MANAGED), "lifecycle": "inactive", "read_parameters": False}
    assert doc["nodes"]["/managed"]["lifecycle"] == "inactive"
    assert "parameters" not in doc["nodes"]["/managed"]
    assert [p["name"] for p in doc["nodes"]["/managed"]["publishers"]] == ["/status"]
    # the contract checks the way it was captured
    check = cli("check", "managed.interfaces.yaml")
    assert check.returncode == 0 and check.stdout == "managed.interfaces.yaml: matches (/managed)\n", check


def test_capture_nodl_has_parameters_and_the_lifecycle_state_in_a_comment(cli):
    result = cli("capture", "--format", "nodl", "--script", LC_MANAGED)
    assert result.returncode == 0, result
    (doc,) = yaml.safe_load_all(result.stdout)
    assert "base" not in doc and "# lifecycle: active (a lifecycle node: NoDL v2 cannot say so" in result.stdout
    assert doc["parameters"]["depth"] == {"type": "int", "default_value": 5}
    assert doc["parameters"]["rate"] == {"type": "double", "default_value": 10.0, "description": "Hz"}
    raw = cli("capture", "--format", "nodl", "--raw", "--script", PARAMS_NODE)
    (raw_doc,) = yaml.safe_load_all(raw.stdout)
    assert raw_doc["parameters"]["blob"]["type"] == "byte_array"
    assert raw_doc["parameters"]["use_sim_time"] == {"type": "bool", "default_value": False}


def test_check_of_a_node_whose_configure_fails_is_an_error_naming_the_contract(cli):
    cli.write("managed.interfaces.yaml", f"contract_version: 1\ntarget:\n  script: {LC_MANAGED}\n"
                                         "  arguments: [fail]\nnodes: {}\n")
    result = cli("check", "managed.interfaces.yaml")
    assert result.returncode == 2, result
    assert result.stderr.startswith("rmw-introspect: managed.interfaces.yaml: lifecycle node /managed of the target "
                                    f"script {LC_MANAGED} failed its configure transition: change_state answered "
                                    "success=false"), result
    assert "set `lifecycle: unconfigured` in the `target:` block of managed.interfaces.yaml" in result.stderr
    assert "--lifecycle unconfigured" in result.stderr
    fixed = cli("check", "--update", "--lifecycle", "unconfigured", "managed.interfaces.yaml")
    assert fixed.returncode == 0, fixed
    assert yaml.safe_load(cli.read("managed.interfaces.yaml"))["nodes"]["/managed"]["lifecycle"] == "unconfigured"
    github = cli("check", "--format", "github", "managed.interfaces.yaml")
    assert github.returncode == 2
    assert github.stdout.startswith("::error file=managed.interfaces.yaml,title=contract not checked::"
                                    "managed.interfaces.yaml: lifecycle node /managed"), github


def test_check_update_adds_parameters_to_a_contract_written_before_they_were_recorded(cli):
    talker = f"script: {NODES / 'talker.py'}"
    cli.write("talker.interfaces.yaml", talker_contract(target=talker, parameters=False))
    result = cli("check", "talker.interfaces.yaml")
    assert result.returncode == 0, result
    assert result.stdout == ("talker.interfaces.yaml: matches (/talker); it does not state /talker parameters yet: "
                             "rmw-introspect check --update talker.interfaces.yaml adds them\n")
    updated = cli("check", "--update", "talker.interfaces.yaml")
    assert updated.returncode == 0, updated
    assert "updated talker.interfaces.yaml" in updated.stderr
    assert cli.read("talker.interfaces.yaml") == talker_contract(target=talker)
    again = cli("check", "talker.interfaces.yaml")
    assert again.stdout == "talker.interfaces.yaml: matches (/talker)\n", again


def test_diff_compat_and_validate_read_contracts_with_parameters(cli_nodes_only):
    cli = cli_nodes_only
    old = talker_contract()
    new = (talker_contract().replace("        default_value: 10\n", "        default_value: 10\n        read_only: true\n")
           .replace("      - name: topic\n", "      - name: rate\n        type: double\n        default_value: null\n"
                    "      - name: topic\n"))
    cli.write("old.interfaces.yaml", old)
    cli.write("new.interfaces.yaml", new)
    text = cli("diff", "old.interfaces.yaml", "new.interfaces.yaml")
    assert text.returncode == 1, text
    assert text.stdout.startswith("Interface drift of new.interfaces.yaml against old.interfaces.yaml: 2 changes "
                                  "(1 breaking, 1 risky, 0 safe)\n"), text
    assert ("    parameter depth\n      [PARAM_READ_ONLY_ADDED] now read-only" in text.stdout)
    assert ("    parameter rate\n      [PARAM_ADDED_WITHOUT_VALUE] new parameter rate (double) without a default "
            "value: launch and parameter files must now set it" in text.stdout)
    as_json = json.loads(cli("diff", "--format", "json", "old.interfaces.yaml", "new.interfaces.yaml").stdout)
    assert [(i["kind"], i["name"], i["rule"]) for i in as_json] == [
        ("parameters", "depth", "PARAM_READ_ONLY_ADDED"), ("parameters", "rate", "PARAM_ADDED_WITHOUT_VALUE")]
    markdown = cli("diff", "--format", "markdown", "old.interfaces.yaml", "new.interfaces.yaml").stdout
    assert "- `/talker` parameter `depth`: `PARAM_READ_ONLY_ADDED` now read-only" in markdown
    github = cli("diff", "--format", "github", "old.interfaces.yaml", "new.interfaces.yaml").stdout.splitlines()
    depth_line = new.splitlines().index("      - name: depth") + 1
    assert github[0].startswith(f"::error file=new.interfaces.yaml,line={depth_line},"
                                "title=PARAM_READ_ONLY_ADDED (BREAKING)::/talker parameter depth: now read-only")
    quiet = cli("diff", "--ignore-parameters", "depth,rate", "old.interfaces.yaml", "new.interfaces.yaml")
    assert quiet.returncode == 0 and "no drift" in quiet.stdout, quiet
    assert cli("compat", "old.interfaces.yaml", "new.interfaces.yaml").returncode == 0
    assert cli("validate", "old.interfaces.yaml", "new.interfaces.yaml").returncode == 0
    cli.write("bad.interfaces.yaml", new.replace("default_value: 10\n", "default_value: ten\n", 1))
    bad = cli("validate", "bad.interfaces.yaml")
    assert bad.returncode == 2
    assert "at nodes./talker.parameters[0].default_value: parameter 'depth': 'ten' is not an integer (node /talker)" \
        in bad.stdout + bad.stderr, bad
