"""System contracts (model.system_contract), the system rules (compare.compatibility.check_launched),
system checks without capturing (check.system_pipeline) and the labels of processes (run.system_capture)."""

from __future__ import annotations

import textwrap

import pytest

from pytest_rmw_introspect.check import diff, system_pipeline
from pytest_rmw_introspect.compare import report
from pytest_rmw_introspect.compare.compatibility import LaunchedProcess, check_launched
from pytest_rmw_introspect.errors import ContractError, TargetConfigError, UsageError
from pytest_rmw_introspect.launch.result import LaunchedNode, LaunchParameter, Where
from pytest_rmw_introspect.model import contract_kind, system_contract
from pytest_rmw_introspect.model.vocabulary import Severity
from pytest_rmw_introspect.run import system_capture
from pytest_rmw_introspect.run.target import TargetSpec

STRING = "std_msgs/msg/String"
HASH = "RIHS01_" + "a" * 64

GOOD = """\
# header comment, kept
system_version: 1
launch:
  package: bringup
  file: robot.launch.xml
  arguments: {use_lidar: "true"}
target: {timeout: 30}
options: {fail_on: risky, system_fail_on: any}
processes:
  - package: demo
    executable: talker
    name: /robot/talker
    nodes: [/robot/talker]
  - package: demo
    executable: listener
    name: null
    nodes: [/robot/listener]
nodes:
  /robot/listener:
    publishers: []
    subscriptions:
      - name: /robot/chatter
        type: std_msgs/msg/String
        qos: {history: KEEP_LAST, depth: 10, reliability: RELIABLE, durability: VOLATILE}
    service_servers: []
    service_clients: []
    action_servers: []
    action_clients: []
  /robot/talker:
    publishers:
      - name: /robot/chatter
        type: std_msgs/msg/String
        qos: {history: KEEP_LAST, depth: 10, reliability: BEST_EFFORT, durability: VOLATILE}
    subscriptions: []
    service_servers: []
    service_clients: []
    action_servers: []
    action_clients: []
"""


def test_load_a_system_contract(tmp_path):
    path = tmp_path / "robot.system.yaml"
    path.write_text(GOOD)
    loaded = system_contract.load(path)
    assert loaded.launch == {"package": "bringup", "file": "robot.launch.xml", "arguments": {"use_lidar": "true"}}
    assert loaded.target == {"timeout": 30}
    assert loaded.options == {"fail_on": "risky", "system_fail_on": "any"}
    assert [p["executable"] for p in loaded.processes] == ["talker", "listener"]
    assert sorted(loaded.nodes) == ["/robot/listener", "/robot/talker"]
    assert [sorted(nodes) for _p, nodes in loaded.process_nodes()] == [["/robot/talker"], ["/robot/listener"]]
    assert contract_kind.is_system_file(path)
    other = tmp_path / "named_otherwise.yaml"
    other.write_text(GOOD.replace("# header comment, kept\n", ""))
    assert contract_kind.is_system_file(other)
    plain = tmp_path / "talker.interfaces.yaml"
    plain.write_text("contract_version: 1\nnodes: {}\n")
    assert not contract_kind.is_system_file(plain)


def test_writing_is_deterministic_and_keeps_the_header(tmp_path):
    loaded = system_contract.loads(GOOD)
    text = system_contract.update_text(GOOD, loaded.processes, loaded.nodes)
    assert text == GOOD
    changed = [dict(loaded.processes[0], nodes=["/robot/talker", "/robot/talker2"]), loaded.processes[1]]
    nodes = dict(loaded.nodes)
    nodes["/robot/talker2"] = {}
    updated = system_contract.update_text(GOOD + "extra_key: 1\n", changed, nodes)
    assert updated.startswith(GOOD.split("processes:")[0])
    assert "    nodes: [/robot/talker, /robot/talker2]\n" in updated
    assert "  /robot/talker2:\n    publishers: []\n" in updated
    assert updated.endswith("extra_key: 1\n")  # top-level keys after the blocks are kept as they are
    reloaded = system_contract.loads(updated.replace("extra_key: 1\n", ""))
    assert reloaded.processes == changed
    new = system_contract.render(loaded.processes, loaded.nodes,
                                 header=system_contract.new_header({"path": "robot.launch.xml"}, target={"timeout": 5}))
    assert system_contract.loads(new).launch == {"path": "robot.launch.xml"}
    assert system_contract.loads(new).target == {"timeout": 5}
    assert system_contract.dump_processes([]) == "processes: []\n"


@pytest.mark.parametrize("text,error", [
    ("", "the file is empty"),
    ("system_version: 2\nlaunch: {path: a.xml}\n", r"robot.system.yaml:1: at system_version: system_version 2 is not supported"),
    ("system_version: 1\n", "'launch' is required"),
    ("system_version: 1\nlaunch: {path: a.xml, bogus: 1}\n", r":2: at launch: unknown key\(s\) 'bogus'"),
    ("system_version: 1\nlaunch: {path: a.xml, package: p, file: f}\n", "not both"),
    ("system_version: 1\nlaunch: {package: p}\n", "name the launch file with `package` and `file`"),
    ("system_version: 1\nlaunch: {path: a.xml}\ntarget: {package: p}\n", r"at target: unknown key\(s\) 'package'"),
    ("system_version: 1\nlaunch: {path: a.xml}\noptions: {system_fail_on: never}\n",
     r"at options.system_fail_on: 'never' is not one of: any, risky, breaking"),
    ("system_version: 1\nlaunch: {path: a.xml}\nprocesses:\n  - {executable: e, nodes: [/x]}\n",
     r":4: at processes\[0\].nodes: node /x is not listed under `nodes:`"),
    ("system_version: 1\nlaunch: {path: a.xml}\nlaunch: {path: b.xml}\n", r":3: at launch: duplicate key 'launch'"),
    ("system_version: 1\nlaunch: {path: a.xml\n", "YAML syntax error"),
    ("system_version: 1\nlaunch: {path: a.xml}\nnodes:\n  /a:\n    publishers:\n      - {name: /t, type: a/msg/B, qos: {depth: -3}}\n",
     r"at nodes./a.publishers\[0\].qos"),
])
def test_malformed_system_contracts(tmp_path, text, error):
    path = tmp_path / "robot.system.yaml"
    path.write_text(text)
    with pytest.raises(ContractError, match=error):
        system_contract.load(path)


def test_a_system_contract_lists_every_problem_each_at_its_own_line(tmp_path):
    path = tmp_path / "robot.system.yaml"
    path.write_text("system_version: 1\nlaunch:\n  path: a.xml\n  bogus: 1\ntarget:\n  timeout: 5\n  package: p\n")
    with pytest.raises(ContractError) as info:
        system_contract.load(path)
    text = str(info.value)
    assert f"{path}:4: at launch: unknown key(s) 'bogus'" in text  # the key's own line, not the mapping's (3)
    assert f"{path}:7: at target: unknown key(s) 'package'" in text
    assert "1 more problem in the file:" in text


# ---------------------------------------------------------------------------- system rules


def node(pubs=(), subs=(), servers=(), clients=(), action_servers=()):
    return {
        "publishers": [{"name": n, "type": STRING, "qos": q} for n, q in pubs],
        "subscriptions": [{"name": n, "type": STRING, "qos": q} for n, q in subs],
        "service_servers": [{"name": n, "type": "std_srvs/srv/SetBool"} for n in servers],
        "service_clients": [{"name": n, "type": "std_srvs/srv/SetBool"} for n in clients],
        "action_servers": [{"name": n, "type": "test_msgs/action/Fibonacci"} for n in action_servers],
        "action_clients": [],
    }


def rules(items):
    return sorted((i.rule, i.name, i.requester.label, i.provider.label if i.provider else None) for i in items)


def test_a_system_that_fits_has_no_problems():
    items = check_launched([
        LaunchedProcess("demo/talker", "/talker", {"/talker": node(pubs=[("/chatter", "default")])}),
        LaunchedProcess("demo/listener", None, {"/listener": node(subs=[("/chatter", "default")])}),
    ])
    assert items == []


def test_duplicate_node_names_across_and_within_processes():
    items = check_launched([
        LaunchedProcess("demo/talker", "/robot/talker", {"/robot/talker": node()}),
        LaunchedProcess("demo/talker #2", "/robot/talker", {"/robot/talker": node()}),
        LaunchedProcess("demo/relay", None, {"/relay": node()}, duplicates=("/relay",)),
    ])
    assert rules(items) == [
        ("DUPLICATE_NODE_NAME", "/relay", "demo/relay", "demo/relay"),
        ("DUPLICATE_NODE_NAME", "/robot/talker", "demo/talker #2", "demo/talker"),
    ]
    assert all(i.severity is Severity.BREAKING for i in items)
    assert "2 nodes are named /robot/talker" in items[1].message or "2 nodes are named /robot/talker" in items[0].message


def test_several_servers_for_one_service_or_action():
    items = check_launched([
        LaunchedProcess("a", None, {"/a": node(servers=["/enable"], action_servers=["/fib"])}),
        LaunchedProcess("b", None, {"/b": node(servers=["/enable"], action_servers=["/fib"])}),
        LaunchedProcess("c", None, {"/c": node(servers=["/other"], clients=["/enable"])}),
    ])
    assert rules(items) == [("ACTION_MULTIPLE_SERVERS", "/fib", "b", "a"), ("SERVICE_MULTIPLE_SERVERS", "/enable", "b", "a")]
    text = report.render_compat_text(items, threshold=Severity.BREAKING)
    assert "[SERVICE_MULTIPLE_SERVERS] service server of /a (a) and service server of /b (b): 2 service servers" in text


def test_launched_processes_that_create_no_node_or_another_one():
    items = check_launched([
        LaunchedProcess("demo/silent", None, {}),
        LaunchedProcess("demo/renamed", "/robot/driver", {"/robot/other": node()}),
        LaunchedProcess("demo/ok", "/robot/ok", {"/robot/ok": node()}),
        LaunchedProcess("talker.interfaces.yaml", None, {}, launched=False),  # a node contract promises nothing
    ])
    assert rules(items) == [("LAUNCHED_NODE_NOT_CREATED", "/robot/driver", "demo/renamed", None),
                            ("LAUNCHED_NODE_NOT_CREATED", "demo/silent", "demo/silent", None)]
    by_name = {i.name: i.message for i in items}
    assert by_name["/robot/driver"] == "the launch file starts node /robot/driver here, but the process created /robot/other"
    assert by_name["demo/silent"] == "the launch file starts a node here, but the process created no node at all"


def test_connections_are_checked_between_processes():
    items = check_launched([
        LaunchedProcess("p", None, {"/p": node(pubs=[("/t", "sensor_data")])}),
        LaunchedProcess("s", None, {"/s": node(subs=[("/t", "default"), ("/missing", "default")])}),
    ])
    # in a launched system a subscription nobody publishes (and `external:` does not declare) is BREAKING
    assert rules(items) == [("DANGLING_SUBSCRIPTION", "/missing", "s", None), ("QOS_INCOMPATIBLE", "/t", "s", "p")]


# ---------------------------------------------------------------------------- without capturing


def test_system_rules_on_contract_files(tmp_path):
    (tmp_path / "robot.system.yaml").write_text(GOOD)
    talker = tmp_path / "talker.interfaces.yaml"
    talker.write_text(textwrap.dedent("""\
        contract_version: 1
        nodes:
          /robot/talker:
            publishers:
              - {name: /robot/chatter, type: std_msgs/msg/String}
        """))
    loaded = system_pipeline.load_any(["robot.system.yaml"], base_dir=tmp_path)
    assert [p.label for p in loaded.processes] == ["demo/talker", "demo/listener"]
    assert rules(system_pipeline.compatibility_items(loaded)) == [("QOS_INCOMPATIBLE", "/robot/chatter", "demo/listener", "demo/talker")]
    both = system_pipeline.load_any(["robot.system.yaml", "talker.interfaces.yaml"], base_dir=tmp_path)
    labels = [p.label for p in both.processes]
    assert labels[0].endswith("robot.system.yaml: demo/talker") and labels[1].endswith("robot.system.yaml: demo/listener")
    assert labels[2].endswith("talker.interfaces.yaml")
    found = rules(system_pipeline.compatibility_items(both))
    assert ("DUPLICATE_NODE_NAME", "/robot/talker") in [(r, n) for r, n, _a, _b in found]
    nodes_only = system_pipeline.load_any(["talker.interfaces.yaml"], base_dir=tmp_path)
    assert not nodes_only.any_system and system_pipeline.compatibility_items(nodes_only) == []


def test_one_compatibility_check_reads_contract_files_of_either_kind(tmp_path, monkeypatch):
    """``check_contracts`` (``compat``, ``check_compatible``): the one loader's labels, lines and
    files, for a system contract beside a node contract."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "robot.system.yaml").write_text(GOOD)
    (tmp_path / "talker.interfaces.yaml").write_text(textwrap.dedent("""\
        contract_version: 1
        nodes:
          /robot/talker:
            publishers:
              - {name: /robot/chatter, type: std_msgs/msg/String}
        """))
    result = system_pipeline.check_contracts(["robot.system.yaml", "talker.interfaces.yaml"], fail_on="risky")
    assert result.labels == ["robot.system.yaml", "talker.interfaces.yaml"]
    assert set(result.lines) == set(result.labels) and result.lines["talker.interfaces.yaml"]
    assert result.file_of is not None and result.file_of("robot.system.yaml: demo/talker") == "robot.system.yaml"
    assert {i.rule for i in result.items} >= {"DUPLICATE_NODE_NAME", "QOS_INCOMPATIBLE"} and result.failed
    with pytest.raises(UsageError, match="no contracts given"):
        system_pipeline.check_contracts([])


def test_diff_of_system_contracts(tmp_path):
    old = tmp_path / "old.system.yaml"
    old.write_text(GOOD)
    new = tmp_path / "new.system.yaml"
    new.write_text(GOOD.replace("reliability: BEST_EFFORT", "reliability: RELIABLE"))
    result = diff.diff_contracts(old, new)
    assert [i.rule for i in result.items] == ["QOS_RELIABILITY_STRENGTHENED"]
    assert not result.failed  # the old contract says fail_on: risky, and a stronger offer is SAFE
    strict = diff.diff_contracts(old, new, [({"fail_on": "any"}, "test")])
    assert strict.failed
    assert "QOS_RELIABILITY_STRENGTHENED" in result.render_text()
    assert result.to_json()[0]["contract"].endswith("old.system.yaml")


# ---------------------------------------------------------------------------- processes


def test_process_labels_and_targets(tmp_path):
    assert system_capture.labels([("demo", "talker"), ("demo", "talker"), (None, "/opt/bin/tool"), ("demo", "talker")]) == [
        "demo/talker", "demo/talker #2", "tool", "demo/talker #3"]
    launched = LaunchedNode(
        executable="talker", package="demo", where=Where(tmp_path / "a.launch.xml", 3), name="t", namespace="/r",
        arguments=("--x",), parameters=(LaunchParameter("rate", 2.0), LaunchParameter(file_text="/**: {}\n")),
        remappings=(("a", "b"),), env={"K": "V"})
    spec = system_capture.process_spec(launched, TargetSpec(timeout=7.0, env={"BASE": "1", "K": "base"}), tmp_path)
    assert (spec.package, spec.executable, spec.timeout) == ("demo", "talker", 7.0)
    assert dict(spec.env) == {"BASE": "1", "K": "V"}
    assert spec.arguments == ("--x", "--ros-args", "-r", "__node:=t", "-r", "__ns:=/r", "-p", "rate:=2.0",
                              "--params-file", str(tmp_path / "params_1.yaml"), "-r", "a:=b")
    assert (tmp_path / "params_1.yaml").read_text() == "/**: {}\n"
    plain = LaunchedNode(executable="/opt/bin/tool", package=None, where=launched.where, cwd=tmp_path)
    spec = system_capture.process_spec(plain, TargetSpec(), tmp_path)
    assert spec.command == ("/opt/bin/tool",) and spec.cwd == tmp_path
    given = LaunchedNode(executable="talker", package="demo", where=launched.where, command=("/x/talker", "--ros-args"))
    assert system_capture.process_spec(given, TargetSpec(), tmp_path).command == ("/x/talker", "--ros-args")


def test_launch_blocks(tmp_path):
    (tmp_path / "robot.launch.xml").write_text("<launch/>")
    spec = system_capture.resolve_launch({"path": "robot.launch.xml", "arguments": {"a": True, "b": 2}},
                                         base_dir=tmp_path, source="test", prefixes=[])
    assert spec.path == tmp_path / "robot.launch.xml"
    assert dict(spec.arguments) == {"a": "true", "b": "2"}
    assert spec.describe().endswith("robot.launch.xml a:=true b:=2")
    assert spec.to_block(tmp_path) == {"path": "robot.launch.xml", "arguments": {"a": "true", "b": "2"}}
    with pytest.raises(TargetConfigError, match="unknown launch key"):
        system_capture.resolve_launch({"path": "x", "nope": 1}, base_dir=tmp_path, source="test", prefixes=[])
    with pytest.raises(TargetConfigError, match="`arguments` must be a mapping"):
        system_capture.resolve_launch({"path": "x", "arguments": [1]}, base_dir=tmp_path, source="test", prefixes=[])
