"""Run by the fidelity test in the overlay's environment on Fast DDS: wait until node ARGV[1]
shows ARGV[2] publishers or more to another process (discovery), optionally drive it to active
(ARGV[3] == "activate": a lifecycle node, as a capture drives it), then print as JSON what
another process sees of it: its endpoints with types, type hashes and the QoS DDS carries
(reliability, durability), and its parameters with their descriptors."""

import json
import sys
import time

import rclpy
from lifecycle_msgs.msg import Transition
from lifecycle_msgs.srv import ChangeState
from rcl_interfaces.srv import DescribeParameters, GetParameters, ListParameters
from rclpy.parameter import parameter_value_to_python

TARGET, MIN_PUBLISHERS = sys.argv[1], int(sys.argv[2])
ACTIVATE = len(sys.argv) > 3 and sys.argv[3] == "activate"


def call(node, srv_type, name, request):
    client = node.create_client(srv_type, name)
    if not client.wait_for_service(timeout_sec=10.0):
        raise SystemExit(f"no service {name}")
    future = client.call_async(request)
    rclpy.spin_until_future_complete(node, future, timeout_sec=10.0)
    return future.result()


def endpoints(node, name, ns):
    seen = {}
    for kind, by_node, info in (
        ("publishers", node.get_publisher_names_and_types_by_node, node.get_publishers_info_by_topic),
        ("subscriptions", node.get_subscriber_names_and_types_by_node, node.get_subscriptions_info_by_topic),
    ):
        entries = []
        for topic, types in by_node(name, ns):
            for endpoint in info(topic):
                if endpoint.node_name == name and endpoint.node_namespace == ns:
                    entries.append({"name": topic, "type": types[0], "type_hash": str(endpoint.topic_type_hash),
                                    "reliability": endpoint.qos_profile.reliability.name.upper(),
                                    "durability": endpoint.qos_profile.durability.name.upper()})
        seen[kind] = sorted(entries, key=lambda e: e["name"])
    seen["service_servers"] = sorted(
        ({"name": s, "type": t[0]} for s, t in node.get_service_names_and_types_by_node(name, ns)), key=lambda e: e["name"])
    seen["service_clients"] = sorted(
        ({"name": s, "type": t[0]} for s, t in node.get_client_names_and_types_by_node(name, ns)), key=lambda e: e["name"])
    return seen


def parameters(node, fqn):
    names = call(node, ListParameters, f"{fqn}/list_parameters", ListParameters.Request()).result.names
    described = call(node, DescribeParameters, f"{fqn}/describe_parameters", DescribeParameters.Request(names=names))
    values = call(node, GetParameters, f"{fqn}/get_parameters", GetParameters.Request(names=names))
    out = []
    for d, v in zip(described.descriptors, values.values, strict=True):
        entry = {"name": d.name, "value": parameter_value_to_python(v), "read_only": d.read_only,
                 "description": d.description}
        if d.integer_range:
            r = d.integer_range[0]
            entry["integer_range"] = {"from_value": r.from_value, "to_value": r.to_value, "step": r.step}
        if d.floating_point_range:
            r = d.floating_point_range[0]
            entry["floating_point_range"] = {"from_value": r.from_value, "to_value": r.to_value, "step": r.step}
        out.append(entry)
    return sorted(out, key=lambda e: e["name"])


def main():
    rclpy.init()
    node = rclpy.create_node("fastdds_observer")
    ns, _, name = TARGET.rpartition("/")
    ns = ns or "/"
    if ACTIVATE:
        deadline = time.monotonic() + 20
        while (name, ns) not in node.get_node_names_and_namespaces() and time.monotonic() < deadline:
            rclpy.spin_once(node, timeout_sec=0.1)
        for transition in (Transition.TRANSITION_CONFIGURE, Transition.TRANSITION_ACTIVATE):
            call(node, ChangeState, f"{TARGET}/change_state", ChangeState.Request(transition=Transition(id=transition)))
    deadline = time.monotonic() + 20
    seen = None
    while time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.1)
        if (name, ns) in node.get_node_names_and_namespaces():
            seen = endpoints(node, name, ns)
            if len(seen["publishers"]) >= MIN_PUBLISHERS:
                break
    time.sleep(0.5)  # a last look after discovery settled
    seen = endpoints(node, name, ns)
    seen["parameters"] = parameters(node, TARGET)
    print(json.dumps(seen))
    rclpy.shutdown()


if __name__ == "__main__":
    main()
