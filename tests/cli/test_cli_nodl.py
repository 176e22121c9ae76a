"""NoDL v2 documents wherever a contract goes, on real nodes: `capture --format nodl` round-trips
(NoDL -> check -> --update -> NoDL), a document written the way NoDL's documentation writes them
checks a node, and diff, compat and validate read NoDL."""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest
import yaml
from cli_helpers import NODES
from sample_contracts import talker_contract

NODL_SRC = Path(os.environ.get("NODL_SRC", "/work/src/nodl"))
TALKER = NODES / "talker.py"

#: tests/plugin/nodes/talker.py as a person writes its NoDL document (NoDL's documentation style:
#: no node name, a relative topic name, a type without `msg`, only the required QoS policies)
HANDWRITTEN = """\
nodl_version: 2
description: Publishes on chatter with a QoS its parameters set.
parameters:
  depth:
    type: int
    default_value: 10
  durability:
    type: string
    default_value: volatile
  listen:
    type: string
  msg_type:
    type: string
    default_value: String
  reliability:
    type: string
    default_value: reliable
  topic:
    type: string
    default_value: chatter
publishers:
  - name: chatter
    type: std_msgs/String
    description: what the talker says
    qos:
      history: KEEP_LAST
      depth: 10
      reliability: RELIABLE
"""


@pytest.fixture
def nodl_cli(cli):
    """The CLI with NoDL's schema where a NoDL checkout is (NODL_SRC), as a NoDL install would give it."""
    if (NODL_SRC / "nodl_schema" / "nodl_schema" / "schemas" / "nodl.schema.yaml").is_file():
        cli.env["RMW_INTROSPECT_NODL_SCHEMA"] = str(NODL_SRC)
    return cli


def test_capture_as_nodl_round_trips_through_check_and_update(nodl_cli):
    cli = nodl_cli
    captured = cli("capture", "--format", "nodl", "--script", TALKER, "-o", "talker.nodl.yaml")
    assert captured.returncode == 0, captured
    first = cli.read("talker.nodl.yaml")
    assert first.startswith("---\n# node: /talker\nnodl_version: 2\n"), first

    matching = cli("check", "--script", TALKER, "talker.nodl.yaml")
    assert matching.returncode == 0 and matching.stdout == "talker.nodl.yaml: matches (/talker)\n", matching
    assert "note: talker.nodl.yaml: NoDL cannot express type hashes, lifecycle states" in matching.stderr

    drifted = cli("check", "--script", TALKER, "--param", "depth:=5", "talker.nodl.yaml")
    assert drifted.returncode == 1, drifted
    assert "[QOS_DEPTH_DECREASED] depth 10 -> 5" in drifted.stdout
    assert "[PARAM_DEFAULT_CHANGED]" in drifted.stdout
    annotated = cli("check", "--script", TALKER, "--param", "depth:=5", "--format", "github", "talker.nodl.yaml")
    lines = first.splitlines()
    on = {title: int(line) for line, title in re.findall(r"::error file=talker\.nodl\.yaml,line=(\d+),title=(\w+)",
                                                              annotated.stdout)}
    assert lines[on["QOS_DEPTH_DECREASED"] - 1] == "- name: /chatter", annotated.stdout  # the entry's line
    assert lines[on["PARAM_DEFAULT_CHANGED"] - 1] == "  depth:", annotated.stdout

    updated = cli("check", "--update", "--script", TALKER, "--param", "depth:=5", "talker.nodl.yaml")
    assert updated.returncode == 0 and "updated talker.nodl.yaml" in updated.stderr, updated
    (doc,) = yaml.safe_load_all(cli.read("talker.nodl.yaml"))
    assert doc["publishers"] == [{"name": "/chatter", "type": "std_msgs/msg/String",
                                  "qos": {"history": "KEEP_LAST", "depth": 5, "reliability": "RELIABLE",
                                          "durability": "VOLATILE"}}]
    assert doc["parameters"]["depth"] == {"type": "int", "default_value": 5}
    assert cli("validate", "talker.nodl.yaml").returncode == 0
    assert cli("check", "--script", TALKER, "--param", "depth:=5", "talker.nodl.yaml").returncode == 0
    back = cli("check", "--update", "--script", TALKER, "talker.nodl.yaml")
    assert back.returncode == 0 and cli.read("talker.nodl.yaml") == first, back  # NoDL -> NoDL, byte for byte


def test_a_handwritten_nodl_document_checks_the_node_it_describes(nodl_cli):
    cli = nodl_cli
    cli.write("talker.nodl.yaml", HANDWRITTEN)
    matching = cli("check", "--script", TALKER, "talker.nodl.yaml")
    assert matching.returncode == 0 and matching.stdout == "talker.nodl.yaml: matches (/talker)\n", matching
    remapped = cli("check", "--script", TALKER, "--namespace", "/robot", "talker.nodl.yaml")  # chatter is relative
    assert remapped.returncode == 0, remapped
    renamed = cli("check", "--script", TALKER, "--param", "topic:=/talk", "--fail-on", "breaking", "talker.nodl.yaml")
    assert renamed.returncode == 1 and "[PUB_RENAMED]" in renamed.stdout, renamed
    # update writes the node's name and keeps the description people wrote
    assert cli("check", "--update", "--script", TALKER, "--param", "durability:=transient_local",
               "talker.nodl.yaml").returncode == 0
    text = cli.read("talker.nodl.yaml")
    assert text.startswith("---\n# node: /talker\n")
    assert yaml.safe_load(text.split("---\n", 2)[1])["description"] == \
        "Publishes on chatter with a QoS its parameters set."


def test_diff_compat_and_validate_read_nodl(nodl_cli):
    cli = nodl_cli
    cli.write("talker.nodl.yaml", HANDWRITTEN)
    cli.write("talker.interfaces.yaml", talker_contract(depth=3))
    cli.write("listener.nodl.yaml", "nodl_version: 2\nsubscriptions:\n  - name: /chatter\n    type: std_msgs/msg/String\n"
                                    "    qos: {history: KEEP_LAST, depth: 10, reliability: RELIABLE}\n")
    diff = cli("diff", "talker.nodl.yaml", "talker.interfaces.yaml", "--format", "json")
    assert diff.returncode == 1, diff
    assert [i["rule"] for i in yaml.safe_load(diff.stdout)] == ["QOS_DEPTH_DECREASED"]  # no hash, no lifecycle
    compat = cli("compat", "talker.nodl.yaml", "listener.nodl.yaml")
    assert compat.returncode == 0, compat
    valid = cli("validate", "talker.nodl.yaml", "listener.nodl.yaml")
    assert valid.returncode == 0 and "talker.nodl.yaml: valid NoDL (/talker)" in valid.stdout, valid
    unchecked = cli("validate", "talker.nodl.yaml", env={"RMW_INTROSPECT_NODL_SCHEMA": "/nonexistent"})
    assert unchecked.stdout == ("talker.nodl.yaml: valid NoDL (/talker); not validated against NoDL's own schema "
                                "(RMW_INTROSPECT_NODL_SCHEMA=/nonexistent holds no nodl.schema.yaml): set "
                                "RMW_INTROSPECT_NODL_SCHEMA to NoDL's schemas directory or install NoDL (nodl_schema)\n")
    cli.write("bad.nodl.yaml", "nodl_version: 2\nbase: lifecycle_node\n")
    bad = cli("validate", "bad.nodl.yaml")
    assert bad.returncode == 2 and "bad.nodl.yaml:2: at base: unknown key 'base' in a NoDL v2 document" in bad.stderr
