"""The contracts the tests share (pytest's ``pythonpath`` puts this directory on ``sys.path``):
those of tests/plugin/nodes/talker.py, whole as a capture writes it or partly, built from one
`/chatter` entry, and the drift item of its depth; and the talker/listener pair with a drifted capture that the report format
tests render (tests/unit/test_ci_report.py, test_sarif.py: their golden text and line numbers
depend on exactly these)."""

from __future__ import annotations

import textwrap

#: the type hash of std_msgs/msg/String (Jazzy), as captures record it
STRING_HASH = "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18"

#: the parameters of tests/plugin/nodes/talker.py with their defaults, as a contract lists them
TALKER_PARAMETERS = """\
    parameters:
      - name: depth
        type: integer
        default_value: 10
      - name: durability
        type: string
        default_value: volatile
      - name: listen
        type: string
        default_value: ''
      - name: msg_type
        type: string
        default_value: String
      - name: reliability
        type: string
        default_value: reliable
      - name: topic
        type: string
        default_value: chatter
"""

#: the endpoint lists talker.py leaves empty, as a capture writes them
_TALKER_EMPTY_LISTS = """\
    subscriptions: []
    service_servers: []
    service_clients: []
    action_servers: []
    action_clients: []
"""


def chatter(*, type_hash: bool = True, qos: bool = True, depth: int = 10, reliability: str = "RELIABLE") -> str:
    """The ``/chatter`` entry (std_msgs/msg/String) of an endpoint list, as talker.py publishes
    it: with its type hash and QoS (``depth`` and ``reliability`` changeable) or without."""
    text = "      - name: /chatter\n        type: std_msgs/msg/String\n"
    if type_hash:
        text += f"        type_hash: {STRING_HASH}\n"
    if qos:
        text += f"        qos: {{history: KEEP_LAST, depth: {depth}, reliability: {reliability}, durability: VOLATILE}}\n"
    return text


def talker_nodes(*, depth: int = 10, reliability: str = "RELIABLE", described: bool = True,
                 complete: bool = True, parameters: bool = True) -> str:
    """The ``nodes:`` block of talker.py as it runs with its defaults. ``complete``: every
    endpoint list and (``parameters``) its parameters, as a capture writes them; else its
    publisher alone. ``described=False``: the publisher by name and type only."""
    text = "nodes:\n  /talker:\n    publishers:\n" + chatter(
        type_hash=described, qos=described, depth=depth, reliability=reliability)
    if complete:
        text += _TALKER_EMPTY_LISTS + (TALKER_PARAMETERS if parameters else "")
    return text


def talker_contract(*, target: str | None = None, header: str = "", distribution: str | None = None,
                    **nodes: object) -> str:
    """A contract of talker.py: ``header`` (comment lines) first, its ``ros_distribution:`` line
    as a golden write records it, a ``target:`` block of ``target`` (e.g. ``script: talker.py``),
    then ``talker_nodes(**nodes)``."""
    block = f"target:\n{textwrap.indent(target, '  ')}\n" if target else ""
    recorded = f"ros_distribution: {distribution}\n" if distribution else ""
    return f"{header}contract_version: 1\n{recorded}{block}" + talker_nodes(**nodes)  # type: ignore[arg-type]


def talker_depth_drift(contract: str, old: int = 3) -> dict[str, object]:
    """The one drift item (JSON, JUnit property) of talker.py against a contract of it whose
    ``/chatter`` depth is ``old`` (talker.py has 10)."""
    return {
        "contract": contract, "node": "/talker", "kind": "publishers", "name": "/chatter",
        "change": "qos.depth", "rule": "QOS_DEPTH_INCREASED", "severity": "SAFE", "old": old, "new": 10,
        "message": f"depth {old} -> 10: more samples are queued; matching is unaffected",
    }


# ---------------------------------------------------------------- the report format tests' pair
REPORT_TALKER = (
    "contract_version: 1\nnodes:\n  /talker:\n    publishers:\n" + chatter(type_hash=False)
    + """\
      - name: /status
        type: std_msgs/msg/String
    service_servers:
      - name: /talker/reset
        type: std_srvs/srv/Empty
""")
#: a capture of REPORT_TALKER's node that drifted from it
REPORT_CAPTURED = {"/talker": {
    "publishers": [
        {"name": "/chatter", "type": "std_msgs/msg/String",
         "qos": {"history": "KEEP_LAST", "depth": 5, "reliability": "BEST_EFFORT", "durability": "VOLATILE"}},
        {"name": "/status", "type": "std_msgs/msg/String"},
        {"name": "/extra", "type": "std_msgs/msg/Int32"},
    ],
    "service_servers": [],
}}
REPORT_LISTENER = (
    "contract_version: 1\nnodes:\n  /listener:\n    subscriptions:\n" + chatter(type_hash=False)
    + """\
    service_clients:
      - name: /talker/reset
        type: std_srvs/srv/Trigger
""")
