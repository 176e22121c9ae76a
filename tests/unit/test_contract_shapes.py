"""The contract's TypedDicts (model/contract_shapes.py) say what the schema says: the same keys,
the same required keys, and for the ``options:``/``target:`` blocks the keys of the option
tables. A key added to the schema or a table without its shape (or the other way round) fails here."""

from __future__ import annotations

import pytest

from pytest_rmw_introspect.model import contract, contract_shapes, system_contract
from pytest_rmw_introspect.model.option_tables import COMPARISON, TARGET, FrontEnd
from pytest_rmw_introspect.model.vocabulary import LISTS


def _keys(shape):
    return set(shape.__annotations__)


def _definition(name, schema=None):
    return (schema or contract.schema())["definitions"][name]


def test_a_node_has_the_keys_the_schema_gives_a_node():
    assert _keys(contract_shapes.ContractNode) == set(_definition("node")["properties"])
    assert contract_shapes.ContractNode.__required_keys__ == frozenset()


def test_an_interface_entry_has_the_keys_of_topics_services_and_actions():
    kinds = ("topic", "service", "action")
    assert _keys(contract_shapes.InterfaceEntry) == set().union(*(_definition(k)["properties"] for k in kinds))
    for kind in kinds:
        assert contract_shapes.InterfaceEntry.__required_keys__ == set(_definition(kind)["required"])


def test_an_action_type_hash_has_the_hashed_parts():
    parts = _definition("action")["properties"]["type_hash"]["properties"]
    assert _keys(contract_shapes.ActionTypeHash) == set(parts)


def test_the_qos_fields_are_the_schema_fields():
    assert _keys(contract_shapes.QosFields) == set(_definition("qos")["else"]["properties"])
    assert contract_shapes.QosFields.__required_keys__ == frozenset()


def test_a_parameter_entry_and_its_ranges_have_the_schema_keys():
    parameter = _definition("parameter")
    assert _keys(contract_shapes.ParameterEntry) == set(parameter["properties"])
    assert contract_shapes.ParameterEntry.__required_keys__ == set(parameter["required"])
    for range_key in ("integer_range", "floating_point_range"):
        assert contract_shapes.RangeEntry.__required_keys__ == set(parameter["properties"][range_key]["required"])


@pytest.mark.parametrize(("shape", "family"), [
    (contract_shapes.ContractOptions, COMPARISON),
    (contract_shapes.TargetBlock, TARGET),
])
def test_the_options_and_target_blocks_have_the_keys_of_their_table(shape, family):
    """The keys a node contract or a system contract takes (``system_fail_on``: system contracts only)."""
    assert _keys(shape) == set(family.names(FrontEnd.CONTRACT)) | set(family.names(FrontEnd.SYSTEM))
    assert shape.__required_keys__ == frozenset()


def test_the_system_contract_blocks_have_the_system_schema_keys():
    schema = system_contract.schema()
    assert _keys(contract_shapes.LaunchBlock) == set(_definition("launch", schema)["properties"])
    process = _definition("process", schema)
    assert _keys(contract_shapes.ProcessEntry) == set(process["properties"])
    assert contract_shapes.ProcessEntry.__required_keys__ == set(process["required"])
    assert set(_definition("options", schema)["properties"]) == _keys(contract_shapes.ContractOptions)
    stand_in = schema["definitions"]["stand_ins"]["items"]
    assert _keys(contract_shapes.StandInEntry) == set(stand_in["properties"])
    assert contract_shapes.StandInEntry.__required_keys__ == set(stand_in["required"])


def test_a_loaded_contract_is_made_of_the_shapes():
    loaded = contract.loads(
        "contract_version: 1\n"
        "target: {package: rmw_introspect_examples, executable: talker}\n"
        "options: {fail_on: risky}\n"
        "nodes:\n"
        "  /talker:\n"
        "    publishers: [{name: /chatter, type: std_msgs/msg/String, qos: sensor_data}]\n"
        "    parameters: [{name: rate, type: double, default_value: 2.0}]\n")
    node = loaded.nodes["/talker"]
    assert set(node) <= _keys(contract_shapes.ContractNode)
    assert set(LISTS) <= set(node)
    assert all(set(e) <= _keys(contract_shapes.InterfaceEntry) for name in LISTS for e in node[name])
    assert all(set(p) <= _keys(contract_shapes.ParameterEntry) for p in node["parameters"])
    assert set(loaded.options) <= _keys(contract_shapes.ContractOptions)
    assert set(loaded.target or {}) <= _keys(contract_shapes.TargetBlock)
    expanded = loaded.expanded_nodes()["/talker"]["publishers"][0]["qos"]
    assert set(expanded) == _keys(contract_shapes.QosFields) - {"profile"}
