"""Witnesses (issue 49 item 5): every compatibility rule that is BREAKING because the middleware
refuses the match or nothing connects, tried on the real middleware.

One process (``nodes/witness_pairs.py``, Fast DDS from the wheels, in a ROS_DOMAIN_ID of its own
limited to this machine) runs every pair below at once and says which got anything across. Each
test then asks the rule itself (``compatibility.check_launched`` on the two ends as two launched
processes, judged for ``rmw_fastrtps_cpp``): a pair the rules call broken (a BREAKING item) must
have exchanged nothing, and a pair they call compatible must have. So rule and witness cannot
drift apart: a rule that turns out wrong fails here. docs/drift-rules.md ("Witnesses") lists
which rule each pair witnesses, and why the rules without a witness are BREAKING anyway.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest
import rmwi_helpers as h

from pytest_rmw_introspect.compare.compatibility import LaunchedProcess, check_launched
from pytest_rmw_introspect.model import qos
from pytest_rmw_introspect.model.vocabulary import Severity

SCRIPT = Path(__file__).resolve().parent / "nodes" / "witness_pairs.py"
RMW = "rmw_fastrtps_cpp"
#: a domain of its own: no other test's nodes answer here
DOMAIN_ID = "142"
STRING, INT32 = "std_msgs/msg/String", "std_msgs/msg/Int32"
TRIGGER, EMPTY = "std_srvs/srv/Trigger", "std_srvs/srv/Empty"
FIBONACCI = "test_msgs/action/Fibonacci"
SECOND = 1_000_000_000


def _topic(pid, offered, requested, rule, *, provider_type=STRING, requester_type=STRING, names=None):
    provider_name, requester_name = names or (f"/w/{pid}", f"/w/{pid}")
    return {"id": pid, "kind": "topic", "rule": rule,
            "provider": {"name": provider_name, "type": provider_type, "qos": offered},
            "requester": {"name": requester_name, "type": requester_type, "qos": requested}}


def _service(pid, server, client, rule, *, client_type=TRIGGER, names=None):
    provider_name, requester_name = names or (f"/w/{pid}", f"/w/{pid}")
    provider = {"name": provider_name, "type": TRIGGER, **({"qos": server} if server else {})}
    requester = {"name": requester_name, "type": client_type, **({"qos": client} if client else {})}
    return {"id": pid, "kind": "service", "rule": rule, "provider": provider, "requester": requester}


def _action(pid, rule, *, names):
    return {"id": pid, "kind": "action", "rule": rule, "provider": {"name": names[0], "type": FIBONACCI},
            "requester": {"name": names[1], "type": FIBONACCI}}


BE, REL = {"reliability": "BEST_EFFORT"}, {"reliability": "RELIABLE"}
VOL, TL = {"durability": "VOLATILE"}, {"durability": "TRANSIENT_LOCAL"}
AUTO, MANUAL = {"liveliness": "AUTOMATIC"}, {"liveliness": "MANUAL_BY_TOPIC"}

#: (pair, the rule that calls it broken or None): every ERROR row of the QoS table, a compatible
#: pair beside each, Fast DDS's SYSTEM_DEFAULT resolution, types, names, services, actions
PAIRS = [
    _topic("qos_same", REL, REL, None),
    _topic("qos_reliability", BE, REL, "QOS_INCOMPATIBLE"),
    _topic("qos_reliability_ok", REL, BE, None),
    _topic("qos_durability", VOL, TL, "QOS_INCOMPATIBLE"),
    _topic("qos_durability_ok", TL, VOL, None),
    _topic("qos_deadline_unset", {}, {"deadline_ns": SECOND // 10}, "QOS_INCOMPATIBLE"),
    _topic("qos_deadline_longer", {"deadline_ns": SECOND // 5}, {"deadline_ns": SECOND // 10}, "QOS_INCOMPATIBLE"),
    _topic("qos_deadline_ok", {"deadline_ns": SECOND // 20}, {"deadline_ns": SECOND // 10}, None),
    _topic("qos_liveliness", AUTO, MANUAL, "QOS_INCOMPATIBLE"),
    _topic("qos_lease_unset", AUTO, {**AUTO, "liveliness_lease_duration_ns": SECOND}, "QOS_INCOMPATIBLE"),
    _topic("qos_lease_ok", {**AUTO, "liveliness_lease_duration_ns": SECOND},
           {**AUTO, "liveliness_lease_duration_ns": 2 * SECOND}, None),
    # Fast DDS creates SYSTEM_DEFAULT as a DataWriter's RELIABLE + TRANSIENT_LOCAL, a DataReader's
    # BEST_EFFORT + VOLATILE: rmw_dds_common's "could be either" resolves to "connects"
    _topic("fastdds_default_writer_reliability", {"reliability": "SYSTEM_DEFAULT"}, REL, None),
    _topic("fastdds_default_writer_durability", {"durability": "SYSTEM_DEFAULT"}, TL, None),
    _topic("fastdds_default_reader_reliability", BE, {"reliability": "SYSTEM_DEFAULT"}, None),
    _topic("type", {}, {}, "TYPE_MISMATCH", requester_type=INT32),
    _topic("topic_name", {}, {}, "TOPIC_NAME_MISMATCH", names=("/w/scan_raw", "/w/scan_row")),
    _service("service_same", None, None, None),
    _service("service_type", None, None, "TYPE_MISMATCH", client_type=EMPTY),
    _service("service_name", None, None, "SERVICE_NAME_MISMATCH", names=("/w/enable_motors", "/w/enable_motor")),
    _service("service_best_effort_client", None, BE, "QOS_INCOMPATIBLE"),
    _service("service_best_effort_server", BE, None, "QOS_INCOMPATIBLE"),
    _service("service_transient_local_client", None, TL, "QOS_INCOMPATIBLE"),
    _service("service_both_best_effort", BE, BE, None),
    _action("action_same", None, names=("/w/fibonacci", "/w/fibonacci")),
    _action("action_name", "ACTION_NAME_MISMATCH", names=("/w/fibonacci_b", "/w/fibonaci_b")),
]
_LISTS = {"topic": ("publishers", "subscriptions"), "service": ("service_servers", "service_clients"),
          "action": ("action_servers", "action_clients")}


def _script_pair(pair: dict) -> dict:
    """A pair as the witness process takes it: explicit QoS, both ends' names and types."""
    out = {"id": pair["id"], "kind": pair["kind"]}
    for side in ("provider", "requester"):
        entry = pair[side]
        out[f"{side}_name"], out[f"{side}_type"] = entry["name"], entry["type"]
        if pair["kind"] != "action":
            out[f"{side}_qos"] = qos.expand(entry.get("qos") or ("default" if pair["kind"] == "topic"
                                                                 else "services_default"))
    return out


def rule_verdict(pair: dict) -> set[str]:
    """The BREAKING rules the compatibility rules give the pair, as a system of two processes."""
    provider_list, requester_list = _LISTS[pair["kind"]]
    processes = [LaunchedProcess("witness/provider", "/provider", {"/provider": {provider_list: [pair["provider"]]}}),
                 LaunchedProcess("witness/requester", "/requester", {"/requester": {requester_list: [pair["requester"]]}})]
    return {item.rule for item in check_launched(processes, rmw=RMW) if item.severity >= Severity.BREAKING}


@pytest.fixture(scope="module")
def witnessed() -> dict:
    """Every pair run once, in one process on the real middleware: its JSON table."""
    env = h.ros_environment({"ROS_DOMAIN_ID": DOMAIN_ID, "ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST"})
    env.pop("RMW_IMPLEMENTATION", None)
    started = time.monotonic()
    done = subprocess.run([sys.executable, str(SCRIPT)], input=json.dumps([_script_pair(p) for p in PAIRS]),
                          capture_output=True, text=True, env=env, timeout=60, cwd=os.getcwd())
    wall = time.monotonic() - started
    assert done.returncode == 0, done.stderr
    table = json.loads(done.stdout)
    assert table["rmw"] == RMW, table  # the wheels' rclpy: Fast DDS
    table["process_wall_s"] = round(wall, 3)
    print(f"witness process: {wall:.2f} s wall for {len(PAIRS)} pairs (in-process {table['wall_s']} s)")
    return table


def disagreement(pair: dict, seen: dict) -> str | None:
    """Why the rules and the middleware disagree on ``pair`` (None: they agree)."""
    broken = rule_verdict(pair)
    if pair["rule"] is None:
        if broken:
            return f"{pair['id']}: the rules call it broken ({', '.join(sorted(broken))})"
        if not seen["across"]:
            return f"{pair['id']}: the rules call it compatible, but nothing got across on {RMW}: {seen}"
        return None
    if pair["rule"] not in broken:
        return f"{pair['id']}: expected {pair['rule']}, the rules say {', '.join(sorted(broken)) or 'nothing'}"
    if seen["across"] or seen["matched"]:
        return f"{pair['id']}: the rules say {pair['rule']}, but {RMW} connected the pair: {seen}"
    return None


def test_the_rules_and_the_middleware_agree(witnessed):
    # one test for every pair, so that pytest-xdist never runs the witness process twice
    problems = [p for p in (disagreement(pair, witnessed["pairs"][pair["id"]]) for pair in PAIRS) if p]
    assert problems == [], "\n".join(problems)
    assert {pair["id"] for pair in PAIRS if pair["rule"] is None} == {
        pid for pid, seen in witnessed["pairs"].items() if seen["across"]}
    # one process for every pair (discovery here takes 0.3 s median, up to 3 s): bounded
    assert witnessed["process_wall_s"] < 20, witnessed["process_wall_s"]


def test_every_breaking_connection_rule_has_a_witness_or_a_reason():
    """The rules that are BREAKING because nothing connects: each is witnessed above, or
    docs/drift-rules.md ("Witnesses") says why it has none."""
    from pytest_rmw_introspect.compare import compatibility

    connection = {"QOS_INCOMPATIBLE", "TYPE_MISMATCH", "TYPE_HASH_MISMATCH", "TOPIC_NAME_MISMATCH",
                  "SERVICE_NAME_MISMATCH", "ACTION_NAME_MISMATCH"}
    assert all(compatibility.RULES[rule] is Severity.BREAKING for rule in connection)
    witnessed = {pair["rule"] for pair in PAIRS if pair["rule"]}
    docs = (Path(__file__).resolve().parents[2] / "docs" / "drift-rules.md").read_text(encoding="utf-8")
    section = docs[docs.index("### Witnesses"):docs.index("## Named profiles")]
    for rule in connection - witnessed:
        assert f"- `{rule}`: " in section, f"{rule}: no witness, and the docs do not say why"
    for rule in witnessed:
        assert f"`{rule}`" in section, rule
