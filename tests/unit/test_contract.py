"""Contract files: load, schema errors with locations and lines, deterministic dump, updates."""

from __future__ import annotations

import json
import textwrap

import jsonschema
import pytest
from sample_contracts import STRING_HASH

from pytest_rmw_introspect.check import golden
from pytest_rmw_introspect.errors import ContractError
from pytest_rmw_introspect.model import contract
from pytest_rmw_introspect.model.contract import (
    Contract,
    dump_nodes,
    load,
    loads,
    render,
    update_text,
)

HASH = STRING_HASH
H1, H2, H3 = ("RIHS01_" + c * 64 for c in "123")

NODES = {
    "/talker": {
        "publishers": [
            {"name": "/chatter", "type": "std_msgs/msg/String", "type_hash": HASH,
             "qos": {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE"}},
            {"name": "/a_first", "type": "std_msgs/msg/Int32",
             "qos": {"history": "KEEP_ALL", "reliability": "BEST_EFFORT", "durability": "VOLATILE",
                     "deadline_ns": 100000000}},
        ],
        "subscriptions": [],
        "service_servers": [{"name": "/talker/reset", "type": "std_srvs/srv/Empty", "type_hash": HASH}],
        "service_clients": [],
        "action_servers": [{"name": "/fibonacci", "type": "test_msgs/action/Fibonacci",
                            "type_hash": {"feedback": H3, "send_goal": H1, "get_result": H2}}],
        "action_clients": [],
    },
    "/ns/listener": {"subscriptions": [{"name": "/chatter", "type": "std_msgs/msg/String", "qos": "sensor_data"}]},
}

EXPECTED_DUMP = f"""\
nodes:
  /ns/listener:
    publishers: []
    subscriptions:
      - name: /chatter
        type: std_msgs/msg/String
        qos: sensor_data
    service_servers: []
    service_clients: []
    action_servers: []
    action_clients: []
  /talker:
    publishers:
      - name: /a_first
        type: std_msgs/msg/Int32
        qos: {{history: KEEP_ALL, reliability: BEST_EFFORT, durability: VOLATILE, deadline_ns: 100000000}}
      - name: /chatter
        type: std_msgs/msg/String
        type_hash: {HASH}
        qos: {{history: KEEP_LAST, depth: 10, reliability: RELIABLE, durability: VOLATILE}}
    subscriptions: []
    service_servers:
      - name: /talker/reset
        type: std_srvs/srv/Empty
        type_hash: {HASH}
    service_clients: []
    action_servers:
      - name: /fibonacci
        type: test_msgs/action/Fibonacci
        type_hash:
          send_goal: {H1}
          get_result: {H2}
          feedback: {H3}
    action_clients: []
"""


@pytest.mark.parametrize(("text", "wanted"), [
    ("contract_version: 1\nnodes: {}\ntarget: {script: a.py, timout: 5}\n",
     "at target: unknown key 'timout'; did you mean 'timeout'? (allowed keys: see the contract schema"),
    ("contract_version: 1\nnodes: {}\noptions: {zz: 1}\n",
     "at options: unknown key 'zz' (allowed keys: see the contract schema, "
     "pytest_rmw_introspect/schema/contract.schema.json)"),
    ("contract_version: 1\nnodes:\n  /t:\n    parameters:\n      - {name: a, type: bool, wat: 1}\n",
     "at nodes./t.parameters[0]: unknown key 'wat' (allowed keys: see the contract schema"),
    ("contract_version: 1\nnodes:\n  /t:\n    publisher: []\n",
     "unknown key 'publisher'; did you mean 'publishers'? (allowed keys: see the contract schema"),
])
def test_unknown_keys_are_named_and_long_lists_of_allowed_keys_point_at_the_schema(text, wanted):
    """A message listing the 21 keys `target:` takes was one line of 300-375 characters."""
    with pytest.raises(ContractError) as info:
        loads(text, path="k.interfaces.yaml")
    assert wanted in str(info.value), str(info.value)
    assert len(str(info.value)) < 240, str(info.value)


def test_dump_is_sorted_and_stably_formatted():
    assert dump_nodes(NODES) == EXPECTED_DUMP


def test_dump_of_load_is_byte_identical():
    text = render(NODES)
    again = loads(text).dump()
    assert again == text
    assert render(loads(text).nodes) == text


def test_dump_empty_nodes():
    assert dump_nodes({}) == "nodes: {}\n"
    assert loads(render({})).nodes == {}


def test_rendered_contract_is_valid_against_the_schema():
    import yaml

    jsonschema.Draft7Validator(contract.schema()).validate(yaml.safe_load(render(NODES)))


def test_schema_is_a_valid_draft7_schema_shipped_in_the_package():
    jsonschema.Draft7Validator.check_schema(contract.schema())
    assert contract.schema()["properties"]["contract_version"] == {"description": "Version of this file format.", "const": 1}


def test_load_normalises_missing_lists_and_expands_qos(tmp_path):
    path = tmp_path / "c.yaml"
    path.write_text(render(NODES))
    c = load(path)
    assert isinstance(c, Contract) and c.path == path and c.contract_version == 1
    assert c.nodes["/ns/listener"]["publishers"] == []
    assert c.nodes["/ns/listener"]["subscriptions"][0]["qos"] == "sensor_data"
    expanded = c.expanded_nodes()
    sub_qos = expanded["/ns/listener"]["subscriptions"][0]["qos"]
    assert sub_qos["reliability"] == "BEST_EFFORT" and sub_qos["depth"] == 5
    assert sub_qos["liveliness"] == "SYSTEM_DEFAULT"
    assert "qos" not in expanded["/talker"]["service_servers"][0]


def test_null_node_and_null_lists_are_empty():
    c = loads("contract_version: 1\nnodes:\n  /a:\n  /b:\n    publishers:\n")
    assert c.nodes["/a"]["publishers"] == [] and c.nodes["/b"]["publishers"] == []


def test_target_and_options_blocks_are_read():
    c = loads(textwrap.dedent("""\
        contract_version: 1
        target:
          package: demo
          executable: talker
          parameters: {rate: 2.0}
        options:
          ignore_qos: [depth]
          fail_on: breaking
        nodes: {}
        """))
    assert c.target == {"package": "demo", "executable": "talker", "parameters": {"rate": 2.0}}
    assert c.options == {"ignore_qos": ["depth"], "fail_on": "breaking"}


# ---------------------------------------------------------------------------- errors

BAD = [
    # (text, location, line, reason fragment)
    (
        (
            "contract_version: 1\nnodes:\n  /talker:\n    publishers:\n      - name: /chatter\n"
            "        type: std_msgs/msg/String\n        qos: {history: KEEP_LAST, reliability: RELIABEL}\n"
        ),
        "nodes./talker.publishers[0].qos.reliability", 7, "'RELIABEL' is not one of: RELIABLE, BEST_EFFORT",
    ),
    (
        "contract_version: 1\nnodes:\n  /talker:\n    publishers:\n      - name: chatter\n        type: std_msgs/msg/String\n",
        "nodes./talker.publishers[0].name", 5, "not a fully resolved ROS name",
    ),
    ("contract_version: 1\nnodes:\n  /ok: {}\n  talker: {}\n", "nodes.talker", 4, "not a fully qualified node name"),
    ("contract_version: 2\nnodes: {}\n", "contract_version", 1, "contract_version 2 is not supported"),
    ("nodes: {}\n", None, 1, "'contract_version' is required"),
    ("contract_version: 1\nfoo: 1\nnodes: {}\n", None, 2, "unknown key 'foo'; allowed: accept, contract_version, interface_version, nodes, options, ros_distribution, target, types, unstable_names"),
    (
        (
            "contract_version: 1\nnodes:\n  /t:\n    publishers:\n      - {name: /a, type: std_msgs/msg/String}\n"
            "      - {name: /a, type: std_msgs/msg/String}\n"
        ),
        "nodes./t.publishers[1].name", 6, "duplicate publisher '/a' in node /t (also at publishers[0])",
    ),
    ("contract_version: 1\nnodes:\n  /t: {}\n  /t: {}\n", "nodes./t", 4, "duplicate key '/t' (first at line 3)"),
    (
        "contract_version: 1\nnodes:\n  /t:\n    publishers:\n      - {name: /a, type: std_msgs/msg/String, qos: fast}\n",
        "nodes./t.publishers[0].qos", 5, "'fast' is not one of: default, system_default, sensor_data",
    ),
    (
        "contract_version: 1\nnodes:\n  /t:\n    publishers:\n      - {name: /a, type: std_msgs/msg/String, qos: {depth: -3}}\n",
        "nodes./t.publishers[0].qos.depth", 5, "-3 is less than the minimum of 0",
    ),
    (
        "contract_version: 1\nnodes:\n  /t:\n    subscriptions:\n      - {name: /a, type: std_msgs/msg/String, qos: {deadline_ns: 1.5}}\n",
        "nodes./t.subscriptions[0].qos.deadline_ns", 5, "1.5 is not of type integer",
    ),
    (
        "contract_version: 1\nnodes:\n  /t:\n    publishers:\n      - {name: /a, type: std_msgs/msg/String, type_hash: abc}\n",
        "nodes./t.publishers[0].type_hash", 5, "'abc' is not a type hash",
    ),
    ("contract_version: 1\nnodes:\n  /t:\n    publishers:\n      - {name: /a}\n", "nodes./t.publishers[0]", 5, "'type' is required"),
    ("contract_version: 1\nnodes:\n  /t:\n    servers: []\n", "nodes./t", 4, "unknown key 'servers'"),
    (
        "contract_version: 1\nnodes:\n  /t:\n    service_servers:\n      - {name: /a, type: std_srvs/srv/Empty, depth: 5}\n",
        "nodes./t.service_servers[0]", 5, "unknown key 'depth'; allowed: destroyed_at, name, qos, type, type_hash",
    ),
    ("contract_version: 1\noptions: {fail_on: sometimes}\nnodes: {}\n", "options.fail_on", 2, "'sometimes' is not one of: any, risky, breaking"),
    ("contract_version: 1\noptions: {ignore_qos: [depth, color]}\nnodes: {}\n", "options.ignore_qos[1]", 2, "'color' is not one of"),
    ("contract_version: 1\ntarget: {timeout: soon}\nnodes: {}\n", "target.timeout", 2, "'soon' is not of type number"),
    ("contract_version: 1\ntarget: {pakage: x}\nnodes: {}\n", "target", 2, "unknown key 'pakage'"),
]


@pytest.mark.parametrize("text, location, line, reason", BAD)
def test_malformed_contracts_name_file_location_line_and_reason(tmp_path, text, location, line, reason):
    path = tmp_path / "contracts" / "talker.yaml"
    path.parent.mkdir()
    path.write_text(text)
    with pytest.raises(ContractError) as info:
        load(path)
    err = info.value
    assert err.path == path
    assert err.location == location
    assert err.line == line
    assert reason in err.reason
    expected_where = f"{path}:{line}" + (f": at {location}" if location else "")
    assert str(err).startswith(f"invalid contract {expected_where}: ")


def test_yaml_syntax_error_has_line_and_column(tmp_path):
    path = tmp_path / "c.yaml"
    path.write_text("contract_version: 1\nnodes:\n  /t:\n    publishers: [\n      {name: /a\n")
    with pytest.raises(ContractError) as info:
        load(path)
    assert "YAML syntax error" in info.value.reason and "column" in info.value.reason
    assert info.value.line is not None and info.value.location is None


def test_every_problem_of_a_file_is_listed_with_its_own_line():
    with pytest.raises(ContractError) as info:
        loads("contract_version: 2\nfoo: 1\nnodes: {}\n", path="c.yaml")
    assert str(info.value).splitlines() == [
        "invalid contract c.yaml:2: unknown key 'foo'; allowed: accept, contract_version, interface_version, "
        "nodes, options, ros_distribution, target, types, unstable_names",
        "1 more problem in the file:",
        "  c.yaml:1: at contract_version: contract_version 2 is not supported; this plugin reads contract_version 1",
    ]
    assert [(where, line) for where, _, line in info.value.others] == [("contract_version", 1)]


UNKNOWN_KEYS_FAR_DOWN = """\
contract_version: 1
nodes:
  /talker:
    publishers:
      - name: /chatter
        type: std_msgs/msg/String
    subscriptions: []
    service_servers: []
    service_clients: []
    action_servers: []
    action_clients: []
    parameters:
      - name: rate
        type: double
        default_value: 10.0
        wat: 1
    publisher: []
"""


def test_an_unknown_key_is_reported_at_its_own_line_not_its_mappings():
    with pytest.raises(ContractError) as info:
        loads(UNKNOWN_KEYS_FAR_DOWN, path="c.yaml")
    err = info.value
    lines = {err.line, *(line for _, _, line in err.others)}
    assert lines == {16, 17}, str(err)  # `wat:` and `publisher:` themselves, not lines 3 and 13
    assert "1 more problem in the file:" in str(err)
    text = str(err)
    assert "c.yaml:16: at nodes./talker.parameters[0]: unknown key 'wat'" in text
    assert "c.yaml:17: at nodes./talker: unknown key 'publisher'" in text


@pytest.mark.parametrize("text, reason", [("", "the file is empty"), ("# only a comment\n", "the file is empty"),
                                          ("- a\n- b\n", "not a mapping")])
def test_empty_or_non_mapping(text, reason):
    with pytest.raises(ContractError, match=reason):
        loads(text, path="x.yaml")


def test_missing_file(tmp_path):
    with pytest.raises(ContractError, match="does not exist"):
        load(tmp_path / "nope.yaml")


def test_lowercase_qos_enum_is_a_schema_error():
    with pytest.raises(ContractError, match="'reliable' is not one of"):
        loads("contract_version: 1\nnodes:\n  /t:\n    publishers:\n"
              "      - {name: /a, type: std_msgs/msg/String, qos: {reliability: reliable}}\n")


# ---------------------------------------------------------------------------- updates keep the header

HEADER = """\
# Interface contract of the talker.
# Owner: team-nav. Do not loosen reliability without asking.

contract_version: 1   # the format

# run the demo talker
target:
  package: demo
  executable: talker   # the C++ one
  parameters:
    rate: 2.0
options:
  ignore_type_hash: true   # hashes differ between our distros
"""


def test_update_keeps_comments_target_and_options_verbatim():
    old = HEADER + "nodes:\n  /talker:\n    publishers: []  # a comment inside nodes is not kept\n"
    new = update_text(old, NODES)
    assert new.startswith(HEADER)
    assert new == HEADER + EXPECTED_DUMP
    # updating again with the same nodes changes nothing
    assert update_text(new, NODES) == new
    assert loads(new).target["executable"] == "talker"


def test_update_keeps_top_level_keys_after_the_nodes_block():
    trailer = "\n# comparison options\noptions:\n  allow_extra: true\n"
    old = "contract_version: 1\nnodes:\n  /x: {}\n" + trailer
    new = update_text(old, NODES)
    assert new == "contract_version: 1\n" + EXPECTED_DUMP + trailer
    assert loads(new).options == {"allow_extra": True}


def test_update_of_a_header_only_file_appends_nodes():
    assert update_text("# hi\ncontract_version: 1\n", {}) == "# hi\ncontract_version: 1\nnodes: {}\n"


def test_update_of_a_flow_style_file_rewrites_it():
    new = update_text("{contract_version: 1, nodes: {}}\n", NODES)
    assert new == render(NODES)


def test_write_creates_updates_and_reports_changes(tmp_path):
    path = tmp_path / "sub" / "c.yaml"
    assert golden.update(path, NODES) == golden.CREATED
    assert path.read_text() == render(NODES)
    assert golden.update(path, NODES) is None
    path.write_text(HEADER + path.read_text().split("contract_version: 1\n", 1)[1])
    before = path.read_text()
    assert golden.update(path, NODES) is None
    assert path.read_text() == before
    changed = json.loads(json.dumps(NODES))
    changed["/talker"]["publishers"].pop()
    assert golden.update(path, changed) == golden.UPDATED
    assert path.read_text().startswith(HEADER)
    assert not list(path.parent.glob(".*tmp"))


def test_preserve_spelling_keeps_equivalent_qos_and_omitted_fields():
    old = {"/n": {"publishers": [
        {"name": "/scan", "type": "sensor_msgs/msg/LaserScan", "qos": "sensor_data"},
        {"name": "/loose", "type": "std_msgs/msg/String"},
        {"name": "/changed", "type": "std_msgs/msg/String", "qos": "sensor_data"},
    ]}}
    new = {"/n": {"publishers": [
        {"name": "/scan", "type": "sensor_msgs/msg/LaserScan", "type_hash": HASH,
         "qos": {"history": "KEEP_LAST", "depth": 5, "reliability": "BEST_EFFORT", "durability": "VOLATILE"}},
        {"name": "/loose", "type": "std_msgs/msg/String", "type_hash": HASH,
         "qos": {"history": "KEEP_LAST", "depth": 1, "reliability": "RELIABLE", "durability": "VOLATILE"}},
        {"name": "/changed", "type": "std_msgs/msg/String",
         "qos": {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE"}},
        {"name": "/new", "type": "std_msgs/msg/String", "type_hash": HASH, "qos": "default"},
    ]}, "/m": {}}
    out = contract.preserve_spelling(old, new)
    pubs = {e["name"]: e for e in out["/n"]["publishers"]}
    assert pubs["/scan"] == {"name": "/scan", "type": "sensor_msgs/msg/LaserScan", "qos": "sensor_data"}
    assert pubs["/loose"] == {"name": "/loose", "type": "std_msgs/msg/String"}
    assert pubs["/changed"]["qos"]["depth"] == 10
    assert pubs["/new"]["type_hash"] == HASH
    assert out["/m"]["publishers"] == []


def test_preserve_spelling_writes_a_service_qos_the_old_entry_did_not_state():
    # a service entry without `qos` has the services default (issue 49 item 4): an update of a
    # service whose QoS changed writes the new one, where a topic's unstated QoS stays unstated
    old = {"/n": {"service_servers": [{"name": "/reset", "type": "std_srvs/srv/Trigger"}]}}
    new = {"/n": {"service_servers": [{"name": "/reset", "type": "std_srvs/srv/Trigger",
                                       "qos": {"reliability": "BEST_EFFORT"}}]}}
    out = contract.preserve_spelling(old, new)
    assert out["/n"]["service_servers"][0]["qos"] == {"reliability": "BEST_EFFORT"}


def test_scalar_quoting():
    assert contract._scalar("/chatter") == "/chatter"
    assert contract._scalar("true") == "'true'"
    assert contract._scalar("a: b") == "'a: b'"
    assert contract._scalar("x,y") == "'x,y'"
    assert contract._scalar(True) == "true"
    assert contract._scalar(10) == "10"


def test_inlined_schema_reports_what_the_schema_itself_reports():
    """The loader validates with the schema's references inlined (speed); both must agree."""
    from pytest_rmw_introspect.model import contract as contract_module

    original = jsonschema.Draft7Validator(contract_module.schema())
    inlined = contract_module._validator()
    assert '"$ref": "#/definitions/' not in json.dumps(inlined.schema)
    hash_ = "RIHS01_" + "ab" * 32
    documents = [
        {"contract_version": 1, "nodes": {"/talker": {"publishers": [
            {"name": "/chatter", "type": "std_msgs/msg/String", "type_hash": hash_, "qos": {"depth": 10}}]}}},
        {"contract_version": 1, "nodes": {"talker": {}}},
        {"contract_version": 2, "nodes": {}},
        {"contract_version": 1, "nodes": {"/t": {"publishers": [{"name": "chatter", "type": "String"}]}}},
        {"contract_version": 1, "nodes": {"/t": {"publishers": [{"name": "/c", "type": "a/msg/B",
                                                                  "qos": {"reliability": "SOMETIMES"}}]}}},
        {"contract_version": 1, "nodes": {"/t": {"services": []}}, "extra": 1},
    ]
    for document in documents:
        expected = sorted((list(e.absolute_path), e.validator, e.message) for e in original.iter_errors(document))
        got = sorted((list(e.absolute_path), e.validator, e.message) for e in inlined.iter_errors(document))
        assert got == expected, document


def test_gc_paused_restores_the_collector_even_on_errors():
    import gc

    from pytest_rmw_introspect.model import untrusted

    assert gc.isenabled()
    with pytest.raises(ContractError):
        with untrusted.gc_paused():
            assert not gc.isenabled()
            loads("contract_version: 1\nnodes: {talker: {}}\n")
    assert gc.isenabled()
    gc.disable()
    try:
        with untrusted.gc_paused():
            pass
        assert not gc.isenabled()  # a caller's own choice is kept
    finally:
        gc.enable()
