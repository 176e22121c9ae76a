"""Witnesses of the compatibility rules on the real middleware (issue 49 item 5).

One process, every pair at once: for each pair, a providing end (publisher, service server,
action server) and a requesting end (subscription, client, action client), each in a context of
its own (a DDS participant of its own, as two processes would have). The pairs come as JSON on
stdin (``tests/middleware/test_witnesses.py`` writes them); the result is one JSON object on
stdout: per pair, whether anything got across (a message received, a service answered, an action
server seen) and how many peers the requesting end matched.

Runs on whatever middleware rclpy is linked to: Fast DDS with the PyPI wheels. The caller gives
the process its own ROS_DOMAIN_ID and ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST.
"""

from __future__ import annotations

import json
import sys
import time

import rclpy
from rclpy.action import ActionClient, ActionServer
from rclpy.duration import Duration
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    LivelinessPolicy,
    QoSProfile,
    ReliabilityPolicy,
)

#: how long pairs get to show they connect, at most
TOTAL_S = 8.0
#: the run ends early once nothing new got across for this long, after the first pair did (discovery
#: here: 0.3 s median, up to 3 s)
QUIET_S = 2.5
#: a request unanswered this long is asked again (a BEST_EFFORT one may be lost)
RETRY_S = 0.5


def _duration(ns: int) -> Duration:
    return Duration(nanoseconds=ns) if ns else Duration()


def qos_profile(spec: dict) -> QoSProfile:
    """A contract-form QoS (``model.qos`` explicit form) as rclpy's QoSProfile."""
    profile = QoSProfile(
        history=HistoryPolicy[spec.get("history", "KEEP_LAST")],
        depth=spec.get("depth", 10) or 10,
        reliability=ReliabilityPolicy[spec.get("reliability", "RELIABLE")],
        durability=DurabilityPolicy[spec.get("durability", "VOLATILE")],
        liveliness=LivelinessPolicy[spec.get("liveliness", "SYSTEM_DEFAULT")],
    )
    if spec.get("deadline_ns"):
        profile.deadline = _duration(spec["deadline_ns"])
    if spec.get("liveliness_lease_duration_ns"):
        profile.liveliness_lease_duration = _duration(spec["liveliness_lease_duration_ns"])
    return profile


def _type(name: str):
    package, kind, leaf = name.split("/")
    module = __import__(f"{package}.{kind}", fromlist=[leaf])
    return getattr(module, leaf)


def main() -> int:
    pairs = json.load(sys.stdin)
    started = time.monotonic()
    provider_ctx, requester_ctx = rclpy.Context(), rclpy.Context()
    rclpy.init(context=provider_ctx)
    rclpy.init(context=requester_ctx)
    provider = rclpy.create_node("witness_provider", context=provider_ctx)
    requester = rclpy.create_node("witness_requester", context=requester_ctx)
    executors = []
    for ctx, node in ((provider_ctx, provider), (requester_ctx, requester)):
        executor = SingleThreadedExecutor(context=ctx)
        executor.add_node(node)
        executors.append(executor)

    got: dict[str, bool] = {pair["id"]: False for pair in pairs}
    publishers, subscriptions, clients, pending, action_clients = [], [], [], {}, []
    asked: dict[str, float] = {}

    def on_message(pair_id: str):
        def callback(_msg) -> None:
            got[pair_id] = True
        return callback

    for pair in pairs:
        pid, kind = pair["id"], pair["kind"]
        if kind == "topic":
            pub_qos, sub_qos = qos_profile(pair["provider_qos"]), qos_profile(pair["requester_qos"])
            pub = provider.create_publisher(_type(pair["provider_type"]), pair["provider_name"], pub_qos)
            sub = requester.create_subscription(_type(pair["requester_type"]), pair["requester_name"],
                                                on_message(pid), sub_qos)
            publishers.append((pid, pub, _type(pair["provider_type"])))
            subscriptions.append((pid, sub))
        elif kind == "service":
            srv_type = _type(pair["provider_type"])

            def serve(request, response):
                return response
            provider.create_service(srv_type, pair["provider_name"], serve,
                                    qos_profile=qos_profile(pair.get("provider_qos") or {}))
            client = requester.create_client(_type(pair["requester_type"]), pair["requester_name"],
                                             qos_profile=qos_profile(pair.get("requester_qos") or {}))
            clients.append((pid, client, _type(pair["requester_type"])))
        elif kind == "action":
            action_type = _type(pair["provider_type"])

            def execute(goal_handle, action_type=action_type):
                goal_handle.succeed()
                return action_type.Result()
            ActionServer(provider, action_type, pair["provider_name"], execute)
            action_clients.append((pid, ActionClient(requester, _type(pair["requester_type"]),
                                                     pair["requester_name"])))
        else:
            raise SystemExit(f"unknown pair kind {kind!r}")

    last_change = time.monotonic()
    first_seen: dict[str, float] = {}
    while time.monotonic() - started < TOTAL_S:
        for _pid, pub, msg_type in publishers:
            pub.publish(msg_type())
        for pid, client, srv_type in clients:
            if pid in pending and pending[pid].done() and pending[pid].exception() is None:
                got[pid] = True
            # a request (or its response) sent BEST_EFFORT just after discovery may be lost, as a
            # message may: ask again until one is answered, as a best-effort client must
            stale = pid in pending and not got[pid] and time.monotonic() - asked.get(pid, 0.0) > RETRY_S
            if (pid not in pending or stale) and client.service_is_ready():
                if stale:
                    client.remove_pending_request(pending[pid])
                pending[pid] = client.call_async(srv_type.Request())
                asked[pid] = time.monotonic()
        for pid, action_client in action_clients:
            if action_client.server_is_ready():
                got[pid] = True
        for executor in executors:
            executor.spin_once(timeout_sec=0.02)
        now = time.monotonic()
        for pid, ok in got.items():
            if ok and pid not in first_seen:
                first_seen[pid] = now - started
                last_change = now
        # ends early only once the two participants found each other (something got across)
        if first_seen and now - last_change > QUIET_S:
            break

    result = {}
    for pid, sub in subscriptions:
        result[pid] = {"across": got[pid], "matched": sub.get_publisher_count()}
    for pid, client, _ in clients:
        result[pid] = {"across": got[pid], "matched": int(client.service_is_ready())}
    for pid, action_client in action_clients:
        result[pid] = {"across": got[pid], "matched": int(action_client.server_is_ready())}
    for pid, seconds in first_seen.items():
        result[pid]["after_s"] = round(seconds, 3)
    wall = time.monotonic() - started
    json.dump({"pairs": result, "wall_s": round(wall, 3), "rmw": rclpy.get_rmw_implementation_identifier()},
              sys.stdout)
    for executor in executors:
        executor.shutdown()
    provider.destroy_node()
    requester.destroy_node()
    rclpy.shutdown(context=provider_ctx)
    rclpy.shutdown(context=requester_ctx)
    return 0


if __name__ == "__main__":
    sys.exit(main())
