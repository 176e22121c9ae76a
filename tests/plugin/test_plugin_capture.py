"""The capture API on real nodes: the library function, the rmw_capture fixture, target options
(namespace, node name, remappings, parameters, params file), the contract's target block, and
the contract view of QoS variants, services and actions."""

from __future__ import annotations

from pathlib import Path

import pytest

import pytest_rmw_introspect
from pytest_rmw_introspect import Capture, NoNodeCreated, TargetExited
from pytest_rmw_introspect.model.capture_view import Interface, Node

NODES = Path(__file__).parent / "nodes"

pytestmark = pytest.mark.usefixtures("middleware_env")


@pytest.fixture
def middleware_env(middleware_library, monkeypatch):
    monkeypatch.setenv("RMW_INTROSPECT_LIBRARY", str(middleware_library))


def test_library_function_captures_a_talker():
    cap = pytest_rmw_introspect.capture(script=str(NODES / "talker.py"))
    assert isinstance(cap, Capture)
    assert cap.state == "settled" and cap.settled
    assert cap.rmw_implementation == "rmw_introspect_cpp"
    node = cap["/talker"]
    assert isinstance(node, Node) and node.name == "talker" and node.namespace == "/"
    [pub] = node.publishers
    assert isinstance(pub, Interface)
    assert (pub.name, pub.type) == ("/chatter", "std_msgs/msg/String")
    assert pub.type_hash == "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18"
    assert pub.qos == {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE"}
    assert pub.raw_qos["liveliness"] in ("SYSTEM_DEFAULT", "AUTOMATIC")
    # the raw capture keeps the infrastructure the contract view leaves out
    raw_names = {e.name for e in cap.endpoints()}
    assert {"/rosout", "/parameter_events", "/talker/get_parameters"} <= raw_names
    assert node.service_servers == []
    assert cap.wall_time < 10


def test_target_options_become_ros_args(tmp_path):
    params = tmp_path / "params.yaml"
    params.write_text("/**:\n  ros__parameters:\n    listen: /from_file\n")
    cap = pytest_rmw_introspect.capture(
        script=str(NODES / "talker.py"),
        namespace="/robot1",
        node_name="speaker",
        remappings={"chatter": "/speech"},
        parameters={"depth": 4, "reliability": "best_effort"},
        params_file=str(params),
    )
    assert cap.node_names == ["/robot1/speaker"]
    node = cap["/robot1/speaker"]
    [pub] = node.publishers
    assert pub.name == "/speech"
    assert pub.qos["depth"] == 4 and pub.qos["reliability"] == "BEST_EFFORT"
    assert node.names("subscriptions") == ["/from_file"]
    assert "--params-file" in cap.command


def test_parameter_types_survive_the_command_line():
    # "true" must stay a string parameter (the node declares `topic` as a string)
    cap = pytest_rmw_introspect.capture(script=str(NODES / "talker.py"), parameters={"topic": "true"})
    assert cap["/talker"].names("publishers") == ["/true"]


def test_module_target_and_env(tmp_path, monkeypatch):
    pkg = tmp_path / "mynodes"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "talk.py").write_text((NODES / "talker.py").read_text())
    cap = pytest_rmw_introspect.capture(module="mynodes.talk", env={"PYTHONPATH": str(tmp_path)}, cwd=str(tmp_path))
    assert cap.node_names == ["/talker"]


def test_qos_variants_and_private_names():
    cap = pytest_rmw_introspect.capture(script=str(NODES / "qos_node.py"))
    nodes = cap.to_contract_nodes()
    node = nodes["/sensors/qos_node"]
    pubs = {p["name"]: p["qos"] for p in node["publishers"]}
    assert pubs["/sensors/scan"] == {"history": "KEEP_LAST", "depth": 5, "reliability": "BEST_EFFORT",
                                     "durability": "VOLATILE"}
    assert pubs["/map"] == {"history": "KEEP_LAST", "depth": 1, "reliability": "RELIABLE",
                            "durability": "TRANSIENT_LOCAL"}
    subs = {s["name"]: s["qos"] for s in node["subscriptions"]}
    assert subs["/sensors/commands"] == {"history": "KEEP_ALL", "reliability": "RELIABLE", "durability": "VOLATILE",
                                         "liveliness": "AUTOMATIC", "deadline_ns": 100_000_000}
    assert subs["/sensors/qos_node/private"]["depth"] == 5


def test_services_and_clients():
    cap = pytest_rmw_introspect.capture(script=str(NODES / "service_node.py"))
    node = cap.to_contract_nodes()["/service_node"]
    assert [(s["name"], s["type"]) for s in node["service_servers"]] == [("/reset", "std_srvs/srv/Empty")]
    assert [(s["name"], s["type"]) for s in node["service_clients"]] == [("/other/trigger", "std_srvs/srv/Trigger")]
    assert all("qos" not in s for s in node["service_servers"] + node["service_clients"])
    assert all(s["type_hash"].startswith("RIHS01_") for s in node["service_servers"])


def test_actions_are_grouped():
    cap = pytest_rmw_introspect.capture(script=str(NODES / "action_node.py"))
    node = cap["/fibonacci_server"]
    [server] = node.action_servers
    [client] = node.action_clients
    assert (server.name, server.type) == ("/fibonacci", "test_msgs/action/Fibonacci")
    assert (client.name, client.type) == ("/count", "test_msgs/action/Fibonacci")
    assert set(server.type_hash) == {"send_goal", "get_result", "feedback"}
    assert len(server.endpoints) == 5 and len(client.endpoints) == 5
    assert node.publishers == node.subscriptions == node.service_servers == node.service_clients == []
    # the raw endpoints are still there
    assert "/fibonacci/_action/status" in {e.name for e in cap.endpoints()}


def test_library_function_raises_target_errors():
    with pytest.raises(TargetExited) as info:
        pytest_rmw_introspect.capture(script=str(NODES / "crashing_node.py"))
    assert info.value.status == 1 and info.value.partial.node_names == ["/crasher"]
    with pytest.raises(NoNodeCreated):
        pytest_rmw_introspect.capture(script=str(NODES / "no_node.py"))


def test_include_infrastructure():
    cap = pytest_rmw_introspect.capture(script=str(NODES / "talker.py"), include_infrastructure=True)
    node = cap["/talker"]
    assert "/rosout" in node.names("publishers")
    assert "/talker/get_type_description" in node.names("service_servers")


# ---------------------------------------------------------------------------- through pytest


def test_rmw_capture_fixture_relative_paths_and_errors(project):
    project.write("nodes/t.py", (NODES / "talker.py").read_text())
    project.test("""
        from pytest_rmw_introspect import TargetExited

        def test_capture(rmw_capture):
            cap = rmw_capture(script="nodes/t.py", namespace="/x")
            assert cap.node_names == ["/x/talker"]

        def test_expected_failure(rmw_capture):
            with pytest.raises(TargetExited):
                rmw_capture(script=NODES + "/crashing_node.py")

        def test_unexpected_failure(rmw_capture):
            rmw_capture(script=NODES + "/crashing_node.py")
    """)
    result = project.run()
    result.assert_outcomes(passed=2, failed=1)
    result.stdout.fnmatch_lines(["The target script */crashing_node.py crashed: it exited with status 1*"])
    assert "pytest_rmw_introspect/" not in result.stdout.str()


def test_contract_target_block_and_marker_override(project):
    project.write("nodes/t.py", (NODES / "talker.py").read_text())
    project.write("contracts/robot.yaml", """\
        contract_version: 1
        target:
          script: ../nodes/t.py      # relative to this file
          namespace: /robot
        nodes:
          /robot/talker:
            publishers:
              - {name: /robot/chatter, type: std_msgs/msg/String, qos: default}
    """)
    project.test("""
        @pytest.mark.interfaces("contracts/robot.yaml")
        def test_from_contract(interfaces):
            assert interfaces.node_names == ["/robot/talker"]

        @pytest.mark.interfaces("contracts/robot.yaml", namespace="/other")
        def test_marker_overrides(interfaces):
            assert interfaces.node_names == ["/other/talker"]
    """)
    result = project.run()
    result.assert_outcomes(passed=1, failed=1, skipped=1)  # the golden's own item: skipped, its marker test checks it
    result.stdout.fnmatch_lines(["*test_marker_overrides*", "*NODE_REMOVED*"])


def test_option_precedence_marker_contract_cli_ini(project):
    # the capture has depth 3 (RISKY drift); fail_on decides
    project.write("contracts/plain.yaml", """\
        contract_version: 1
        nodes:
          /talker:
            publishers:
              - {name: /chatter, type: std_msgs/msg/String, qos: default}
    """)
    project.write("contracts/lenient.yaml", """\
        contract_version: 1
        options: {fail_on: breaking}
        nodes:
          /talker:
            publishers:
              - {name: /chatter, type: std_msgs/msg/String, qos: default}
    """)
    project.test("""
        T = dict(script=NODES + "/talker.py", parameters={"depth": 3})

        @pytest.mark.interfaces("contracts/plain.yaml", **T)
        def test_plain():
            pass

        @pytest.mark.interfaces("contracts/lenient.yaml", **T)
        def test_contract_lenient():
            pass

        @pytest.mark.interfaces("contracts/lenient.yaml", fail_on="any", **T)
        def test_marker_strict():
            pass
    """)
    # defaults: any
    r = project.run("-rA")
    r.assert_outcomes(passed=1, failed=2, skipped=2)
    r.stdout.fnmatch_lines_random(["FAILED test_nodes.py::test_plain*", "FAILED test_nodes.py::test_marker_strict*",
                                   "PASSED test_nodes.py::test_contract_lenient*"])
    # ini says breaking: plain passes, the contract is lenient anyway, the marker still strict
    project.pytester.makeini("[pytest]\nrmw_introspect_fail_on = breaking\n")
    r = project.run("-rA")
    r.assert_outcomes(passed=2, failed=1, skipped=2)
    r.stdout.fnmatch_lines(["FAILED test_nodes.py::test_marker_strict*"])
    # the command line beats the ini file, the contract beats the command line
    r = project.run("-rA", "--rmw-introspect-fail-on=risky")
    r.assert_outcomes(passed=1, failed=2, skipped=2)
    r.stdout.fnmatch_lines_random(["FAILED test_nodes.py::test_plain*", "PASSED test_nodes.py::test_contract_lenient*"])


def test_ini_ignore_options(project):
    project.write("contracts/c.yaml", """\
        contract_version: 1
        nodes:
          /talker:
            publishers:
              - {name: /chatter, type: std_msgs/msg/String, type_hash: RIHS01_0000000000000000000000000000000000000000000000000000000000000000, qos: default}
    """)
    project.test("""
        @pytest.mark.interfaces("contracts/c.yaml", script=NODES + "/talker.py", parameters={"depth": 3, "listen": "/in"})
        def test_x():
            pass
    """)
    project.run().assert_outcomes(failed=1, skipped=1)
    project.pytester.makeini(
        "[pytest]\nrmw_introspect_ignore_type_hash = true\nrmw_introspect_ignore_qos = depth\n"
        "rmw_introspect_allow_extra = true\n"
    )
    project.run().assert_outcomes(passed=1, skipped=1)
    project.pytester.makeini("[pytest]\nrmw_introspect_ignore_qos = depth\n")
    project.run("--rmw-introspect-ignore-type-hash", "--rmw-introspect-allow-extra").assert_outcomes(passed=1, skipped=1)
    project.run("--rmw-introspect-ignore-type-hash").assert_outcomes(failed=1, skipped=1)


def test_bad_command_line_and_ini_options_are_usage_errors(project):
    project.test("def test_x():\n    pass\n")
    r = project.run("--rmw-introspect-ignore-qos=colour")
    assert r.ret == 4
    r.stderr.fnmatch_lines(["*command line: `ignore_qos` names unknown QoS field(s) colour*"])
    project.pytester.makeini("[pytest]\nrmw_introspect_fail_on = sometimes\n")
    r = project.run()
    assert r.ret == 4
    r.stderr.fnmatch_lines(["*ini file: `fail_on` must be one of any, risky, breaking, got 'sometimes'*"])


def test_timeout_from_the_command_line(project):
    project.test("""
        @pytest.mark.interfaces("c.yaml", script=NODES + "/hanging_node.py")
        def test_x():
            pass
    """)
    r = project.run("--rmw-introspect-timeout=1")
    r.assert_outcomes(failed=1)
    r.stdout.fnmatch_lines(["*did not settle within 1 s*"])


def test_marker_listed_in_pytest_markers(project):
    r = project.run("--markers")
    r.stdout.fnmatch_lines(["@pytest.mark.interfaces(contract, **options): capture the test's target*"])
    r = project.run("--help")
    r.stdout.fnmatch_lines(["*--update-golden*", "*--rmw-introspect-fail-on*", "*rmw_introspect_ignore_type_hash*"])
