"""Parameters and lifecycle: what asking the node itself costs a capture.

    python bench/bench_parameters_lifecycle.py [--reps 5]

Every figure is measured in this run, on this machine (medians, ms; the rows are run in turn,
``--reps`` rounds, so that a shared machine's load weighs on all of them alike). The targets are two rclpy
nodes the benchmark writes, captured through the public API, ``pytest_rmw_introspect.capture(...)``,
exactly as the plugin and the CLI run a target (default options: settle 0.1 s, virtual-time
horizon 10 s); the middleware's injection is switched off
(target options ``read_parameters: false`` and ``lifecycle: none``, which the runner passes as
``RMW_INTROSPECT_PARAMETERS=0`` and ``RMW_INTROSPECT_LIFECYCLE=none``), everything else is equal.

Rows:
- a parameter-heavy node: 135 parameters of all nine types (15 each; ranges, descriptions,
  read-only and dynamically typed ones among them), read (list, describe, get) vs. not read;
- a lifecycle node (a publisher, a subscription and a service on configure, a publisher and a
  timer on activate, parameters declared in on_configure): driven to active with its
  parameters read after each transition (the default), left alone with its parameters read
  (``LIFECYCLE=none``), and not asked at all (both off);
- the plain talker of the example package with the default options, for scale.
Each run checks that the capture is what the row claims (parameters there or not, the lifecycle
state reached), so a row cannot silently measure something else.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import pytest_rmw_introspect

PACKAGE = "rmw_introspect_examples"
PER_TYPE = 15

PARAMETER_NODE = r"""
import rclpy
from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
from rclpy.node import Node
from std_msgs.msg import String

PER_TYPE = %d
rclpy.init()
node = Node("many_parameters")
for i in range(PER_TYPE):
    read_only = ParameterDescriptor(description=f"parameter {i}", read_only=i %% 5 == 0)
    node.declare_parameter(f"flag_{i}", i %% 2 == 0, read_only)
    node.declare_parameter(f"count_{i}", i, ParameterDescriptor(
        integer_range=[IntegerRange(from_value=0, to_value=100, step=1)]))
    node.declare_parameter(f"gain_{i}", i / 10, ParameterDescriptor(
        floating_point_range=[FloatingPointRange(from_value=0.0, to_value=10.0, step=0.0)],
        additional_constraints="tuned on the robot"))
    node.declare_parameter(f"name_{i}", f"value {i}", ParameterDescriptor(dynamic_typing=i %% 3 == 0))
    node.declare_parameter(f"group.blob_{i}", [bytes([i]), bytes([255 - i])])
    node.declare_parameter(f"group.flags_{i}", [True, False, i %% 2 == 1])
    node.declare_parameter(f"group.ids_{i}", list(range(i %% 7 + 1)))
    node.declare_parameter(f"group.weights_{i}", [0.5 * i, -1.0, 1e300])
    node.declare_parameter(f"group.nested.names_{i}", ["a", f"b{i}", "c d"])
node.create_publisher(String, "chatter", 10)
rclpy.spin(node)
""" % PER_TYPE

LIFECYCLE_NODE = r"""
import rclpy
from rcl_interfaces.msg import ParameterDescriptor
from rclpy.lifecycle import LifecycleNode, TransitionCallbackReturn
from std_msgs.msg import String
from std_srvs.srv import Trigger


class Managed(LifecycleNode):
    def __init__(self):
        super().__init__("managed")
        self.declare_parameter("rate", 10.0, ParameterDescriptor(description="Hz"))

    def on_configure(self, state):
        for i in range(10):
            self.declare_parameter(f"configured_{i}", i)
        self.status = self.create_lifecycle_publisher(String, "status", 10)
        self.commands = self.create_subscription(String, "cmd", lambda msg: None, 10)
        self.reset = self.create_service(Trigger, "reset", lambda request, response: response)
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state):
        self.diagnostics = self.create_publisher(String, "diagnostics", 10)
        self.timer = self.create_timer(1.0, lambda: self.diagnostics.publish(String(data="ok")))
        return super().on_activate(state)


rclpy.init()
rclpy.spin(Managed())
"""

# target options the runner turns into RMW_INTROSPECT_PARAMETERS=0 / RMW_INTROSPECT_LIFECYCLE=none
PARAMETERS_OFF = {"read_parameters": False}
LIFECYCLE_OFF = {"lifecycle": "none"}


def the_node(cap: Any, fqn: str) -> dict[str, Any]:
    return next(n for n in cap.raw["nodes"] if n["fqn"] == fqn)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--reps", type=int, default=5)
    args = parser.parse_args()

    def captured(check, **target) -> float:
        t0 = time.monotonic()
        cap = pytest_rmw_introspect.capture(**target)
        ms = (time.monotonic() - t0) * 1000
        problem = check(cap)
        if problem:
            raise RuntimeError(f"{target}: {problem}")
        return ms

    def parameters_read(fqn: str, at_least: int):
        def check(cap) -> str | None:
            params = the_node(cap, fqn)["parameters"]
            return None if params is not None and len(params) >= at_least else f"{fqn}: parameters {params!r}"
        return check

    def parameters_not_read(fqn: str):
        def check(cap) -> str | None:
            return None if the_node(cap, fqn)["parameters"] is None else f"{fqn}: its parameters were read"
        return check

    def lifecycle(state: str | None, with_parameters: bool):
        def check(cap) -> str | None:
            record = the_node(cap, "/managed")
            reached = (record["lifecycle"] or {}).get("state")
            if reached != state:
                return f"/managed: lifecycle state {reached!r}, expected {state!r}"
            if (record["parameters"] is not None) != with_parameters:
                return f"/managed: parameters {'missing' if with_parameters else 'read'}"
            has_diagnostics = any(p.name == "/diagnostics" for p in cap["/managed"].publishers)
            return None if has_diagnostics == (state == "active") else "/managed: /diagnostics"
        return check

    total = 9 * PER_TYPE
    with tempfile.TemporaryDirectory() as d:
        params_script = Path(d) / "many_parameters.py"
        params_script.write_text(PARAMETER_NODE)
        lifecycle_script = Path(d) / "managed.py"
        lifecycle_script.write_text(LIFECYCLE_NODE)
        params = {"script": str(params_script)}
        managed = {"script": str(lifecycle_script)}
        talker = {"package": PACKAGE, "executable": "talker"}
        measures = {
            "talker": ("talker (example), default options", lambda: captured(lambda cap: None, **talker)),
            "params_on": (f"{total} parameters, read (default)",
                          lambda: captured(parameters_read("/many_parameters", total), **params)),
            "params_off": (f"{total} parameters, not read (PARAMETERS=0)",
                           lambda: captured(parameters_not_read("/many_parameters"), **PARAMETERS_OFF, **params)),
            "lc_on": ("lifecycle node, driven to active + parameters (default)",
                      lambda: captured(lifecycle("active", True), **managed)),
            "lc_params": ("lifecycle node, left alone + parameters (LIFECYCLE=none)",
                          lambda: captured(lifecycle(None, True), **LIFECYCLE_OFF, **managed)),
            "lc_off": ("lifecycle node, not asked (PARAMETERS=0, LIFECYCLE=none)",
                       lambda: captured(lifecycle(None, False), **PARAMETERS_OFF, **LIFECYCLE_OFF, **managed)),
        }
        for _, measure in measures.values():
            measure()  # warm-up: page cache, Python bytecode, the middleware build
        # Round robin, so that the load of a shared machine weighs on every row alike.
        samples: dict[str, list[float]] = {key: [] for key in measures}
        for _ in range(args.reps):
            for key, (_, measure) in measures.items():
                samples[key].append(measure())
        rows = {key: (name, statistics.median(samples[key])) for key, (name, _) in measures.items()}
    reference = rows["talker"][1]
    print(f"{'median of %d runs' % args.reps:<60} {'ms':>9} {'/ talker':>9}")
    for name, ms in rows.values():
        print(f"{name:<60} {ms:9.1f} {ms / reference:8.2f}x")
    print()
    print(f"{'the injection (default / off)':<60} {'+ms':>9} {'ratio':>9}")
    for name, on, off in (
        (f"{total} parameters read", "params_on", "params_off"),
        ("lifecycle node driven to active, parameters read", "lc_on", "lc_off"),
        ("  of which the driving (configure, activate)", "lc_on", "lc_params"),
    ):
        with_ms, without_ms = rows[on][1], rows[off][1]
        print(f"{name:<60} {with_ms - without_ms:9.1f} {with_ms / without_ms:8.2f}x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
