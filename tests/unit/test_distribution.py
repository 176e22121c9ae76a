"""Which ROS 2 distribution a contract was captured on (``ros_distribution:``), and what a type
hash that differs between distributions is called (docs/drift-rules.md)."""

from __future__ import annotations

import pytest

from pytest_rmw_introspect import diff_contracts
from pytest_rmw_introspect.check import golden
from pytest_rmw_introspect.errors import ContractError
from pytest_rmw_introspect.model import contract as contract_module

NODES = {"/talker": {"publishers": [{"name": "/chatter", "type": "std_msgs/msg/String",
                                     "type_hash": "RIHS01_" + "a" * 64}]}}


def _with_hash(digit: str) -> dict:
    return {"/talker": {"publishers": [{**NODES["/talker"]["publishers"][0], "type_hash": "RIHS01_" + digit * 64}]}}


def test_the_distribution_line_is_added_after_contract_version_and_replaced_later():
    text = "# my notes\ncontract_version: 1\ntarget: {script: t.py}\n" + contract_module.dump_nodes(NODES)
    recorded = contract_module.with_distribution(text, "jazzy")
    assert recorded.startswith("# my notes\ncontract_version: 1\nros_distribution: jazzy\ntarget: {script: t.py}\n")
    assert contract_module.loads(recorded).ros_distribution == "jazzy"
    moved = contract_module.with_distribution(recorded, "kilted")
    assert moved == recorded.replace("ros_distribution: jazzy", "ros_distribution: kilted")
    assert contract_module.with_distribution(moved, None) == moved  # unknown: left as it is
    assert contract_module.loads(text).ros_distribution is None


@pytest.mark.parametrize("value", ["Jazzy", "'jazzy kilted'", "3", "[jazzy]"])
def test_a_distribution_that_is_not_a_lowercase_name_is_refused_with_its_line(value):
    with pytest.raises(ContractError) as info:
        contract_module.loads(f"contract_version: 1\nros_distribution: {value}\nnodes: {{}}\n", path="c.yaml")
    assert info.value.location == "ros_distribution" and info.value.line == 2, str(info.value)


def test_golden_writes_record_the_distribution_of_the_capture(tmp_path):
    path = tmp_path / "t.interfaces.yaml"
    assert golden.update(path, NODES, distribution="kilted") == golden.CREATED
    assert "\nros_distribution: kilted\n" in path.read_text()
    assert golden.update(path, NODES, distribution="jazzy") == golden.UPDATED
    assert contract_module.load(path).ros_distribution == "jazzy"
    assert golden.update(path, NODES, distribution="jazzy") is None  # nothing to change


def test_an_existing_contract_without_the_line_keeps_its_header_byte_for_byte(tmp_path):
    path = tmp_path / "t.interfaces.yaml"
    path.write_text("# mine\ncontract_version: 1\n" + contract_module.dump_nodes(_with_hash("b")))
    assert golden.update(path, NODES, distribution="kilted") == golden.UPDATED
    assert path.read_text() == "# mine\ncontract_version: 1\n" + contract_module.dump_nodes(NODES)


def test_diff_of_contracts_from_two_distributions_names_them(tmp_path):
    old, new = tmp_path / "old.interfaces.yaml", tmp_path / "new.interfaces.yaml"
    old.write_text(contract_module.with_distribution(contract_module.render(_with_hash("a")), "jazzy"))
    new.write_text(contract_module.with_distribution(contract_module.render(_with_hash("b")), "kilted"))
    [item] = diff_contracts(old, new).items
    assert item.rule == "TYPE_HASH_DISTRIBUTION_CHANGED"
    assert "ROS 2 jazzy (the contract) and kilted (this run)" in item.message
    new.write_text(contract_module.with_distribution(contract_module.render(_with_hash("b")), "jazzy"))
    assert [i.rule for i in diff_contracts(old, new).items] == ["TYPE_HASH_CHANGED"]
