"""`rmw-introspect` and the contract's `types:` section: `check --update --include-types`
writes it, and the section is then kept and checked."""

from __future__ import annotations

from cli_helpers import NODES
from sample_contracts import talker_contract

from pytest_rmw_introspect.model import contract as contract_module
from pytest_rmw_introspect.model.types import Field, MessageType

TALKER = f"script: {NODES / 'talker.py'}"
STRING = {"std_msgs/msg/String": MessageType("std_msgs/msg/String", (Field("data", "string"),), ())}


def test_check_update_include_types_writes_the_section_and_then_matches(cli):
    cli.write("talker.interfaces.yaml", talker_contract(target=TALKER))
    result = cli("check", "--include-types", "talker.interfaces.yaml")
    assert result.returncode == 1, result
    assert "[TYPE_DESCRIPTION_MISSING]" in result.stdout
    assert "rmw-introspect check --update --include-types talker.interfaces.yaml" in result.stdout
    written = cli("check", "--update", "--include-types", "talker.interfaces.yaml")
    assert written.returncode == 0, written
    assert "updated talker.interfaces.yaml" in written.stderr
    text = cli.read("talker.interfaces.yaml")
    assert text.startswith(talker_contract(target=TALKER))
    assert contract_module.load(cli.path / "talker.interfaces.yaml").types == STRING
    # the section is kept and compared without the flag
    again = cli("check", "talker.interfaces.yaml")
    assert again.returncode == 0 and again.stdout == "talker.interfaces.yaml: matches (/talker)\n", again
    assert cli("check", "--update", "talker.interfaces.yaml").returncode == 0
    assert cli.read("talker.interfaces.yaml") == text


TYPES = """
types:
  std_msgs/msg/String:
    fields:
      - {field}
    constants:{constants}
"""


def test_diff_shows_why_the_hash_changed(cli_nodes_only):
    old = talker_contract() + TYPES.format(field="string data", constants=" []")
    new = (talker_contract().replace("df668c74", "00000000")
           + TYPES.format(field="string<=64 data", constants="\n      - uint8 MAX=64"))
    cli_nodes_only.write("old.yaml", old)
    cli_nodes_only.write("new.yaml", new)
    result = cli_nodes_only("diff", "old.yaml", "new.yaml")
    assert result.returncode == 1, result
    assert result.stdout.startswith("Interface drift of new.yaml against old.yaml: 3 changes (1 breaking, 1 risky, "
                                    "1 safe)\n")
    assert ("    publisher /chatter\n"
            "      [TYPE_HASH_CHANGED] message definition of std_msgs/msg/String changed; the types: section shows how "
            "(2 field-level changes listed under this interface)") in result.stdout
    assert ("      [TYPE_FIELD_BOUND_NARROWED] std_msgs/msg/String: field `data` string -> string<=64: strings "
            "longer than 64, valid before, are now rejected\n") in result.stdout
    assert "      [TYPE_CONSTANT_ADDED] std_msgs/msg/String: constant `uint8 MAX=64` added\n" in result.stdout
    as_json = cli_nodes_only("diff", "--format", "json", "old.yaml", "new.yaml")
    import json

    items = json.loads(as_json.stdout)
    assert [(i["rule"], i["change"], i["old"], i["new"]) for i in items] == [
        ("TYPE_HASH_CHANGED", "type_hash", items[0]["old"], items[0]["new"]),
        ("TYPE_FIELD_BOUND_NARROWED", "type:std_msgs/msg/String", "string data", "string<=64 data"),
        ("TYPE_CONSTANT_ADDED", "type:std_msgs/msg/String", None, "uint8 MAX=64"),
    ]
    # below the threshold the field-level items are still shown
    risky = cli_nodes_only("diff", "--fail-on", "breaking", "old.yaml", "new.yaml")
    assert risky.returncode == 1 and "[TYPE_CONSTANT_ADDED]" in risky.stdout
