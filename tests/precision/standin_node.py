"""One generic rclpy stand-in for the nodes of the modelled bring-ups (tests/precision/systems).

Each installed package of a modelled system has a table, ``share/<package>/standins.yaml``, that
says for each of its executables the node it creates (default name, lifecycle or not), the
parameters it declares with their defaults, and its publishers, subscriptions, service servers
and clients, action servers and clients (name → type, or name → {type, qos}). The executable the
suite installs (``lib/<package>/<executable>``) runs :func:`main` with that table and its own
name. The node declares its parameters first, then creates its interfaces, so an interface name
may come from a parameter as in the original (``{scan_topic}``, slam_toolbox's scan topic); a
placeholder naming a list parameter makes one interface per element (``{node_names}/change_state``,
a lifecycle manager's clients of the nodes it manages); a node name may take the program's
arguments (``spawner_{arg0}``); an interface with ``when: PARAMETER`` is created only when that
boolean parameter is true (a driver's optional streams). ``nodes_also`` lists further nodes of
the same process (a controller manager's controllers). Nothing is published or served: a capture
only needs the graph."""

from __future__ import annotations

import importlib
import re
import sys
from typing import Any

import rclpy
import rclpy.executors
import yaml
from rclpy.action import ActionClient, ActionServer
from rclpy.executors import ExternalShutdownException
from rclpy.lifecycle import LifecycleNode
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy, qos_profile_sensor_data, qos_profile_system_default
from rclpy.utilities import remove_ros_args

PROFILES = {
    "default": QoSProfile(depth=10),
    "sensor_data": qos_profile_sensor_data,
    "system_default": qos_profile_system_default,
    # REP-2003: maps (and robot_description) are latched
    "map": QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL),
}
KINDS = ("publishers", "subscriptions", "service_servers", "service_clients", "action_servers", "action_clients")
PLACEHOLDER = re.compile(r"\{([^{}]+)\}")


def interface_type(name: str) -> Any:
    """``sensor_msgs/msg/LaserScan`` → the Python class."""
    package, kind, type_name = name.split("/")
    return getattr(importlib.import_module(f"{package}.{kind}"), type_name)


def flatten(parameters: dict[str, Any], prefix: str = "") -> dict[str, Any]:
    flat: dict[str, Any] = {}
    for key, value in parameters.items():
        if isinstance(value, dict):
            flat.update(flatten(value, f"{prefix}{key}."))
        else:
            flat[f"{prefix}{key}"] = value
    return flat


def expand(template: str, values: dict[str, Any]) -> list[str]:
    """The interface names a template stands for, placeholders filled from parameter values."""
    match = PLACEHOLDER.search(template)
    if match is None:
        return [template]
    value = values[match.group(1)]
    items = value if isinstance(value, list) else [value]
    names: list[str] = []
    for item in items:
        names += expand(template[:match.start()] + str(item) + template[match.end():], values)
    return names


def build(node: Node, spec: dict[str, Any]) -> list[Any]:
    declared = flatten(spec.get("parameters") or {})
    values = {name: node.declare_parameter(name, default).value for name, default in declared.items()}
    entities: list[Any] = []
    for kind in KINDS:
        for template, entry in (spec.get(kind) or {}).items():
            entry = entry if isinstance(entry, dict) else {"type": entry}
            if "when" in entry and not values[entry["when"]]:  # created in some configurations only
                continue
            cls = interface_type(entry["type"])
            qos = PROFILES[entry.get("qos", "default")]
            for name in expand(template, values):
                if kind == "publishers":
                    entities.append(node.create_publisher(cls, name, qos))
                elif kind == "subscriptions":
                    entities.append(node.create_subscription(cls, name, lambda _msg: None, qos))
                elif kind == "service_servers":
                    entities.append(node.create_service(cls, name, lambda _req, res: res))
                elif kind == "service_clients":
                    entities.append(node.create_client(cls, name))
                elif kind == "action_servers":
                    entities.append(ActionServer(node, cls, name, lambda goal, result=cls.Result: result()))
                else:
                    entities.append(ActionClient(node, cls, name))
    return entities


def main(table: str, executable: str) -> int:
    with open(table, encoding="utf-8") as stream:
        spec = yaml.safe_load(stream)[executable]
    rclpy.init(args=sys.argv)
    # a node name may come from the command line as in the original (spawner_{arg0})
    arguments = {f"arg{i}": value for i, value in enumerate(remove_ros_args(sys.argv)[1:])}
    executor = rclpy.executors.SingleThreadedExecutor()
    nodes, entities = [], []
    for index, each in enumerate([spec, *(spec.get("nodes_also") or [])]):
        # the process's other nodes (controllers in a controller manager, plugins of mavros) keep
        # their own names: a node-name remapping of the launch file renames the first one only
        name = expand(each["node"], arguments)[0]
        cli_args = [] if index == 0 else ["--ros-args", "-r", f"__node:={name}"]
        node = (LifecycleNode if each.get("lifecycle") else Node)(name, cli_args=cli_args)
        entities += build(node, each)
        nodes.append(node)
        executor.add_node(node)
    try:
        executor.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        del entities
        rclpy.try_shutdown()
    return 0
