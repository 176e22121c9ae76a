"""Virtual time through the plugin's library API and marker, with the DEFAULT options: nodes
whose interfaces appear seconds after start, never spin, or end by themselves are captured
right (the same real rclpy nodes as tests/middleware/test_virtual_time.py, which drives the
middleware's environment variables directly)."""

from __future__ import annotations

from pathlib import Path

import pytest

import pytest_rmw_introspect

VT_NODES = Path(__file__).parent.parent / "middleware" / "nodes"

pytestmark = pytest.mark.usefixtures("middleware_env")


@pytest.fixture
def middleware_env(middleware_library, monkeypatch):
    monkeypatch.setenv("RMW_INTROSPECT_LIBRARY", str(middleware_library))


def interfaces(cap: pytest_rmw_introspect.Capture, fqn: str) -> dict[str, list[str]]:
    node = cap[fqn]
    return {list_name: [i["name"] for i in entries] for list_name, entries in node.to_contract(with_parameters=False).items()
            if entries and list_name != "lifecycle"}


@pytest.mark.parametrize(
    "script, fqn, expected",
    [
        ("vt_oneshot_timer.py", "/vt_oneshot", {"publishers": ["/late3"]}),
        ("vt_fifth_tick.py", "/vt_ticker", {"publishers": ["/ticks"], "subscriptions": ["/fifth"]}),
        ("vt_mt_groups.py", "/vt_mt", {"publishers": ["/from_group_a"], "subscriptions": ["/from_group_b"]}),
        ("vt_lifecycle.py", "/vt_lc", {"publishers": ["/lc_vt"], "subscriptions": ["/lc_vt_cmd"]}),
        ("vt_1khz.py", "/vt_fast", {"publishers": ["/fast"]}),
        ("vt_client_gives_up.py", "/impatient_client", {"publishers": ["/asked"], "service_clients": ["/set_flag"]}),
    ],
)
def test_late_interfaces_are_captured_with_default_options(script, fqn, expected):
    # vt_lifecycle drives itself: the middleware must leave its lifecycle alone (it would
    # configure and activate it first, and the node's own configure would then raise).
    lifecycle = "none" if script == "vt_lifecycle.py" else None
    cap = pytest_rmw_introspect.capture(script=str(VT_NODES / script), lifecycle=lifecycle)
    assert interfaces(cap, fqn) == expected
    assert cap.virtual_time is not None and cap.virtual_time.horizon_ms == 10_000
    assert cap.notes() == [] or cap.virtual_time.warp_budget_exhausted  # the 1 kHz node may use up its budget


def test_horizon_zero_turns_virtual_time_off_and_misses_the_late_publisher():
    cap = pytest_rmw_introspect.capture(script=str(VT_NODES / "vt_oneshot_timer.py"), horizon=0)
    assert interfaces(cap, "/vt_oneshot") == {}
    assert cap.virtual_time is not None and cap.virtual_time.jumps == 0


def test_service_created_at_30_s_needs_a_60_s_horizon():
    script = str(VT_NODES / "vt_service_30s.py")
    assert interfaces(pytest_rmw_introspect.capture(script=script), "/vt_slow_server") == {}
    cap = pytest_rmw_introspect.capture(script=script, horizon=60)
    assert interfaces(cap, "/vt_slow_server") == {"service_servers": ["/ready_after_30s"]}


def test_old_school_loop_settles_on_its_sleep_and_is_stepped_through_the_horizon():
    cap = pytest_rmw_introspect.capture(script=str(VT_NODES / "vt_old_school.py"))
    assert interfaces(cap, "/old_school") == {"publishers": ["/topic"]}
    assert cap.settled_by == "sleep" and cap.ever_waited is False
    assert cap.virtual_time is not None and cap.virtual_time.horizon_reached


def test_program_that_finishes_by_itself_is_captured_and_marked():
    cap = pytest_rmw_introspect.capture(script=str(VT_NODES / "vt_finishes.py"))
    assert cap.ended_by_itself and cap.returncode == 0
    assert interfaces(cap, "/short_lived") == {"publishers": ["/short"]}
    assert all(n.destroyed and n.in_teardown for n in cap.raw_nodes)
    assert "ended by itself" in cap.notes()[0]


def test_marker_horizon_and_the_report_notes(project):
    """The marker takes `horizon`; a capture's notes appear in a drift report."""
    project.test(
        """
        @pytest.mark.interfaces("late.yaml", script=NODES + "/../../middleware/nodes/vt_oneshot_timer.py",
                                horizon=0)
        def test_without_virtual_time(interfaces):
            assert interfaces["/vt_oneshot"].publishers == []

        @pytest.mark.interfaces("short.yaml", script=NODES + "/../../middleware/nodes/vt_finishes.py")
        def test_ended(interfaces):
            assert interfaces.ended_by_itself
        """
    )
    project.write("late.yaml", "contract_version: 1\nnodes:\n  /vt_oneshot: {}\n")
    project.write("short.yaml", "contract_version: 1\nnodes:\n  /short_lived: {}\n")
    result = project.run("-rA")
    result.assert_outcomes(passed=1, failed=1, skipped=2)
    result.stdout.fnmatch_lines(["*Notes on the capture:*", "*the program ended by itself (status 0)*"])


def test_a_node_on_sim_time_is_recorded_and_noted():
    cap = pytest_rmw_introspect.capture(script=str(VT_NODES / "talker.py"), parameters={"use_sim_time": True})
    (node,) = cap
    assert node.uses_sim_time
    assert any(f"node {node.fqn} uses sim time" in note for note in cap.notes())
    plain = pytest_rmw_introspect.capture(script=str(VT_NODES / "talker.py"))
    assert not any(n.uses_sim_time for n in plain) and plain.notes() == []
