"""The live check as an independent truth for the rclcpp programs of the overlay tier (issue 52
item 5): every C++ example node runs on Fast DDS over the overlay (RMW_IMPLEMENTATION unset, one
ROS_DOMAIN_ID of its own, localhost discovery), and one `check --live` run compares the graph
with the nodes' contracts, which are the recording middleware's captures. Beyond the notes on what
a live graph cannot show, the one difference is the lifecycle node nobody drives: a capture drives
it to `active`, here it stays `unconfigured`, without the publisher it creates on activation.
About 20 s on a shared 2-core machine, the build of the C++ examples aside (shared with the tier)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys

import pytest
from overlay_support import CPP_EXAMPLES, with_prefix

from pytest_rmw_introspect.live import bringup

PACKAGE = "rmw_introspect_examples_cpp"
CONTRACTS = sorted((CPP_EXAMPLES / "contracts").glob("*.interfaces.yaml"))
#: what the live check finds, by contract (every other contract matches)
EXPECTED = {"lifecycle_talker.interfaces.yaml": {"LIFECYCLE_STATE_CHANGED", "PUB_REMOVED"}}
pytestmark = pytest.mark.timeout(1800)  # the first test of a session may build the C++ examples


def test_every_cpp_example_node_runs_on_fast_dds_as_its_capture_says(overlay, cpp_examples):
    domain = bringup.reserve_domain()
    env = bringup.isolated_env(domain.id, with_prefix(overlay.env(), cpp_examples))
    nodes = [subprocess.Popen([str(cpp_examples / "lib" / PACKAGE / p.name.removesuffix(".interfaces.yaml"))],
                              env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
             for p in CONTRACTS]
    try:
        result = subprocess.run([sys.executable, "-m", "pytest_rmw_introspect", "check", "--live", *map(str, CONTRACTS),
                                 "--format", "json"], env=env, capture_output=True, text=True, timeout=180)
        assert all(node.poll() is None for node in nodes), [node.args for node in nodes if node.poll() is not None]
    finally:
        for node in nodes:
            if node.poll() is None:
                os.killpg(node.pid, signal.SIGINT)
        for node in nodes:
            node.wait(timeout=15)
        domain.release()
    assert result.returncode == 1, result.stdout + result.stderr
    found: dict[str, set[str]] = {}
    for item in json.loads(result.stdout):
        found.setdefault(os.path.basename(item["contract"]), set()).add(item["rule"])
    assert found == EXPECTED, (found, result.stderr)
    assert f"joined ROS_DOMAIN_ID {domain.id} on rmw_fastrtps_cpp" in result.stderr, result.stderr
