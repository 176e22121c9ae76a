"""--update-golden machinery: CI refusal, locked writes, the record of written files."""

from __future__ import annotations

import multiprocessing
from pathlib import Path

import pytest

from pytest_rmw_introspect.check import golden
from pytest_rmw_introspect.model import contract

NODES = {"/talker": {"publishers": [{"name": "/chatter", "type": "std_msgs/msg/String",
                                     "qos": {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE",
                                             "durability": "VOLATILE"}}]}}


@pytest.mark.parametrize("value, refused", [
    (None, False), ("", False), ("0", False), ("false", False), ("False", False), ("no", False),
    ("1", True), ("true", True), ("yes", True), ("github-actions", True),
])
def test_ci_refusal(value, refused):
    env = {} if value is None else {"CI": value}
    reason = golden.ci_refusal(env)
    assert (reason is not None) == refused
    if refused:
        assert "--update-golden refuses to write" in reason and repr(value) in reason


def test_update_creates_then_updates_then_leaves_alone(tmp_path):
    path = tmp_path / "contracts" / "talker.yaml"
    assert golden.update(path, NODES) == golden.CREATED
    assert golden.update(path, NODES) is None
    changed = {"/talker": {"publishers": [dict(NODES["/talker"]["publishers"][0], name="/chat")]}}
    assert golden.update(path, changed) == golden.UPDATED
    assert "/chat\n" in path.read_text()


def test_update_keeps_header_and_equivalent_spelling(tmp_path):
    path = tmp_path / "c.yaml"
    header = "# keep me\ncontract_version: 1\ntarget:\n  script: talker.py\n"
    path.write_text(header + "nodes:\n  /talker:\n    publishers:\n      - {name: /chatter, type: std_msgs/msg/String, qos: default}\n")
    new = {"/talker": {"publishers": NODES["/talker"]["publishers"] + [{"name": "/b", "type": "std_msgs/msg/String"}]}}
    assert golden.update(path, new) == golden.UPDATED
    text = path.read_text()
    assert text.startswith(header)
    assert "qos: default\n" in text
    assert contract.load(path).nodes["/talker"]["publishers"][1]["name"] == "/chatter"


def test_a_broken_golden_is_replaced_keeping_its_header(tmp_path):
    path = tmp_path / "c.yaml"
    path.write_text("# header\ncontract_version: 1\nnodes:\n  /talker:\n    publishers: 3\n")
    assert golden.update(path, NODES) == golden.UPDATED
    assert path.read_text().startswith("# header\ncontract_version: 1\nnodes:\n  /talker:\n")
    contract.load(path)


def _write_in_process(args):
    path, = args
    return golden.update(Path(path), NODES)


def test_concurrent_writers_write_a_golden_once(tmp_path):
    path = tmp_path / "shared.yaml"
    ctx = multiprocessing.get_context("fork")
    with ctx.Pool(4) as pool:
        results = pool.map(_write_in_process, [(str(path),)] * 8)
    assert results.count(golden.CREATED) == 1
    assert results.count(None) == 7
    assert contract.load(path).nodes["/talker"]["publishers"][0]["name"] == "/chatter"


def test_session_collects_reports_and_lists_files(tmp_path):
    session = golden.GoldenSession(enabled=True)
    a, b = tmp_path / "a.yaml", tmp_path / "sub" / "b.yaml"
    session.record_report([("other", "x"), (golden.USER_PROPERTY, golden.property_value(golden.CREATED, a))])
    session.record_report([(golden.USER_PROPERTY, golden.property_value(golden.UPDATED, a))])
    session.record_report([(golden.USER_PROPERTY, golden.property_value(golden.UPDATED, b)),
                           (golden.USER_PROPERTY, "garbage")])
    assert session.written == {a.resolve(): golden.CREATED, b.resolve(): golden.UPDATED}
    assert session.summary_lines(tmp_path) == ["created  a.yaml", "updated  sub/b.yaml"]
