"""The C++ example package (examples/rmw_introspect_examples_cpp) built over the overlay: each
rclcpp node's contract checks against a real run, a drifted one fails, and the components are
registered for component containers."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from overlay_support import CPP_EXAMPLES, with_prefix

CONTRACTS = sorted((CPP_EXAMPLES / "contracts").glob("*.interfaces.yaml"))
CLI = [sys.executable, "-m", "pytest_rmw_introspect"]

# the first test of a session may build the C++ examples (a few minutes on 2 cores)
pytestmark = pytest.mark.timeout(1800)


def check(overlay, cpp_examples, contract: Path) -> subprocess.CompletedProcess:
    return subprocess.run([*CLI, "check", str(contract)], env=with_prefix(overlay.env(), cpp_examples),
                          capture_output=True, text=True, timeout=300)


def test_every_cpp_example_node_has_a_contract():
    names = {p.name.removesuffix(".interfaces.yaml") for p in CONTRACTS}
    assert names == {"talker", "listener", "lifecycle_talker", "fibonacci_server", "late_publisher"}


@pytest.mark.parametrize("contract", CONTRACTS, ids=lambda p: p.name.removesuffix(".interfaces.yaml"))
def test_the_cpp_example_contract_holds(overlay, cpp_examples, contract):
    result = check(overlay, cpp_examples, contract)
    assert result.returncode == 0, result.stdout + result.stderr


def test_a_drifted_cpp_contract_fails(overlay, cpp_examples, tmp_path):
    drifted = tmp_path / "talker.interfaces.yaml"
    drifted.write_text((CPP_EXAMPLES / "contracts" / "talker.interfaces.yaml").read_text()
                       .replace("default_value: 2.0", "default_value: 5.0")
                       .replace("depth: 10", "depth: 7"))
    result = check(overlay, cpp_examples, drifted)
    assert result.returncode == 1, result.stdout + result.stderr
    assert "/chatter" in result.stdout and "rate_hz" in result.stdout


def test_the_components_are_registered_for_containers(cpp_examples):
    index = cpp_examples / "share" / "ament_index" / "resource_index" / "rclcpp_components" / "rmw_introspect_examples_cpp"
    entries = dict(line.split(";") for line in index.read_text().split())
    assert set(entries) == {"rmw_introspect_examples_cpp::Talker", "rmw_introspect_examples_cpp::Listener"}
    assert {Path(p).name for p in entries.values()} == {"libtalker_listener_components.so"}
