"""Every C++ example node's capture equals what Fast DDS shows of it to another process: node
endpoints with their names, types, type hashes and the QoS DDS carries (reliability,
durability), services and clients, and parameters with their descriptors and values. The node
runs on Fast DDS in the overlay (RMW_IMPLEMENTATION unset) and an rclpy observer looks at it,
then the same node is captured on the middleware."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from overlay_support import with_prefix

OBSERVER = Path(__file__).with_name("fastdds_observer.py")
CLI = [sys.executable, "-m", "pytest_rmw_introspect"]
PACKAGE = "rmw_introspect_examples_cpp"
pytestmark = pytest.mark.timeout(1800)

# executable, node, publishers Fast DDS must show before it is looked at, driven to active
EXAMPLES = [
    ("talker", "/talker", 3, False),
    ("listener", "/listener", 2, False),
    ("lifecycle_talker", "/lifecycle_talker", 4, True),
    ("fibonacci_server", "/fibonacci_server", 4, False),
    ("late_publisher", "/late_publisher", 3, False),  # its third appears 2 s after start
]


def seen_on_fast_dds(env: dict[str, str], executable: Path, fqn: str, publishers: int, activate: bool) -> dict:
    env = dict(env, ROS_DOMAIN_ID=str(60 + hash(fqn) % 40))  # apart from other tests' nodes
    node = subprocess.Popen([str(executable)], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        args = [sys.executable, str(OBSERVER), fqn, str(publishers)] + (["activate"] if activate else [])
        out = subprocess.run(args, env=env, capture_output=True, text=True, timeout=90)
        assert out.returncode == 0, out.stderr
        return json.loads(out.stdout)
    finally:
        node.terminate()
        node.wait(timeout=10)


def captured(env: dict[str, str], executable: str, fqn: str) -> dict:
    out = subprocess.run([*CLI, "capture", "--package", PACKAGE, "--executable", executable, "--raw", "--format", "json"],
                         env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)
    alive = [e for e in doc["endpoints"] if e["node"] == fqn and (not e["destroyed"] or e.get("in_teardown"))]
    seen: dict = {}
    for kind, key in (("publisher", "publishers"), ("subscription", "subscriptions")):
        seen[key] = sorted(({"name": e["name"], "type": e["type"], "type_hash": e["type_hash"],
                             "reliability": e["qos"]["reliability"], "durability": e["qos"]["durability"]}
                            for e in alive if e["kind"] == kind), key=lambda e: e["name"])
    for kind, key in (("service", "service_servers"), ("client", "service_clients")):
        seen[key] = sorted(({"name": e["name"], "type": e["type"]} for e in alive if e["kind"] == kind),
                           key=lambda e: e["name"])
    [record] = [n for n in doc["nodes"] if n["fqn"] == fqn]
    seen["parameters"] = sorted(({k: p[k] for k in ("name", "value", "read_only", "description", "integer_range",
                                                    "floating_point_range") if k in p and p[k] not in (None, [])}
                                 for p in record["parameters"]), key=lambda e: e["name"])
    return seen


@pytest.mark.parametrize("executable,fqn,publishers,activate", EXAMPLES, ids=[e[0] for e in EXAMPLES])
def test_the_capture_of_a_cpp_example_equals_what_fast_dds_shows(overlay, cpp_examples, executable, fqn,
                                                                 publishers, activate):
    env = with_prefix(overlay.env(), cpp_examples)
    real = seen_on_fast_dds(env, cpp_examples / "lib" / PACKAGE / executable, fqn, publishers, activate)
    ours = captured(env, executable, fqn)
    assert ours == real
