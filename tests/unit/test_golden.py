"""--update-golden machinery: CI refusal, locked writes, the record of written files."""

from __future__ import annotations

import hashlib
import multiprocessing
import os
import re
import shutil
import stat
import tempfile
from collections.abc import Callable
from pathlib import Path

import pytest

from pytest_rmw_introspect.check import golden, golden_record
from pytest_rmw_introspect.errors import GoldenWriteError
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
    assert session.summary_lines(tmp_path) == ["created  a.yaml", "updated  sub/b.yaml", "2 golden contract(s) written"]
    assert golden_record.GoldenSession(enabled=True).summary_lines(tmp_path) == ["no golden contract needed changes"]


def test_an_invalid_golden_is_listed_as_not_written_with_what_to_do(tmp_path):
    session = golden_record.GoldenSession(enabled=True)
    session.record_report([(golden_record.USER_PROPERTY,
                            golden_record.property_value(golden_record.INVALID, tmp_path / "contracts" / "t.yaml"))])
    assert session.summary_lines(tmp_path) == [
        "invalid  contracts/t.yaml  (not written: fix or delete it, then run --update-golden again)",
        "0 golden contract(s) written; 1 invalid golden contract(s) not written",
    ]


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
    with FileLock(str(golden.lock_path(path))):  # another process writing the same golden
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


# ---------------------------------------------------------------------------- another user, read-only files, owners, links

#: the other local user these tests play (nobody): as root, a test creates files as that user with os.chown
OTHER = 65534
as_root = pytest.mark.skipif(os.geteuid() != 0, reason="playing another user needs root (os.chown, setuid)")


@pytest.fixture
def shared_tmp(tmp_path, monkeypatch):
    """A temporary directory every user may create files in (like /tmp: mode 1777), used as the
    golden writer's tempfile.gettempdir()."""
    shared = tmp_path / "tmp"
    shared.mkdir()
    shared.chmod(0o1777)
    monkeypatch.setattr(tempfile, "tempdir", str(shared))
    return shared


def _plant(directory: Path, golden_path: Path, victim: Path) -> None:
    """What another user does: create the lock directory the victim will use, open to all, with
    the lock name of ``golden_path`` (its scheme is public) as a symlink to ``victim``."""
    directory.mkdir()
    directory.chmod(0o777)
    os.chown(directory, OTHER, OTHER)
    link = directory / (hashlib.sha256(str(golden_path.resolve()).encode()).hexdigest()[:24] + ".lock")
    link.symlink_to(victim)
    os.lchown(link, OTHER, OTHER)


def _victim(tmp_path: Path) -> Path:
    victim = tmp_path / "victim-data"
    victim.write_text("the victim's own file\n")
    victim.chmod(0o600)
    return victim


@as_root
def test_a_lock_directory_planted_by_another_user_stops_the_write_and_touches_nothing(tmp_path, shared_tmp):
    victim, path = _victim(tmp_path), tmp_path / "c.yaml"
    # the other user plants the shared directory of earlier releases and this user's own name
    for name in (golden.LOCK_DIRECTORY, f"{golden.LOCK_DIRECTORY}-{os.geteuid()}"):
        _plant(shared_tmp / name, path, victim)
    with pytest.raises(GoldenWriteError) as info:
        golden.update(path, NODES, timeout=0.5)
    message = str(info.value)
    assert f"{golden.LOCK_DIRECTORY}-{os.geteuid()} belongs to uid {OTHER}, not to you" in message, message
    assert "another user may have planted it: nothing was written" in message and "set TMPDIR" in message
    assert victim.read_text() == "the victim's own file\n" and victim.stat().st_mode & 0o777 == 0o600
    assert not path.exists()


@as_root
def test_the_shared_lock_directory_of_earlier_releases_is_not_used(tmp_path, shared_tmp):
    victim, path = _victim(tmp_path), tmp_path / "c.yaml"
    _plant(shared_tmp / golden.LOCK_DIRECTORY, path, victim)
    assert golden.update(path, NODES, timeout=0.5) == golden.CREATED
    assert victim.read_text() == "the victim's own file\n" and victim.stat().st_mode & 0o777 == 0o600
    own = shared_tmp / f"{golden.LOCK_DIRECTORY}-{os.geteuid()}"
    info = own.lstat()
    assert stat.S_ISDIR(info.st_mode) and info.st_uid == os.geteuid() and stat.S_IMODE(info.st_mode) == 0o700


@pytest.mark.parametrize("make, problem", [
    (lambda d: (d.mkdir(), d.chmod(0o755)), "has mode 0755: other users may create files in it or read it"),
    (lambda d: d.symlink_to(d.parent), "is not a directory (a symlink or a file)"),
    (lambda d: d.write_text(""), "is not a directory (a symlink or a file)"),
], ids=["mode 0755", "symlink", "file"])
def test_a_lock_directory_open_to_others_or_not_a_directory_is_refused(tmp_path, shared_tmp, make, problem):
    make(shared_tmp / f"{golden.LOCK_DIRECTORY}-{os.geteuid()}")
    with pytest.raises(GoldenWriteError, match=re.escape(problem)):
        golden.write_text(tmp_path / "out.yaml", "x\n")
    assert not (tmp_path / "out.yaml").exists()


def test_a_read_only_golden_is_refused_and_left_as_it_is(tmp_path):
    path = tmp_path / "c.yaml"
    golden.update(path, NODES)
    before = path.read_bytes()
    path.chmod(0o444)
    assert golden.update(path, NODES) is None  # nothing to change: nothing refused either
    with pytest.raises(GoldenWriteError) as info:
        golden.update(path, CHANGED)
    message = str(info.value)
    assert message.startswith(f"cannot write {path}: it is read-only (mode 0444, owner uid {os.geteuid()}) and was "
                              f"left as it is. Make it writable (chmod u+w {path})"), message
    assert path.read_bytes() == before and path.stat().st_mode & 0o777 == 0o444
    with pytest.raises(GoldenWriteError, match="read-only"):
        golden.write_text(path, "x\n")


@as_root
def test_a_rewritten_golden_keeps_its_owner_and_group(tmp_path):
    path = tmp_path / "c.yaml"
    golden.update(path, NODES)
    os.chown(path, OTHER, OTHER)
    path.chmod(0o664)
    assert golden.update(path, CHANGED) == golden.UPDATED
    info = path.stat()
    assert (info.st_uid, info.st_gid, info.st_mode & 0o777) == (OTHER, OTHER, 0o664)
    assert "/chat\n" in path.read_text()


def test_a_hard_linked_golden_is_rewritten_in_place_not_split(tmp_path):
    path = tmp_path / "c.yaml"
    golden.update(path, NODES)
    other_name = tmp_path / "elsewhere" / "c.yaml"
    other_name.parent.mkdir()
    os.link(path, other_name)
    inode = path.stat().st_ino
    assert golden.update(path, CHANGED) == golden.UPDATED
    assert path.stat().st_ino == inode and path.stat().st_nlink == 2
    assert other_name.read_text() == path.read_text() and "/chat\n" in other_name.read_text()
    assert not list(tmp_path.glob(".*.tmp"))


def _as_other_user(write: Callable[[], object]) -> str:
    """``write()`` in a forked child that became the other user (uid and gid ``OTHER``, no
    supplementary groups): its result or GoldenWriteError, as text. A fork, not a new
    interpreter: the other user may not read this interpreter's installation."""
    import filelock  # noqa: F401  (imported here: the child may not be able to read its files)

    read_end, write_end = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: never returns into pytest
        status = 1
        try:
            os.close(read_end)
            os.setgroups([])
            os.setgid(OTHER)
            os.setuid(OTHER)
            try:
                said = str(write())
            except GoldenWriteError as exc:
                said = str(exc)
            os.write(write_end, said.encode())
            status = 0
        finally:
            os._exit(status)
    os.close(write_end)
    with os.fdopen(read_end, "rb") as f:
        said = f.read().decode()
    _, status = os.waitpid(pid, 0)
    assert os.waitstatus_to_exitcode(status) == 0, "the child playing the other user failed"
    return said


@as_root
def test_as_a_user_who_may_not_keep_the_owner_the_golden_is_rewritten_in_place(monkeypatch):
    """A user who can write someone else's golden (through its group) cannot give a renamed
    file that owner: the golden is rewritten in place, so it keeps owner and group; a file that
    user may not write is refused, though the directory would allow the rename."""
    shared = Path(tempfile.mkdtemp(prefix="rmwi-other-user-", dir="/tmp"))  # the other user can reach it
    try:
        shared.chmod(0o1777)
        monkeypatch.setattr(tempfile, "tempdir", str(shared))  # where the other user's lock directory goes
        group_writable, readable = shared / "group.yaml", shared / "mine.yaml"
        for p in (group_writable, readable):
            p.write_text("old\n")
        os.chown(group_writable, 0, OTHER)
        group_writable.chmod(0o664)
        readable.chmod(0o644)

        assert _as_other_user(lambda: golden.write_text(group_writable, "new\n")) == "True"
        info = group_writable.stat()
        assert (info.st_uid, info.st_gid, info.st_mode & 0o777) == (0, OTHER, 0o664)
        assert group_writable.read_text() == "new\n"
        said = _as_other_user(lambda: golden.write_text(readable, "new\n"))
        assert "it is read-only (mode 0644, owner uid 0) and was left as it is" in said, said
        assert readable.read_text() == "old\n" and readable.stat().st_uid == 0
    finally:
        shutil.rmtree(shared)


def test_a_fifo_in_the_place_of_a_golden_is_refused_not_read(tmp_path):
    fifo = tmp_path / "out.yaml"
    os.mkfifo(fifo)
    with pytest.raises(GoldenWriteError, match=r"it is a FIFO \(named pipe\), not a regular file"):
        golden.write_text(fifo, "x\n")  # reading its current text would block
    assert stat.S_ISFIFO(fifo.stat().st_mode)


def test_a_temporary_name_planted_as_a_symlink_is_not_followed(tmp_path):
    """In a directory others may write to, the temporary file's name must not be one they can
    plant in advance (a pid is no secret)."""
    victim = _victim(tmp_path)
    path = tmp_path / "c.yaml"
    planted = tmp_path / f".c.yaml.{os.getpid()}.tmp"
    planted.symlink_to(victim)
    assert golden.update(path, NODES) == golden.CREATED
    assert victim.read_text() == "the victim's own file\n"
    assert planted.is_symlink() and contract.load(path).nodes == contract.normalize_nodes(NODES)
    assert [p.name for p in tmp_path.glob(".c.yaml.*")] == [planted.name]
