"""The live reader: one process that joins the running ROS 2 graph and writes what it sees.

Run as ``python -m pytest_rmw_introspect.live.reader --settle S --timeout T --parameter-timeout P
[--expect FQN ...]`` by ``live.graph`` (never by hand: the environment it gets is checked there), on the middleware
of its environment (``RMW_IMPLEMENTATION``, ``ROS_DOMAIN_ID``, ``ROS_AUTOMATIC_DISCOVERY_RANGE``).
It waits until the graph (nodes, topics and their endpoints, each node's services and clients)
has not changed for ``S`` seconds (for ``live.ABSENT_AFTER`` seconds while a node of ``--expect``,
which the contracts name, is not in it: discovery comes in bursts), at most ``T`` seconds, saying
on stderr what it waits for;
then reads every node, every publisher and subscription with its type, type hash and QoS as the
middleware reports them (``get_publishers_info_by_topic``, ``get_subscriptions_info_by_topic``),
every service server and client per node, each node's parameters through its own parameter
services (ListParameters, GetParameters, DescribeParameters; at most ``P`` seconds for all nodes
together) and the state of each lifecycle node (``<node>/get_state``). It prints one JSON object
on stdout: ``capture``, a document in the recording middleware's capture format
(docs/design.md section 1), and ``live``, what only a live read knows (the domain, whether the
graph settled, the nodes whose services did not answer).

Its own node (hidden, ``_rmw_introspect_live_<pid>``, without parameter services or rosout) is
left out of what it writes, and is destroyed with its context before the process ends.

It imports nothing of the package but ``live``'s exit statuses and times: it runs in the reader process only.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import sys
import time
from collections import Counter
from collections.abc import Collection
from typing import Any

import rclpy
from lifecycle_msgs.srv import GetState  # type: ignore[import-untyped]
from rcl_interfaces.srv import DescribeParameters, GetParameters, ListParameters  # type: ignore[import-untyped]
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.utilities import get_rmw_implementation_identifier

from . import ABSENT_AFTER, EXIT_EMPTY, EXIT_WRONG_MIDDLEWARE

#: rcl_interfaces/msg/ParameterType → the capture's (NoDL) spelling
PARAMETER_TYPES = {1: "bool", 2: "integer", 3: "double", 4: "string", 5: "byte_array", 6: "bool_array",
                   7: "integer_array", 8: "double_array", 9: "string_array"}
_VALUE_FIELDS = {1: "bool_value", 2: "integer_value", 3: "double_value", 4: "string_value", 5: "byte_array_value",
                 6: "bool_array_value", 7: "integer_array_value", 8: "double_array_value",
                 9: "string_array_value"}
#: what a middleware that refuses the reader's own purpose identifies as
RECORDING_MIDDLEWARE = "rmw_introspect_cpp"
#: the node name prefix of the ros2 command line's daemon: not part of any system
ROS2CLI_DAEMON = "_ros2cli_daemon_"
#: the node `ros2 launch` (launch_ros) adds to the graph, ``/launch_ros_<pid>``: it drives lifecycle
#: nodes and loads components for the launch file, and is no part of the system it starts
LAUNCHER = re.compile(r"launch_ros_[0-9]+")
#: the node name prefix of live readers (this one's and others': not part of any system)
READER_PREFIX = "_rmw_introspect_live_"
INFINITE_NS = 9_223_372_036_854_775_807
#: seconds after joining before the graph can count as stable, whatever the settle time: a new
#: participant learns of the others one by one (measured with Fast DDS on a loaded 2-core machine:
#: gaps of more than a second between two nodes of a running system, up to 3.1 s in all)
JOIN_WINDOW = 3.0


def say(text: str) -> None:
    print(f"rmw-introspect: live: {text}", file=sys.stderr, flush=True)


def _fqn(namespace: str, name: str) -> str:
    return ("/" if namespace in ("", "/") else namespace.rstrip("/") + "/") + name


def _duration_ns(duration: Any) -> int:
    ns = int(duration.nanoseconds)
    return -1 if ns >= INFINITE_NS else ns


def _qos(profile: Any) -> dict[str, Any]:
    return {
        "history": profile.history.name,
        "depth": int(profile.depth),
        "reliability": profile.reliability.name,
        "durability": profile.durability.name,
        "liveliness": profile.liveliness.name,
        "deadline_ns": _duration_ns(profile.deadline),
        "lifespan_ns": _duration_ns(profile.lifespan),
        "liveliness_lease_duration_ns": _duration_ns(profile.liveliness_lease_duration),
        "avoid_ros_namespace_conventions": bool(profile.avoid_ros_namespace_conventions),
    }


def _hash(value: Any) -> str | None:
    text = str(value) if value is not None else ""
    return text if text.startswith("RIHS01_") and text.removeprefix("RIHS01_").strip("0") else None


class Reader:
    """The reader's node and what it has read."""

    def __init__(self, node: Any, executor: Any) -> None:
        self.node = node
        self.executor = executor
        self.own = node.get_fully_qualified_name()
        #: other live readers seen in the graph (left out like this one)
        self.other_readers: set[str] = set()
        self.launchers: set[str] = set()
        #: the names more than one node of the last read has (fully qualified name: how many)
        self.duplicates: dict[str, int] = {}

    def spin_once(self, timeout: float) -> None:
        self.executor.spin_once(timeout_sec=timeout)

    # ------------------------------------------------------------------ the graph
    def nodes(self) -> list[tuple[str, str, str]]:
        """(name, namespace, enclave) of every node but the reader's own and the ros2 daemon."""
        out = []
        for name, namespace, enclave in self.node.get_node_names_and_namespaces_with_enclaves():
            if _fqn(namespace, name) == self.own or name.startswith(ROS2CLI_DAEMON):
                continue
            if name.startswith(READER_PREFIX):
                self.other_readers.add(_fqn(namespace, name))
                continue
            if namespace in ("", "/") and LAUNCHER.fullmatch(name):
                self.launchers.add(_fqn(namespace, name))
                continue
            out.append((name, namespace, enclave))
        return sorted(out)

    def signature(self) -> Any:
        """What must stay the same for the graph to count as stable."""
        nodes = self.nodes()
        topics = sorted((name, tuple(types)) for name, types in self.node.get_topic_names_and_types())
        counts = [(name, self.node.count_publishers(name), self.node.count_subscribers(name)) for name, _ in topics]
        services = []
        for name, namespace, _ in nodes:
            try:
                services.append(sorted(map(str, self.node.get_service_names_and_types_by_node(name, namespace))))
                services.append(sorted(map(str, self.node.get_client_names_and_types_by_node(name, namespace))))
            except Exception:  # a node gone between the two calls: the graph is changing
                services.append(["gone", name, namespace])
        return (nodes, topics, counts, services)

    def read(self) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
        """The nodes and endpoints of the graph, as capture records."""
        records: dict[str, dict[str, Any]] = {}
        listed = self.nodes()  # each node once, so two nodes of one name are listed twice
        named = Counter(_fqn(namespace, name) for name, namespace, _ in listed)
        self.duplicates = {fqn: count for fqn, count in sorted(named.items()) if count > 1}
        for name, namespace, enclave in listed:
            fqn = _fqn(namespace, name)
            if fqn not in records:
                records[fqn] = {"id": len(records) + 1, "seq": len(records) + 1, "name": name, "namespace": namespace,
                                "fqn": fqn, "enclave": enclave or "/"}
        endpoints: list[dict[str, Any]] = []

        def add(kind: str, node_name: str, namespace: str, name: str, type_name: str, type_hash: str | None,
                qos: dict[str, Any]) -> None:
            fqn = _fqn(namespace, node_name)
            if fqn not in records:  # the reader's own endpoints, the daemon's, another reader's
                return
            record = records[fqn]
            endpoints.append({"seq": len(endpoints) + 1, "kind": kind, "node_id": record["id"], "node": fqn,
                              "name": name, "type": type_name, "type_hash": type_hash, "qos": qos})

        for topic, _types in sorted(self.node.get_topic_names_and_types()):
            for info in self.node.get_publishers_info_by_topic(topic):
                add("publisher", info.node_name, info.node_namespace, topic, info.topic_type,
                    _hash(getattr(info, "topic_type_hash", None)), _qos(info.qos_profile))
            for info in self.node.get_subscriptions_info_by_topic(topic):
                add("subscription", info.node_name, info.node_namespace, topic, info.topic_type,
                    _hash(getattr(info, "topic_type_hash", None)), _qos(info.qos_profile))
        for record in list(records.values()):
            try:
                served = self.node.get_service_names_and_types_by_node(record["name"], record["namespace"])
                called = self.node.get_client_names_and_types_by_node(record["name"], record["namespace"])
            except Exception:  # gone since it was listed
                continue
            for kind, found in (("service", served), ("client", called)):
                for name, types in sorted(found):
                    for type_name in types:
                        add(kind, record["name"], record["namespace"], name, type_name, None, {})
        return list(records.values()), endpoints

    # ------------------------------------------------------------------ the nodes' own services
    def spin_until(self, futures: list[Any], deadline: float) -> None:
        while time.monotonic() < deadline and not all(f.done() for f in futures):
            self.spin_once(0.02)

    def ask(self, requests: dict[Any, tuple[Any, str, Any]], deadline: float) -> dict[Any, Any]:
        """Send each request (key → (service type, service name, request)) once its server is
        ready; the answers by key (absent: no server, or no answer before ``deadline``)."""
        clients = {key: self.node.create_client(srv, name) for key, (srv, name, _req) in requests.items()}
        futures: dict[str, Any] = {}
        try:
            while time.monotonic() < deadline and len(futures) < len(clients):
                for key, client in clients.items():
                    if key not in futures and client.service_is_ready():
                        futures[key] = client.call_async(requests[key][2])
                if len(futures) < len(clients):
                    self.spin_once(0.02)
            self.spin_until(list(futures.values()), deadline)
            return {key: f.result() for key, f in futures.items() if f.done() and f.result() is not None}
        finally:
            for client in clients.values():
                self.node.destroy_client(client)

    def parameters(self, records: list[dict[str, Any]], endpoints: list[dict[str, Any]], budget: float) -> list[str]:
        """Each node's parameters into its record (``parameters``, or ``parameters_error``);
        returns the nodes whose services did not answer. Every node is asked on its own, so a
        node that never answers does not hold up the others (they all share ``budget``)."""
        served = {(e["node"], e["name"]) for e in endpoints if e["kind"] == "service"}
        deadline = time.monotonic() + budget
        asking = {r["fqn"]: ParameterQuestions(self.node, r["fqn"])
                  for r in records if (r["fqn"], f"{r['fqn']}/list_parameters") in served}
        try:
            waiting = set(asking)
            while waiting and time.monotonic() < deadline:
                waiting = {fqn for fqn in waiting if not asking[fqn].step()}
                if waiting:
                    self.spin_once(0.02)
        finally:
            for questions in asking.values():
                questions.destroy()
        unanswered = []
        for record in records:
            if record["fqn"] not in asking:
                continue
            questions = asking[record["fqn"]]
            if questions.values is None:
                unanswered.append(record["fqn"])
                record["parameters_error"] = (f"its parameter services did not answer the live reader within "
                                              f"{budget:g} s")
                continue
            record["parameters"] = [_parameter(name, value, descriptor) for name, value, descriptor
                                    in zip(questions.names or [], questions.values, questions.descriptors,
                                           strict=False)]
        return unanswered

    def lifecycle(self, records: list[dict[str, Any]], endpoints: list[dict[str, Any]], budget: float) -> list[str]:
        """Each lifecycle node's state into its record (``lifecycle``); returns the lifecycle
        nodes whose ``get_state`` did not answer."""
        served = {(e["node"], e["name"], e["type"]) for e in endpoints if e["kind"] == "service"}
        managed = [r for r in records if (r["fqn"], f"{r['fqn']}/get_state", "lifecycle_msgs/srv/GetState") in served]
        answers = self.ask({r["fqn"]: (GetState, f"{r['fqn']}/get_state", GetState.Request()) for r in managed},
                           time.monotonic() + budget)
        unanswered = []
        for record in managed:
            answer = answers.get(record["fqn"])
            state = answer.current_state.label if answer is not None else None
            if state is None:
                unanswered.append(record["fqn"])
            record["lifecycle"] = {"target": "none", "initial_state": state, "state": state, "transitions": []}
        return unanswered


class ParameterQuestions:
    """One node's parameter services asked in turn: ListParameters, then GetParameters and
    DescribeParameters (and, when rclpy answers an empty list because one parameter has no
    value, GetParameters for each name); :meth:`step` moves on as answers come."""

    def __init__(self, node: Any, fqn: str) -> None:
        self.node = node
        self.lister = node.create_client(ListParameters, f"{fqn}/list_parameters")
        self.getter = node.create_client(GetParameters, f"{fqn}/get_parameters")
        self.describer = node.create_client(DescribeParameters, f"{fqn}/describe_parameters")
        self.futures: dict[str, Any] = {}
        self.singles: list[Any] = []
        self.names: list[str] | None = None
        self.values: list[Any] | None = None
        self.descriptors: list[Any] = []

    def step(self) -> bool:
        """Send what can be sent; True once every answer is in."""
        f = self.futures
        if "list" not in f:
            if self.lister.service_is_ready():
                f["list"] = self.lister.call_async(ListParameters.Request(depth=0))
            return False
        if not f["list"].done() or f["list"].result() is None:
            return False
        names = self.names = list(f["list"].result().result.names)
        if "get" not in f:
            if self.getter.service_is_ready() and self.describer.service_is_ready():
                f["get"] = self.getter.call_async(GetParameters.Request(names=names))
                f["describe"] = self.describer.call_async(DescribeParameters.Request(names=names))
            return False
        if not all(f[k].done() and f[k].result() is not None for k in ("get", "describe")):
            return False
        values = list(f["get"].result().values)
        if len(values) != len(names):
            if not self.singles:
                self.singles = [self.getter.call_async(GetParameters.Request(names=[n])) for n in names]
                return False
            if not all(x.done() and x.result() is not None for x in self.singles):
                return False
            values = [x.result().values[0] if x.result().values else None for x in self.singles]
        self.values, self.descriptors = values, list(f["describe"].result().descriptors)
        return True

    def destroy(self) -> None:
        for client in (self.lister, self.getter, self.describer):
            self.node.destroy_client(client)


def _value(value: Any) -> Any:
    if value is None:
        return None
    kind = int(value.type)
    if kind not in _VALUE_FIELDS:
        return None
    raw = getattr(value, _VALUE_FIELDS[kind])
    if kind == 3:
        return _double(raw)
    if kind == 8:
        return [_double(v) for v in raw]
    if kind == 5:
        return [b if isinstance(b, int) else int.from_bytes(b, "little") for b in raw]
    if kind in (6, 7, 9):
        return list(raw)
    return raw


def _double(value: float) -> Any:
    if math.isnan(value):
        return "nan"
    if math.isinf(value):
        return "inf" if value > 0 else "-inf"
    return float(value)


def _range(ranges: Any, integer: bool) -> dict[str, Any] | None:
    for r in ranges:
        if integer:
            return {"from_value": int(r.from_value), "to_value": int(r.to_value), "step": int(r.step)}
        return {"from_value": _double(r.from_value), "to_value": _double(r.to_value), "step": _double(r.step)}
    return None


def _parameter(name: str, value: Any, descriptor: Any) -> dict[str, Any]:
    kind = (int(value.type) if value is not None else 0) or int(descriptor.type)
    return {
        "name": name,
        "type": PARAMETER_TYPES.get(kind),
        "value": _value(value),
        "read_only": bool(descriptor.read_only),
        "dynamic_typing": bool(descriptor.dynamic_typing),
        "description": descriptor.description,
        "additional_constraints": descriptor.additional_constraints,
        "integer_range": _range(descriptor.integer_range, True),
        "floating_point_range": _range(descriptor.floating_point_range, False),
    }


def wait_stable(reader: Reader, settle: float, timeout: float,
                expect: Collection[str] = ()) -> tuple[bool, float, list[str]]:
    """Poll the graph until it has not changed for ``settle`` seconds with a node in it, and
    :data:`JOIN_WINDOW` seconds have passed since joining, at most ``timeout`` seconds; while a
    node of ``expect`` (the nodes the contracts name) is not in it, until it has not changed for
    ``live.ABSENT_AFTER`` seconds. (settled, seconds waited, the expected nodes not seen)."""
    start = time.monotonic()
    last, since, said = None, start, 0.0
    wanted = set(expect)
    while True:
        reader.spin_once(0.05)
        now = time.monotonic()
        current = reader.signature()
        if current != last:
            last, since = current, now
        nodes = len(current[0])
        missing = _missing(wanted, current)
        quiet = settle if not missing else max(settle, ABSENT_AFTER)
        if nodes and now - since >= quiet and now - start >= min(JOIN_WINDOW, timeout):
            return True, now - start, missing
        if now - start >= timeout:
            return False, now - start, missing
        if now - said >= 1.0:
            said = now
            what = (f"{nodes} node(s), {len(current[1])} topic(s); unchanged for {now - since:.1f} s of {quiet:g} s"
                    if nodes else "no node yet")
            if missing:
                what += f"; not seen yet: {_listed(missing)}"
            say(f"waiting for the graph to be stable: {what} ({now - start:.0f} s of at most {timeout:g} s)")
        time.sleep(0.1)


def _missing(wanted: Collection[str], signature: tuple) -> list[str]:
    """The nodes of ``wanted`` (fully qualified names) not in the graph of ``signature``."""
    return sorted(set(wanted) - {_fqn(namespace, name) for name, namespace, _ in signature[0]})


def _listed(names: list[str], most: int = 5) -> str:
    return ", ".join(names[:most]) + (f" and {len(names) - most} more" if len(names) > most else "")


def snapshot(reader: Reader, args: argparse.Namespace, live: dict[str, Any], identifier: str, *,
             parameters: bool) -> dict[str, Any] | None:
    """The graph now as the reader's answer (``parameters``: ask the nodes' services too); None
    when it holds no node."""
    records, endpoints = reader.read()
    if not records:
        return None
    if parameters:
        say(f"read {len(records)} node(s), {len(endpoints)} endpoint(s) after {live['waited_s']:.1f} s"
            f"{'' if live['settled'] else ' (the graph was still changing when the time was up)'}; asking their "
            "parameters")
        live["parameters_unanswered"] = reader.parameters(records, endpoints, args.parameter_timeout)
        live["lifecycle_unanswered"] = reader.lifecycle(records, endpoints, args.parameter_timeout)
    capture = {"format": "rmw_introspect_capture", "format_version": 1, "format_minor": 0,
               "rmw_implementation": identifier, "pid": None, "argv": [], "state": "live",
               "nodes": records, "endpoints": endpoints}
    return {"capture": capture, "live": {**live, "at": time.time(), "other_readers": sorted(reader.other_readers),
                                         "launchers": sorted(reader.launchers), "duplicate_nodes": reader.duplicates}}


def watch(reader: Reader, args: argparse.Namespace, live: dict[str, Any], identifier: str) -> None:
    """After the first answer: a new answer (a line, without parameters) each time the graph has
    changed and is stable again for ``--settle`` seconds, until ``--duration`` seconds have
    passed (0: until interrupted). Memory stays flat: nothing is kept but the last signature."""
    end = time.monotonic() + args.duration if args.duration > 0 else math.inf
    last = reader.signature()
    try:
        while time.monotonic() < end:
            reader.spin_once(0.05)
            time.sleep(0.2)
            current = reader.signature()
            if current == last:
                continue
            since = time.monotonic()  # changed: wait until it is stable again (or the time is up)
            while time.monotonic() < end and time.monotonic() - since < args.settle:
                reader.spin_once(0.05)
                time.sleep(0.1)
                newer = reader.signature()
                if newer != current:
                    current, since = newer, time.monotonic()
            last = current
            # what is missing now, not what was missing at the first answer
            now = {**live, "settled": True, "waited_s": 0.0, "expected_absent": _missing(args.expect, current)}
            answer = snapshot(reader, args, now, identifier, parameters=False)
            print(json.dumps(answer if answer is not None else {"live": {**live, "at": time.time()}}), flush=True)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m pytest_rmw_introspect.live.reader")
    parser.add_argument("--settle", type=float, default=2.0)
    parser.add_argument("--timeout", type=float, default=30.0)
    parser.add_argument("--parameter-timeout", type=float, default=5.0)
    parser.add_argument("--expect", action="append", default=[], metavar="FQN",
                        help="a node the contracts name: wait for it (repeatable)")
    parser.add_argument("--watch", action="store_true", help="a new answer (one JSON line) at every change")
    parser.add_argument("--duration", type=float, default=0.0, help="with --watch: seconds to watch (0: until Ctrl-C)")
    args = parser.parse_args(argv)

    context = rclpy.Context()
    rclpy.init(context=context)
    node = executor = None
    try:
        identifier = get_rmw_implementation_identifier()
        if identifier == RECORDING_MIDDLEWARE:
            say("refusing to read the graph on the recording middleware rmw_introspect_cpp, which sees no other "
                "process: unset its activation (LD_PRELOAD, RMW_IMPLEMENTATION)")
            return EXIT_WRONG_MIDDLEWARE
        node = rclpy.create_node(f"_rmw_introspect_live_{os.getpid()}", context=context,
                                 start_parameter_services=False, enable_rosout=False)
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(node)
        reader = Reader(node, executor)
        domain = context.get_domain_id()
        say(f"joined ROS_DOMAIN_ID {domain} on {identifier}; waiting for the graph to be stable for {args.settle:g} s")
        settled, waited, absent = wait_stable(reader, args.settle, args.timeout, args.expect)
        live: dict[str, Any] = {"domain_id": domain, "rmw_implementation": identifier, "settled": settled,
                                "waited_s": round(waited, 2), "settle_s": args.settle, "timeout_s": args.timeout,
                                "expected_absent": absent,
                                "parameter_timeout_s": args.parameter_timeout, "hidden": [reader.own]}
        answer = snapshot(reader, args, live, identifier, parameters=True)
        if answer is None:
            print(json.dumps({"live": live}))
            return EXIT_EMPTY
        print(json.dumps(answer), flush=True)
        if args.watch:
            watch(reader, args, live, identifier)
        return 0
    finally:
        if executor is not None:
            executor.shutdown()
        if node is not None:
            node.destroy_node()
        if context.ok():
            rclpy.shutdown(context=context)


if __name__ == "__main__":
    sys.exit(main())
