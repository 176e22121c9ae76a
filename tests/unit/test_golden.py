"""--update-golden machinery: CI refusal, locked writes, the record of written files."""

from __future__ import annotations

import multiprocessing
from pathlib import Path

import pytest

from pytest_rmw_introspect.check import golden, golden_record
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
    reason = golden_record.ci_refusal(env)
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
    # spawn, not fork: a worker of this test process may hold threads (pipe readers of earlier
    # captures), and a forked child can inherit a lock one of them held
    ctx = multiprocessing.get_context("spawn")
    with ctx.Pool(4) as pool:
        results = pool.map(_write_in_process, [(str(path),)] * 8)
    assert results.count(golden.CREATED) == 1
    assert results.count(None) == 7
    assert contract.load(path).nodes["/talker"]["publishers"][0]["name"] == "/chatter"


def test_session_collects_reports_and_lists_files(tmp_path):
    session = golden_record.GoldenSession(enabled=True)
    a, b = tmp_path / "a.yaml", tmp_path / "sub" / "b.yaml"
    session.record_report([("other", "x"), (golden_record.USER_PROPERTY, golden_record.property_value(golden.CREATED, a))])
    session.record_report([(golden_record.USER_PROPERTY, golden_record.property_value(golden.UPDATED, a))])
    session.record_report([(golden_record.USER_PROPERTY, golden_record.property_value(golden.UPDATED, b)),
                           (golden_record.USER_PROPERTY, "garbage")])
    assert session.written == {a.resolve(): golden.CREATED, b.resolve(): golden.UPDATED}
    assert session.summary_lines(tmp_path) == ["created  a.yaml", "updated  sub/b.yaml"]


# ---------------------------------------------------------------------------- links, modes, line endings, errors


CHANGED = {"/talker": {"publishers": [dict(NODES["/talker"]["publishers"][0], name="/chat")]}}


def test_a_symlinked_golden_updates_the_shared_file_and_stays_a_link(tmp_path):
    shared = tmp_path / "shared" / "talker.interfaces.yaml"
    golden.update(shared, NODES)
    link = tmp_path / "pkg" / "talker.interfaces.yaml"
    link.parent.mkdir()
    link.symlink_to(shared)
    assert golden.update(link, CHANGED) == golden.UPDATED
    assert link.is_symlink() and link.resolve() == shared.resolve()
    assert "/chat\n" in shared.read_text()


def test_an_updated_golden_keeps_its_permission_bits(tmp_path):
    path = tmp_path / "c.yaml"
    golden.update(path, NODES)
    path.chmod(0o640)
    assert golden.update(path, CHANGED) == golden.UPDATED
    assert path.stat().st_mode & 0o777 == 0o640


def test_a_crlf_golden_keeps_its_header_byte_for_byte_and_its_line_endings(tmp_path):
    path = tmp_path / "c.yaml"
    header = b"# written on Windows\r\ncontract_version: 1\r\ntarget:\r\n  script: talker.py\r\n"
    path.write_bytes(header + contract.dump_nodes(NODES).replace("\n", "\r\n").encode())
    assert golden.update(path, NODES) is None  # the same nodes: nothing to change
    assert golden.update(path, CHANGED) == golden.UPDATED
    data = path.read_bytes()
    assert data.startswith(header)
    assert b"/chat\r\n" in data and b"\n" not in data.replace(b"\r\n", b"")
    assert contract.load(path).nodes["/talker"]["publishers"][0]["name"] == "/chat"


def test_an_unwritable_directory_is_a_golden_write_error(tmp_path):
    from pytest_rmw_introspect.errors import GoldenWriteError

    blocker = tmp_path / "afile"
    blocker.write_text("x")
    with pytest.raises(GoldenWriteError) as info:
        golden.update(blocker / "sub" / "c.yaml", NODES)
    message = str(info.value)
    assert message.startswith(f"cannot write {blocker / 'sub' / 'c.yaml'}:") and "writable" in message
    with pytest.raises(GoldenWriteError):
        golden.write_text(blocker / "out.yaml", "x\n")


def test_a_lock_held_too_long_is_a_golden_write_error(tmp_path):
    from filelock import FileLock

    from pytest_rmw_introspect.errors import GoldenWriteError

    path = tmp_path / "c.yaml"
    with FileLock(str(golden._lock_path(path))):  # another process writing the same golden
        with pytest.raises(GoldenWriteError, match="held its lock"):
            golden.update(path, NODES, timeout=0.05)


def test_update_writes_replaces_and_leaves_alone_the_types_section(tmp_path):
    from pytest_rmw_introspect.model.types import Field, MessageType

    string = {"std_msgs/msg/String": MessageType("std_msgs/msg/String", (Field("data", "string"),), ())}
    path = tmp_path / "c.yaml"
    assert golden.update(path, NODES, types=string) == golden.CREATED
    text = path.read_text()
    assert text.endswith("\n# Generated with include_types: the definitions behind the type hashes above, so that a\n"
                         "# changed hash is reported field by field. Rewritten by --update-golden.\n"
                         "types:\n  std_msgs/msg/String:\n    fields:\n      - string data\n    constants: []\n")
    assert contract.load(path).types == string
    assert golden.update(path, NODES, types=string) is None  # byte-identical
    wide = {"std_msgs/msg/String": MessageType("std_msgs/msg/String", (Field("data", "wstring"),), ())}
    changed = {"/talker": {"publishers": [dict(NODES["/talker"]["publishers"][0], name="/chat")]}}
    assert golden.update(path, changed, types=wide) == golden.UPDATED
    assert contract.load(path).types == wide and "/chat\n" in path.read_text()
    # types=None: the section stays as it is
    assert golden.update(path, NODES) == golden.UPDATED
    assert contract.load(path).types == wide and "/chatter\n" in path.read_text()
