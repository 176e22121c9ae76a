"""`rmw-introspect` and the contract's `types:` section: `check --update --include-types`
writes it, and the section is then kept and checked."""

from __future__ import annotations

from cli_helpers import NODES, talker_contract

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
