"""Names that change every run: the built-in rules, declared patterns, keys of a pattern's
nodes (as a set), and contracts that write and read patterns (model/unstable_names.py)."""

from __future__ import annotations

import time

import pytest

from pytest_rmw_introspect.check import golden
from pytest_rmw_introspect.compare import drift
from pytest_rmw_introspect.errors import ContractError
from pytest_rmw_introspect.model import contract, system_contract
from pytest_rmw_introspect.model.unstable_names import (
    NODE_KEY_SYNTAX,
    PATTERN_SYNTAX,
    NamePattern,
    NameRules,
    contract_keys,
    recognise,
)


def node(*publishers: str, services: tuple[str, ...] = ()) -> dict:
    out = contract.normalize_nodes({"/n": {}})["/n"]
    out["publishers"] = [{"name": p, "type": "std_msgs/msg/String"} for p in publishers]
    out["service_servers"] = [{"name": s, "type": "std_srvs/srv/Trigger"} for s in services]
    return out


@pytest.mark.parametrize(("fqn", "pid", "pattern", "reason"), [
    # tf2_ros: snprintf("transform_listener_impl_%zx", this)
    ("/transform_listener_impl_7ffffdcaec90", None, "/transform_listener_impl_*", "TransformListener"),
    ("/robot1/transform_listener_impl_55d0c8a4e2b0", None, "/robot1/transform_listener_impl_*", "its own address"),
    # tf2_ros: 16 characters of [0-9a-zA-Z], even when all are letters
    ("/static_transform_publisher_AbCdEfGhIjKlMnOp", None, "/static_transform_publisher_*", "16 random"),
    ("/static_transform_publisher_x7Yz0123abcdQRst", None, "/static_transform_publisher_*", "16 random"),
    # ros2cli's DirectNode: _ros2cli_<pid>; ros2doctor: the pid in the middle
    ("/_ros2cli_48213", 48213, "/_ros2cli_*", "process id"),
    ("/ros2doctor_host_48213_node", 48213, "/ros2doctor_host_*_node", "process id"),
    # ros2cli's daemon: _ros2cli_daemon_<domain>_<uuid4().hex>
    ("/_ros2cli_daemon_0_3f2b9c1d0e8a4b7c9d6e5f4a3b2c1d0e", None, "/_ros2cli_daemon_0_*", "hexadecimal"),
    ("/worker_1a2b3c4d_5e6f_4a7b_8c9d_0e1f2a3b4c5d", None, "/worker_*", "uuid"),
    ("/node_12345678a", None, "/node_*", "hexadecimal"),
    ("/logger_1764349200", None, "/logger_*", "8 or more digits"),
    ("/logger_1764349200123456789_x", None, "/logger_*_x", "8 or more digits"),
    ("/recorder_20261128_171500", None, "/recorder_*", "date and time"),
    ("/recorder_2026_11_28_17_15_00", None, "/recorder_*", "date and time"),
])
def test_the_built_in_rules_recognise_names_made_anew_every_run(fqn, pid, pattern, reason):
    found = recognise(fqn, pid)
    assert found is not None and found.pattern == pattern
    assert reason in (found.reason or "")
    assert found.matches(fqn)


@pytest.mark.parametrize(("fqn", "pid"), [
    ("/talker", 4242), ("/camera_front", None), ("/camera_2", 2), ("/lidar_v2", None),
    ("/worker_4242_x", 4243),                 # a number that is not the pid
    ("/node_1234567", None),                  # 7 digits: a name, not a token
    ("/node_deadbeef", None),                 # hex letters only: a word
    ("/static_transform_publisher_short", None),
    ("/transform_listener_impl_xyz", None),
    ("/worker_99", 99),                       # a pid under 100 is not looked for
])
def test_ordinary_names_are_not_patterns(fqn, pid):
    assert recognise(fqn, pid) is None


def test_a_pattern_star_never_crosses_a_namespace():
    pattern = NamePattern("/robot_*/camera")
    assert pattern.matches("/robot_12/camera")
    assert not pattern.matches("/robot_1/x/camera")
    assert not pattern.matches("/robot_1/cameras")


def test_nodes_of_a_pattern_get_keys_under_it_with_their_own_names_moved():
    keyed = contract_keys([
        ("/talker", node("/chatter"), 777),
        ("/anon_3f2b9c1d0e8a4b7c", node("/chatter", services=("/anon_3f2b9c1d0e8a4b7c/reset",)), 777),
    ])
    assert [k for k, _ in keyed] == ["/talker", "/anon_*"]
    moved = keyed[1][1]
    assert [e["name"] for e in moved["service_servers"]] == ["/anon_*/reset"]
    assert "hexadecimal" in moved["unstable_name"]


def test_several_nodes_of_a_pattern_are_paired_with_the_contract_keys_they_resemble():
    a, b = node("/a"), node("/b")
    expected = {"/x_*": dict(b), "/x_*#2": dict(a)}
    named = [("/x_11111111aaaa", a, None), ("/x_22222222bbbb", b, None)]
    keys = dict((k, n["publishers"][0]["name"]) for k, n in contract_keys(named, NameRules.of_contract((), expected)))
    assert keys == {"/x_*": "/b", "/x_*#2": "/a"}
    # without a contract the numbering follows the nodes' contents: the same every run
    def key_of_each(order):
        return {n["publishers"][0]["name"]: k for k, n in contract_keys(order)}

    assert key_of_each(named) == key_of_each(list(reversed(named))) == {"/a": "/x_*", "/b": "/x_*#2"}
    # a third node of the pattern is a new member of the set
    more = contract_keys([*named, ("/x_33333333cccc", node("/c"), None)], NameRules.of_contract((), expected))
    assert sorted(k for k, _ in more) == ["/x_*", "/x_*#2", "/x_*#3"]


def test_declared_patterns_come_first_and_literal_or_launch_given_names_stay():
    declared = NamePattern("/cam_*", "serial number of the camera")
    rules = NameRules.of_contract([declared], {"/logger_1764349200": node()}, stable={"/talker_anon_1a2b3c4d"})
    assert rules.pattern_for("/cam_front", None) == declared
    assert rules.pattern_for("/logger_1764349200", None) is None      # the contract says it literally
    assert rules.pattern_for("/talker_anon_1a2b3c4d", None) is None   # the launch file gave it
    assert rules.pattern_for("/talker_anon_1a2b3c4e", None) is not None


def test_an_unchanged_capture_of_a_pattern_node_does_not_drift_and_a_rename_does():
    text = contract.render(dict(contract_keys([("/anon_3f2b9c1d0e8a", node("/chatter"), None)])))
    loaded = contract.loads(text)
    assert "unstable_name: " in text and "/anon_*:" in text
    run = dict(contract_keys([("/anon_99aa88bb77cc", node("/chatter"), None)], loaded.name_rules()))
    assert drift.compare(loaded.nodes, run) == []
    renamed = dict(contract_keys([("/other_99aa88bb77cc", node("/chatter"), None)], loaded.name_rules()))
    assert {(i.rule, i.node) for i in drift.compare(loaded.nodes, renamed) if i.kind == "node"} >= {
        ("NODE_REMOVED", "/anon_*")} or any(i.rule == "NODE_RENAMED" for i in drift.compare(loaded.nodes, renamed))


def test_a_contract_declares_patterns_and_an_update_keeps_them_and_hand_written_keys(tmp_path):
    path = tmp_path / "c.interfaces.yaml"
    path.write_text(
        "contract_version: 1\n"
        "unstable_names:\n"
        "  - pattern: /cam_*\n"
        "    reason: the driver appends the camera's serial number\n"
        "nodes:\n"
        "  /mine_*:\n"
        "    publishers: []\n")
    loaded = contract.load(path)
    assert loaded.unstable_names == (NamePattern("/cam_*", "the driver appends the camera's serial number"),)
    rules = loaded.name_rules()
    captured = dict(contract_keys([("/cam_A12", node("/image"), None), ("/mine_x", node(), None)], rules))
    assert sorted(captured) == ["/cam_*", "/mine_*"]
    assert golden.update(path, captured) == golden.UPDATED
    text = path.read_text()
    assert text.startswith("contract_version: 1\nunstable_names:\n  - pattern: /cam_*\n")
    assert "  /mine_*:\n    publishers: []\n" in text
    assert "  /cam_*:\n    unstable_name: the driver appends the camera's serial number\n" in text
    assert contract.loads(text).dump() == text


@pytest.mark.parametrize(("text", "where"), [
    ("contract_version: 1\nnodes:\n  /a*b/c d: {}\n", "nodes"),
    ("contract_version: 1\nnodes:\n  /x_*#1: {}\n", "nodes"),
    ("contract_version: 1\nnodes:\n  /x_#2: {}\n", "nodes"),
    ("contract_version: 1\nunstable_names:\n  - pattern: /x_*\nnodes: {}\n", "unstable_names[0]"),
    ("contract_version: 1\nunstable_names:\n  - {pattern: x_*, reason: r}\nnodes: {}\n", "unstable_names[0].pattern"),
    ("contract_version: 1\nunstable_names:\n  - {pattern: /camera, reason: r}\nnodes: {}\n",
     "unstable_names[0].pattern"),
])
def test_bad_patterns_are_errors_with_their_place(text, where):
    with pytest.raises(ContractError) as raised:
        contract.loads(text, path="bad.interfaces.yaml")
    assert "bad.interfaces.yaml:" in str(raised.value) and where in str(raised.value)


def test_the_schema_spells_the_module_s_pattern_syntax():
    document = contract.schema()
    assert document["properties"]["nodes"]["propertyNames"]["pattern"] == NODE_KEY_SYNTAX
    assert document["definitions"]["unstable_names"]["items"]["properties"]["pattern"]["pattern"] == PATTERN_SYNTAX


def test_a_declared_pattern_may_stand_in_a_namespace():
    loaded = contract.loads("contract_version: 1\nunstable_names:\n  - {pattern: /robot_*/camera, reason: r}\n"
                            "nodes:\n  /robot_*/camera: {}\n")
    assert dict(contract_keys([("/robot_7f3a/camera", node(), None)], loaded.name_rules())).keys() == {"/robot_*/camera"}


def test_a_pattern_that_backtracks_in_a_regex_matches_in_linear_time():
    """Issue 50, N17: `/*a*a*a*a*a*a*a*a*b` against a 60-character name took 68 s a match."""
    loaded = contract.loads("contract_version: 1\nunstable_names:\n  - {pattern: /*a*a*a*a*a*a*a*a*b, reason: r}\n"
                            "nodes: {}\n")
    began = time.monotonic()
    keys = contract_keys([("/" + "a" * 60, node(), None), ("/" + "a" * 60 + "b", node(), None)], loaded.name_rules())
    assert [key for key, _node in keys] == ["/" + "a" * 60, "/*a*a*a*a*a*a*a*a*b"]
    assert time.monotonic() - began < 0.5
    assert NamePattern("/x_*_" + "*" * 5000 + "y").matches("/x_" + "_" * 10000) is False


@pytest.mark.parametrize("pattern", ["/*", "/*/*", "/robot1/*", "/**", "/*_*/*"])
def test_a_pattern_that_matches_every_node_is_refused_with_its_place(pattern):
    """Issue 50, N18: a catch-all pattern hid a real rename (`check` said "matches")."""
    for text, where in ((f"contract_version: 1\nunstable_names:\n  - {{pattern: '{pattern}', reason: r}}\nnodes: {{}}\n",
                         "unstable_names[0].pattern"),
                        (f"contract_version: 1\nnodes:\n  '{pattern}': {{}}\n", "nodes")):
        with pytest.raises(ContractError) as raised:
            contract.loads(text, path="broad.interfaces.yaml")
        message = str(raised.value)
        assert "broad.interfaces.yaml" in message and where in message
        assert "matches every node name in its namespace" in message and "/worker_*" in message


def test_a_system_contract_refuses_a_catch_all_pattern_too(tmp_path):
    path = tmp_path / "demo.system.yaml"
    path.write_text("system_version: 1\nlaunch: {path: demo.launch.py}\nunstable_names:\n"
                    "  - {pattern: '/*/*', reason: r}\nnodes: {}\n")
    with pytest.raises(ContractError, match=r"demo\.system\.yaml.*unstable_names\[0\]\.pattern.*matches every node"):
        system_contract.load(path)
