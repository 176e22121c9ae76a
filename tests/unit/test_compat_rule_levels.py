"""`rmw-introspect compat` at the project's rule levels (issue 49's `rules`, as every other report
command applies them): the command line's `--rule`, over the `options: rules` of the file of each
end of a problem; the more severe when the two files say different levels. Nothing runs."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from pytest_rmw_introspect import cli


def contract(node: str, kind: str, reliability: str, rules: str) -> str:
    """A node contract with one /chatter endpoint, and ``rules`` (a flow mapping's inside) if any."""
    options = f"options: {{rules: {{{rules}}}}}\n" if rules else ""
    qos = f"{{history: KEEP_LAST, depth: 10, reliability: {reliability}, durability: VOLATILE}}"
    return (f"contract_version: 1\n{options}nodes:\n  {node}:\n    {kind}:\n"
            f"      - {{name: /chatter, type: std_msgs/msg/String, qos: {qos}}}\n")


@pytest.fixture
def files(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)

    def write(talker: str = "", listener: str = "") -> list[str]:
        Path("talker.yaml").write_text(contract("/talker", "publishers", "BEST_EFFORT", talker))
        Path("listener.yaml").write_text(contract("/listener", "subscriptions", "RELIABLE", listener))
        return ["talker.yaml", "listener.yaml"]

    return write


def compat(capsys, *args: str) -> tuple[int, list[dict]]:
    status = cli.main(["compat", *args, "--format", "json"])
    out = capsys.readouterr().out
    return status, json.loads(out) if status != 2 else []


def test_without_levels_the_incompatible_pair_breaks(files, capsys):
    status, found = compat(capsys, *files())
    assert status == 1 and [(f["rule"], f["severity"]) for f in found] == [("QOS_INCOMPATIBLE", "BREAKING")]


def test_a_level_in_the_file_of_either_end_applies_and_says_where_it_was_set(files, capsys):
    status, found = compat(capsys, *files(listener="QOS_INCOMPATIBLE: note"))
    assert status == 0 and [(f["rule"], f["severity"]) for f in found] == [("QOS_INCOMPATIBLE", "NOTE")]
    assert found[0]["level_set_by"] == "set by rules: in listener.yaml: options"
    status, found = compat(capsys, *files(talker="QOS_*: risky"))
    assert status == 0 and found[0]["severity"] == "RISKY" and "`QOS_*`: in talker.yaml" in found[0]["level_set_by"]


def test_two_files_that_disagree_get_the_more_severe_level(files, capsys):
    status, found = compat(capsys, *files(talker="QOS_INCOMPATIBLE: breaking", listener="QOS_INCOMPATIBLE: 'off'"))
    assert status == 1 and found[0]["severity"] == "BREAKING" and "talker.yaml" in found[0]["level_set_by"]


def test_the_command_line_wins_over_the_files_and_off_is_counted(files, capsys):
    assert cli.main(["compat", *files(talker="QOS_INCOMPATIBLE: breaking"), "--rule", "QOS_INCOMPATIBLE=off"]) == 0
    out = capsys.readouterr().out
    assert "QOS_INCOMPATIBLE" not in out and "1 finding turned off by the project's rules" in out


def test_an_unknown_rule_is_an_error_naming_the_file_and_the_closest_rule(files, capsys):
    assert cli.main(["compat", *files(listener="QOS_INCOMPATIBL: note")]) == 2
    err = capsys.readouterr().err
    assert "listener.yaml: options: `rules`: unknown rule id QOS_INCOMPATIBL" in err and "QOS_INCOMPATIBLE" in err
    assert cli.main(["compat", *files(), "--rule", "QOS_INCOMPATIBLE=loud"]) == 2
    assert "command line" in capsys.readouterr().err
