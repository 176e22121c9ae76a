"""NoDL v2 node documents as contracts (model.nodl): read the way NoDL's documentation and
fixtures write them, validated against NoDL's own schema where it is found, compared with the
same rules (what NoDL cannot state is not compared), and written back as NoDL.

NoDL's schema is not part of this repository: the tests that need it read it from a NoDL source
checkout, `NODL_SRC` (default /work/src/nodl), and are skipped without one. The rest always runs.
"""

from __future__ import annotations

import os
import textwrap
from pathlib import Path

import pytest
import yaml

from pytest_rmw_introspect.compare import drift
from pytest_rmw_introspect.errors import ContractError
from pytest_rmw_introspect.model import contract as contract_module
from pytest_rmw_introspect.model import nodl

NODL_SRC = Path(os.environ.get("NODL_SRC", "/work/src/nodl"))
SCHEMAS = NODL_SRC / "nodl_schema" / "nodl_schema" / "schemas"
needs_schema = pytest.mark.skipif(
    not (SCHEMAS / "nodl.schema.yaml").is_file(),
    reason=f"NoDL's schema not found under NODL_SRC={NODL_SRC}: set NODL_SRC to a checkout of "
           "https://github.com/ros-tooling/nodl (main)")
HASH = "RIHS01_" + "a" * 64

#: a node described the way NoDL's documentation writes documents: no node name, relative and
#: private names, a type without its middle namespace, QoS with only the required policies,
#: parameters in generate_parameter_library's shape
DOCUMENTED = """\
---
nodl_version: 2
description: Publishes a greeting and answers a reset.
parameters:
  rate:
    type: double
    default_value: 2.0
    description: publishing rate in Hz
    validation:
      bounds<>: [0.1, 100.0]
  names:
    type: string_array_fixed_3
    default_value: [a, b]
  mode:
    type: none
publishers:
  - name: chatter
    type: std_msgs/String
    qos:
      history: KEEP_LAST
      depth: 10
      reliability: RELIABLE
  - name: ~/status
    type: std_msgs/msg/String
    qos:
      history: KEEP_LAST
      depth: 1
      reliability: RELIABLE
      durability: TRANSIENT_LOCAL
service_servers:
  - name: /reset
    type: std_srvs/Trigger
action_clients:
  - name: fibonacci
    type: test_msgs/action/Fibonacci
"""


@pytest.fixture(autouse=True)
def _schema_from_the_checkout(monkeypatch):
    """NoDL's schema as a user's NoDL install provides it (here: the checkout), when there is one."""
    if (SCHEMAS / "nodl.schema.yaml").is_file():
        monkeypatch.setenv(nodl.SCHEMA_ENV, str(NODL_SRC))
    else:
        monkeypatch.setenv(nodl.SCHEMA_ENV, "/nonexistent")


def _load(tmp_path: Path, text: str, name: str = "greeter.nodl.yaml") -> contract_module.Contract:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return contract_module.load(path)


def test_a_document_as_nodl_writes_them_is_a_contract_of_the_node_named_by_the_file(tmp_path):
    loaded = _load(tmp_path, DOCUMENTED)
    assert loaded.nodl is not None and loaded.nodl.unnamed
    assert list(loaded.nodes) == ["/greeter"]
    node = loaded.nodes["/greeter"]
    assert node["publishers"] == [
        {"name": "/chatter", "type": "std_msgs/msg/String",
         "qos": {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE"}},
        {"name": "/greeter/status", "type": "std_msgs/msg/String",
         "qos": {"history": "KEEP_LAST", "depth": 1, "reliability": "RELIABLE", "durability": "TRANSIENT_LOCAL"}}]
    assert node["service_servers"] == [{"name": "/reset", "type": "std_srvs/srv/Trigger"}]
    assert node["action_clients"] == [{"name": "/fibonacci", "type": "test_msgs/action/Fibonacci"}]
    assert node["parameters"] == [
        {"name": "rate", "type": "double", "default_value": 2.0, "description": "publishing rate in Hz"},
        {"name": "names", "type": "string_array", "default_value": ["a", "b"]}]  # `none`: nothing to compare
    assert any("NoDL cannot express type hashes, lifecycle states" in n for n in loaded.nodl.notes)


def test_a_json_document_and_a_document_by_content_are_nodl_too(tmp_path):
    as_json = _load(tmp_path, '{"nodl_version": 2, "publishers": [{"name": "/a", "type": "std_msgs/msg/Bool", '
                              '"qos": {"history": "KEEP_ALL", "reliability": "BEST_EFFORT"}}]}', "a.nodl.json")
    assert as_json.nodes["/a"]["publishers"][0]["qos"] == {"history": "KEEP_ALL", "reliability": "BEST_EFFORT"}
    by_content = _load(tmp_path, "nodl_version: 2\n", "plain.yaml")
    assert by_content.nodl is not None and list(by_content.nodes) == ["/plain"]


def test_a_stream_names_each_node_and_binds_only_an_unnamed_document():
    text = "---\n# node: /robot/a\nnodl_version: 2\n---\n# node: /robot/b\nnodl_version: 2\n"
    loaded = contract_module.loads(text, path="two.nodl.yaml")
    assert sorted(loaded.nodes) == ["/robot/a", "/robot/b"]
    assert nodl.bind(loaded.nodl, loaded.nodes, ["/x"], "two.nodl.yaml") == loaded.nodes
    above = contract_module.loads("# node: /robot/a\n---\nnodl_version: 2\n", path="one.nodl.yaml")
    assert list(above.nodes) == ["/robot/a"]  # the comment may also stand above the `---`
    single = contract_module.loads(DOCUMENTED, path="greeter.nodl.yaml")
    bound = nodl.bind(single.nodl, single.nodes, ["/robot/talker"], "greeter.nodl.yaml")
    assert [e["name"] for e in bound["/robot/talker"]["publishers"]] == ["/robot/chatter", "/robot/talker/status"]
    with pytest.raises(ContractError, match=r"does not name its node, and the target created 2 nodes \(/a, /b\): "
                                            r"put a `# node: /fqn` line above it"):
        nodl.bind(single.nodl, single.nodes, ["/a", "/b"], "greeter.nodl.yaml")


@pytest.mark.parametrize(("text", "where", "reason"), [
    ("nodl_version: 1\n", "nodl_version", "nodl_version 1 is not supported: this tool reads NoDL v2"),
    ("nodl_version: 2\nbase: lifecycle_node\n", "base", "unknown key 'base' in a NoDL v2 document"),
    ("nodl_version: 2\npublishers:\n  - name: /a\n    type: std_msgs/msg/String\n    qos: {history: KEEP_SOME, "
     "reliability: RELIABLE}\n", "publishers[0].qos", "invalid QoS history 'KEEP_SOME'"),
    ("nodl_version: 2\npublishers:\n  - name: /a\n    type: String\n", "publishers[0].type", "is not an interface type"),
    ("nodl_version: 2\nparameters:\n  rate: {type: float}\n", "parameters.rate.type", "'float' is not a NoDL parameter type"),
    ("nodl_version: 2\nparameters:\n  rate: {type: double, default_value: fast}\n", "parameters.rate", "fast"),
    ("nodl_version: 2\nsubscriptions:\n  - {name: /a, type: std_msgs/msg/String}\n  - {name: /a, type: std_msgs/msg/String}\n",
     "subscriptions[1].name", "/a is listed twice"),
    ("nodl_version: 2\ninclude:\n  - ref: local://no_such.nodl.yaml\n", "include[0]", "does not exist"),
    ("nodl_version: 2\ninclude:\n  - ref: https://example.org/x.nodl.yaml\n", "include[0]",
     "resolves local:// and nodl:// references, not https://"),
])
def test_bad_documents_are_errors_with_the_place_and_reason(text, where, reason):
    error = pytest.raises(ContractError, contract_module.loads, text, path="bad.nodl.yaml").value
    assert (error.location, reason in error.reason) == (where, True), str(error)
    assert error.line is not None  # the line of the place, for annotations


def test_a_stream_with_an_unnamed_document_among_several_is_an_error():
    with pytest.raises(ContractError, match=r"document 2 of 2 does not name its node") as info:
        contract_module.loads("---\n# node: /a\nnodl_version: 2\n---\nnodl_version: 2\n", path="x.nodl.yaml")
    assert info.value.line == 5


def _captured(**extra) -> dict:
    """The greeter as a capture would give it (contract form), with what NoDL cannot state."""
    node = {
        "lifecycle": "active",
        "publishers": [
            {"name": "/chatter", "type": "std_msgs/msg/String", "type_hash": HASH,
             "qos": {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE",
                     "avoid_ros_namespace_conventions": True}},
            {"name": "/greeter/status", "type": "std_msgs/msg/String", "type_hash": HASH,
             "qos": {"history": "KEEP_LAST", "depth": 1, "reliability": "RELIABLE", "durability": "TRANSIENT_LOCAL"}}],
        "subscriptions": [], "service_clients": [], "action_servers": [],
        "service_servers": [{"name": "/reset", "type": "std_srvs/srv/Trigger", "type_hash": HASH}],
        "action_clients": [{"name": "/fibonacci", "type": "test_msgs/action/Fibonacci"}],
        "parameters": [
            {"name": "names", "type": "string_array", "default_value": ["a", "b"], "declared_in": "constructor"},
            {"name": "rate", "type": "double", "default_value": 2.0, "description": "publishing rate in Hz",
             "read_only": True, "floating_point_range": {"from_value": 0.1, "to_value": 100.0, "step": 0.0}},
        ],
    }
    node.update(extra)
    return {"/greeter": node}


def test_what_nodl_cannot_state_or_the_document_leaves_out_is_not_compared():
    loaded = contract_module.loads(DOCUMENTED, path="greeter.nodl.yaml")
    actual = nodl.project(_captured(), loaded.nodes)
    assert drift.compare(loaded.nodes, actual) == []
    # without the projection the same capture drifts: the test can fail
    assert {i.rule for i in drift.compare(loaded.nodes, _captured())} >= {"PARAM_READ_ONLY_ADDED"}
    # what the document does state is compared
    changed = _captured()
    changed["/greeter"]["publishers"][0]["qos"]["depth"] = 5
    changed["/greeter"]["parameters"][1]["default_value"] = 3.0
    changed["/greeter"]["service_servers"] = []
    rules = {i.rule for i in drift.compare(loaded.nodes, nodl.project(changed, loaded.nodes))}
    assert rules == {"QOS_DEPTH_DECREASED", "PARAM_DEFAULT_CHANGED", "SERVICE_SERVER_REMOVED"}


def test_contract_nodes_written_as_nodl_read_back_the_same(tmp_path):
    nodes = nodl.project(_captured(), {})
    text = nodl.render(_captured())
    assert text.startswith("---\n# node: /greeter\n# lifecycle: active (a lifecycle node: NoDL v2 cannot say so")
    assert "type_hash" not in text and "avoid_ros_namespace_conventions" not in text
    path = tmp_path / "greeter.nodl.yaml"
    path.write_text(text)
    again = contract_module.load(path)
    assert drift.compare(again.nodes, nodes) == []
    # a NoDL contract dumps as NoDL (the lifecycle comment comes from a capture, not from the file)
    assert again.dump() == text.replace("# lifecycle: active (a lifecycle node: NoDL v2 cannot say so, not compared)\n", "")


def test_a_rewrite_keeps_the_descriptions_people_wrote():
    loaded = contract_module.loads(DOCUMENTED, path="greeter.nodl.yaml")
    text = nodl.render(nodl.bind(loaded.nodl, loaded.nodes, ["/greeter"], "g"), loaded.nodl)
    assert yaml.safe_load(text.split("---\n", 2)[1])["description"] == "Publishes a greeting and answers a reset."


@needs_schema
def test_written_nodl_is_valid_under_nodls_own_schema():
    directory, how = nodl.schema_directory()
    assert directory == SCHEMAS and how.startswith(nodl.SCHEMA_ENV)
    rich = _captured()
    rich["/greeter"]["parameters"].append({"name": "blob", "type": "byte_array", "default_value": [1, 255]})
    rich["/greeter"]["parameters"].append({"name": "count", "type": "integer", "default_value": 3})
    rich["/greeter"]["subscriptions"] = [{"name": "/cmd", "type": "std_msgs/msg/String",
                                          "qos": {"history": "KEEP_ALL", "reliability": "BEST_EFFORT",
                                                  "durability": "VOLATILE", "deadline_ns": 100_000_000}}]
    for document in yaml.safe_load_all(nodl.render(rich)):
        assert nodl.schema_problem(document, SCHEMAS) is None


@needs_schema
def test_nodls_schema_finds_what_this_tools_reading_does_not():
    # NoDL requires a topic endpoint's qos; this tool alone would not compare what is left out
    text = "nodl_version: 2\npublishers:\n  - name: /a\n    type: std_msgs/msg/String\n"
    with pytest.raises(ContractError) as info:
        contract_module.loads(text, path="a.nodl.yaml")
    assert info.value.location == "publishers[0]" and "'qos' is a required property (NoDL's schema" in info.value.reason
    assert info.value.line == 3


def test_without_nodls_schema_a_document_is_read_and_a_note_says_how_to_validate(monkeypatch):
    monkeypatch.setenv(nodl.SCHEMA_ENV, "/nonexistent")
    loaded = contract_module.loads("nodl_version: 2\npublishers:\n  - name: /a\n    type: std_msgs/msg/String\n",
                                   path="a.nodl.yaml")
    assert loaded.nodes["/a"]["publishers"] == [{"name": "/a", "type": "std_msgs/msg/String"}]
    assert any(n.startswith(f"not validated against NoDL's own schema ({nodl.SCHEMA_ENV}=/nonexistent holds no "
                            "nodl.schema.yaml)") for n in loaded.nodl.notes)


@needs_schema
def test_nodls_own_fixtures_are_read(tmp_path):
    fixtures = sorted([*NODL_SRC.glob("test_ament_nodl/test/fixtures/*.nodl.*"),
                       *NODL_SRC.glob("ros2nodl/test/describe/fixtures/*.nodl.yaml")])
    assert len(fixtures) >= 10
    for fixture in fixtures:
        loaded = contract_module.load(fixture)
        assert loaded.nodl is not None and len(loaded.nodes) == 1, fixture
    # composed_node includes basic_node (local://): it describes both documents' entities
    composed = contract_module.load(NODL_SRC / "test_ament_nodl/test/fixtures/composed_node.nodl.yaml")
    basic = contract_module.load(NODL_SRC / "test_ament_nodl/test/fixtures/basic_node.nodl.yaml")
    ((_, node),) = composed.nodes.items()
    ((_, included),) = basic.nodes.items()
    assert "/composed_input" in [e["name"] for e in node["subscriptions"]]
    for list_name in ("publishers", "subscriptions", "service_servers", "service_clients"):
        assert {e["name"] for e in included[list_name]} <= {e["name"] for e in node[list_name]}, list_name


@needs_schema
def test_the_schema_is_found_in_an_installed_nodl_schema_package_or_where_the_setting_says(tmp_path, monkeypatch):
    package = tmp_path / "site" / "nodl_schema"
    (package / "schemas").mkdir(parents=True)
    (package / "__init__.py").write_text("raise ImportError('finding the schema must not import the package')\n")
    for name in nodl.SCHEMA_FILES:  # a NoDL install, made of the checkout's files
        (package / "schemas" / name).symlink_to(SCHEMAS / name)
    monkeypatch.delenv(nodl.SCHEMA_ENV)
    monkeypatch.syspath_prepend(str(tmp_path / "site"))
    assert nodl.schema_directory() == (package / "schemas", "the installed nodl_schema package")
    monkeypatch.setenv(nodl.SCHEMA_ENV, str(SCHEMAS))  # the setting wins, and may name the schemas directory
    assert nodl.schema_directory() == (SCHEMAS, f"{nodl.SCHEMA_ENV}={SCHEMAS}")


# ---------------------------------------------------------------------------- include:

BASE = """\
    nodl_version: 2
    parameters:
      rate: {type: double, default_value: 2.0}
    publishers:
      - name: status
        type: std_msgs/msg/String
        qos: {history: KEEP_LAST, depth: 10, reliability: RELIABLE, durability: VOLATILE}
    """


def _with_base(tmp_path: Path, top: str, base: str = BASE) -> contract_module.Contract:
    (tmp_path / "common").mkdir(exist_ok=True)
    (tmp_path / "common" / "base.nodl.yaml").write_text(textwrap.dedent(base))
    return _load(tmp_path, top, name="driver.nodl.yaml")


TOP = """\
    nodl_version: 2
    include:
      - ref: local://common/base.nodl.yaml
    subscriptions:
      - name: cmd
        type: std_msgs/msg/String
        qos: {history: KEEP_LAST, depth: 1, reliability: RELIABLE, durability: VOLATILE}
    """


def test_included_documents_add_their_entities_and_parameters_to_the_node(tmp_path):
    loaded = _with_base(tmp_path, TOP)
    node = loaded.nodes["/driver"]
    assert [e["name"] for e in node["publishers"]] == ["/status"]  # relative names resolve in the including node's namespace
    assert [e["name"] for e in node["subscriptions"]] == ["/cmd"]
    assert [p["name"] for p in node["parameters"]] == ["rate"]


def test_includes_are_followed_recursively_and_a_circle_is_an_error(tmp_path):
    (tmp_path / "common").mkdir()
    (tmp_path / "common" / "middle.nodl.yaml").write_text("nodl_version: 2\ninclude:\n  - ref: local://base.nodl.yaml\n")
    loaded = _with_base(tmp_path, TOP.replace("common/base", "common/middle"))
    assert [e["name"] for e in loaded.nodes["/driver"]["publishers"]] == ["/status"]
    (tmp_path / "common" / "base.nodl.yaml").write_text("nodl_version: 2\ninclude:\n  - ref: local://middle.nodl.yaml\n")
    with pytest.raises(ContractError, match=r"includes itself in a circle \(.*middle.nodl.yaml -> .*base.nodl.yaml -> "
                                            r".*middle.nodl.yaml\)"):
        contract_module.load(tmp_path / "driver.nodl.yaml")


def test_an_entity_defined_here_and_in_an_included_document_is_an_error(tmp_path):
    with pytest.raises(ContractError, match=r"publishers status is defined twice: here and in local://common/base") as info:
        _with_base(tmp_path, TOP.rstrip(" ") + "    publishers:\n      - {name: status, type: std_msgs/msg/String, qos: {history: KEEP_LAST, "
                            "depth: 1, reliability: RELIABLE, durability: VOLATILE}}\n")
    assert (info.value.location, info.value.line) == ("include[0]", 3)


def test_a_nodl_reference_is_found_in_the_ament_index(tmp_path, monkeypatch):
    index = tmp_path / "install" / "share" / "ament_index" / "resource_index" / "nodl"
    index.mkdir(parents=True)
    (index / "robot_base__base").write_text(textwrap.dedent(BASE))
    monkeypatch.setenv("AMENT_PREFIX_PATH", str(tmp_path / "elsewhere") + os.pathsep + str(tmp_path / "install"))
    loaded = _load(tmp_path, TOP.replace("local://common/base.nodl.yaml", "nodl://robot_base/base"), "driver.nodl.yaml")
    assert [e["name"] for e in loaded.nodes["/driver"]["publishers"]] == ["/status"]
    with pytest.raises(ContractError, match=r"nodl://robot_base/other: no NoDL document robot_base__other registered "
                                            r"in the ament index .*ament_nodl_register"):
        _load(tmp_path, TOP.replace("local://common/base.nodl.yaml", "nodl://robot_base/other"), "driver.nodl.yaml")


def test_an_update_keeps_the_include_and_leaves_the_included_entities_to_it(tmp_path):
    loaded = _with_base(tmp_path, TOP)
    nodes = {"/driver": dict(loaded.nodes["/driver"])}
    qos = {"history": "KEEP_LAST", "depth": 1, "reliability": "RELIABLE", "durability": "VOLATILE"}
    nodes["/driver"]["subscriptions"] = [{"name": "/cmd_vel", "type": "std_msgs/msg/String", "qos": qos}]
    text = nodl.render(nodes, loaded.nodl, loaded.path)
    written = yaml.safe_load(text.split("---\n", 2)[1])
    assert written["include"] == [{"ref": "local://common/base.nodl.yaml"}]
    assert "publishers" not in written and "parameters" not in written  # still the included document's
    assert [e["name"] for e in written["subscriptions"]] == ["/cmd_vel"]
    (tmp_path / "driver.nodl.yaml").write_text(text)  # and reads back as the same node
    again = contract_module.load(tmp_path / "driver.nodl.yaml")
    assert drift.compare(again.nodes, nodl.project(nodes, again.nodes)) == []


def test_an_update_that_changes_an_included_entity_names_it_and_what_to_do(tmp_path):
    loaded = _with_base(tmp_path, TOP)
    nodes = {"/driver": dict(loaded.nodes["/driver"])}
    nodes["/driver"]["publishers"] = [{"name": "/status", "type": "std_msgs/msg/Header"}]
    with pytest.raises(ContractError, match=r"publishers /status comes from an included document and the node "
                                            r"has it otherwise: update the included document") as info:
        nodl.render(nodes, loaded.nodl, loaded.path)
    assert info.value.path == loaded.path
