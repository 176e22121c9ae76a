"""Parameters and lifecycle states through the check pipeline, without running anything: a
contract that does not state them yet passes and is completed by updating, ignored parameters
stay as the contract has them, a target that does not read parameters does not compare them."""

from __future__ import annotations

import copy

import pytest
from test_capture import Builder
from test_parameters import LIFECYCLE, RCLPY, param, probed

from pytest_rmw_introspect.check import pipeline
from pytest_rmw_introspect.check.outcome import Verdict, decide
from pytest_rmw_introspect.check.pipeline import Layers
from pytest_rmw_introspect.model import contract as contract_module

OLD_CONTRACT = """\
# written before parameters were recorded
contract_version: 1
target:
  script: managed.py
nodes:
  /managed:
    publishers:
      - name: /status
        type: std_msgs/msg/String
        qos: {history: KEEP_LAST, depth: 10, reliability: RELIABLE, durability: VOLATILE}
    subscriptions: []
    service_servers: []
    service_clients: []
    action_servers: []
    action_clients: []
"""


@pytest.fixture
def capture():
    b = Builder()
    n = b.node("managed")
    b.ep(n, "publisher", "/status", "std_msgs/msg/String", type_hash=None)
    probed(b, n, RCLPY + [param("rate", "double", 10.0, description="Hz"),
                          param("frame", "string", "base", read_only=True)], lifecycle=copy.deepcopy(LIFECYCLE))
    return b.capture()


def check(path, capture, **options):
    prepared = pipeline.prepare(path, layers=Layers(strong_options=[(options, "test")] if options else []))
    return pipeline.compare(prepared, capture)


def test_a_contract_without_parameters_matches_and_updating_completes_it(tmp_path, capture):
    path = tmp_path / "managed.interfaces.yaml"
    path.write_text(OLD_CONTRACT)
    result = check(path, capture)
    assert result.items == [] and result.gains == ["/managed lifecycle", "/managed parameters"]
    passed = decide(result, update=False, accept_command="pytest --update-golden x")
    assert passed.verdict is Verdict.PASS
    assert passed.message == (f"{result.shown}: matches (/managed); it does not state /managed lifecycle, "
                              "/managed parameters yet: pytest --update-golden x adds them")
    written = decide(result, update=True)
    assert written.verdict is Verdict.WRITE and "adds /managed lifecycle, /managed parameters" in written.message
    assert result.update() == "updated"
    text = path.read_text()
    assert text.startswith(OLD_CONTRACT.split("nodes:")[0])  # the header kept byte for byte
    nodes = contract_module.load(path).nodes["/managed"]
    assert nodes["lifecycle"] == "active"
    assert nodes["parameters"] == [
        {"name": "frame", "type": "string", "default_value": "base", "read_only": True},
        {"name": "rate", "type": "double", "default_value": 10.0, "description": "Hz"}]
    again = check(path, capture)
    assert again.items == [] and again.gains == [] and not again.drifted
    assert decide(again, update=True).verdict is Verdict.PASS


def test_ignored_parameters_stay_as_the_contract_has_them(tmp_path, capture):
    path = tmp_path / "managed.interfaces.yaml"
    path.write_text(OLD_CONTRACT)
    check(path, capture).update()
    text = path.read_text().replace("default_value: 10.0", "default_value: 99.0").replace(
        "      - name: frame\n", "      - name: gone\n        type: bool\n      - name: frame\n")
    path.write_text(text)
    result = check(path, capture, ignore_parameter_values="rate", ignore_parameters=["gone"])
    assert result.items == []
    changed = check(path, capture)
    assert {i.rule for i in changed.items} == {"PARAM_DEFAULT_CHANGED", "PARAM_REMOVED"}
    changed.options = result.options
    changed.drift_items = [i for i in changed.drift_items if i.name == "frame"]  # pretend something else drifted
    changed.update()
    kept = contract_module.load(path).nodes["/managed"]["parameters"]
    assert kept == sorted(contract_module.loads(text).nodes["/managed"]["parameters"], key=lambda e: e["name"])
    assert {"name": "gone", "type": "bool"} in kept  # the ignored parameter and value kept as written
    assert {"name": "rate", "type": "double", "default_value": 99.0, "description": "Hz"} in kept


def test_a_target_that_does_not_read_parameters_does_not_compare_them(tmp_path, capture):
    path = tmp_path / "managed.interfaces.yaml"
    path.write_text(OLD_CONTRACT)
    check(path, capture).update()
    unread = copy.deepcopy(capture.raw)
    unread["nodes"][0]["parameters"] = None
    unread_capture = type(capture).from_dict(unread)
    result = check(path, unread_capture)
    assert [i.rule for i in result.items] == ["PARAMS_NOT_READ"]
    prepared = pipeline.prepare(path, layers=Layers(strong_target=[({"read_parameters": False}, tmp_path, "test")]))
    assert prepared.options.ignore_parameters is True
    result = pipeline.compare(prepared, unread_capture)
    assert result.items == [] and result.gains == []
    assert result.golden_nodes()["/managed"]["parameters"] == contract_module.load(path).nodes["/managed"]["parameters"]
