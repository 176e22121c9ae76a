"""A contract, a capture that drifted from it and a second contract, shared by the tests of the
report formats (tests/unit/test_ci_report.py, test_sarif.py): their golden text and line
numbers depend on exactly these."""

TALKER = """\
contract_version: 1
nodes:
  /talker:
    publishers:
      - name: /chatter
        type: std_msgs/msg/String
        qos: {history: KEEP_LAST, depth: 10, reliability: RELIABLE, durability: VOLATILE}
      - name: /status
        type: std_msgs/msg/String
    service_servers:
      - name: /talker/reset
        type: std_srvs/srv/Empty
"""
CAPTURED = {"/talker": {
    "publishers": [
        {"name": "/chatter", "type": "std_msgs/msg/String",
         "qos": {"history": "KEEP_LAST", "depth": 5, "reliability": "BEST_EFFORT", "durability": "VOLATILE"}},
        {"name": "/status", "type": "std_msgs/msg/String"},
        {"name": "/extra", "type": "std_msgs/msg/Int32"},
    ],
    "service_servers": [],
}}
LISTENER = """\
contract_version: 1
nodes:
  /listener:
    subscriptions:
      - name: /chatter
        type: std_msgs/msg/String
        qos: {history: KEEP_LAST, depth: 10, reliability: RELIABLE, durability: VOLATILE}
    service_clients:
      - name: /talker/reset
        type: std_srvs/srv/Trigger
"""
