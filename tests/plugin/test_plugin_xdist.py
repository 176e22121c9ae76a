"""Under pytest-xdist (-n 2): captures never collide, each golden is written once, and the
controller's terminal summary lists every file the workers wrote."""

from __future__ import annotations

XDIST_TESTS = """
@pytest.mark.parametrize("ns", ["/a", "/b", "/c", "/d"])
def test_namespaced(ns, rmw_capture):
    cap = rmw_capture(script=NODES + "/talker.py", namespace=ns)
    assert cap.node_names == [ns + "/talker"]
    assert cap[ns + "/talker"].names("publishers") == [ns + "/chatter"]

@pytest.mark.interfaces("contracts/talker_a.yaml", script=NODES + "/talker.py", namespace="/a")
def test_a(interfaces):
    assert interfaces.node_names == ["/a/talker"]

@pytest.mark.interfaces("contracts/talker_b.yaml", script=NODES + "/talker.py", namespace="/b")
def test_b(interfaces):
    assert interfaces.node_names == ["/b/talker"]

@pytest.mark.interfaces("contracts/service.yaml", script=NODES + "/service_node.py")
def test_service(interfaces):
    pass

@pytest.mark.interfaces("contracts/action.yaml", script=NODES + "/action_node.py")
def test_action(interfaces):
    pass

# two tests sharing one golden: written once
@pytest.mark.interfaces("contracts/shared.yaml", script=NODES + "/talker.py")
def test_shared_1(interfaces):
    pass

@pytest.mark.interfaces("contracts/shared.yaml", script=NODES + "/talker.py")
def test_shared_2(interfaces):
    pass
"""


def test_update_golden_under_xdist_writes_each_golden_once_and_lists_them(project):
    project.test(XDIST_TESTS)
    result = project.run("-n", "2", "--update-golden")
    result.assert_outcomes(passed=10)
    result.stdout.fnmatch_lines(["*rmw-introspect: golden contracts*"])
    out = result.stdout.str()
    summary = out.split("rmw-introspect: golden contracts", 1)[1]
    for name in ("talker_a", "talker_b", "service", "action", "shared"):
        assert summary.count(f"created  contracts/{name}.yaml") == 1, summary
    assert "5 golden contract(s) written" in summary
    assert "/a/talker:" in project.read("contracts/talker_a.yaml")
    assert "/b/talker:" in project.read("contracts/talker_b.yaml")
    before = {p.name: p.read_bytes() for p in (project.path / "contracts").iterdir()}

    again = project.run("-n", "2")
    again.assert_outcomes(passed=10, skipped=5)  # the goldens' own items: skipped, their marker tests check them
    after = {p.name: p.read_bytes() for p in (project.path / "contracts").iterdir()}
    assert after == before


def test_drift_under_xdist_is_a_failure_with_the_report(project):
    project.test("""
        @pytest.mark.interfaces("a.yaml", script=NODES + "/talker.py")
        def test_a():
            pass

        @pytest.mark.interfaces("b.yaml", script=NODES + "/talker.py")
        def test_b():
            pass
    """)
    project.run("--update-golden", "-n", "2").assert_outcomes(passed=2)
    project.test("""
        @pytest.mark.interfaces("a.yaml", script=NODES + "/talker.py", parameters={"topic": "x"})
        def test_a():
            pass

        @pytest.mark.interfaces("b.yaml", script=NODES + "/talker.py")
        def test_b():
            pass
    """)
    result = project.run("-n", "2")
    result.assert_outcomes(passed=1, failed=1, skipped=2)
    result.stdout.fnmatch_lines(["*PUB_RENAMED*", "*pytest --update-golden test_nodes.py::test_a"])
    result = project.run("-n", "2", "--update-golden")
    result.assert_outcomes(passed=2, skipped=2)
    result.stdout.fnmatch_lines(["updated  a.yaml", "1 golden contract(s) written"])
