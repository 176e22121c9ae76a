"""Type hashes of nested types and the package's type lock (`rmw-introspect lock`): the hashes
equal rosidl's, the lock file is deterministic and read with errors for people, and a nested
type that changed is reported with the path to it."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import pytest
import type_tables

from pytest_rmw_introspect.compare import type_lock as lock_check
from pytest_rmw_introspect.errors import TypeLockError, UnhashableType
from pytest_rmw_introspect.model import type_hash, type_lock
from pytest_rmw_introspect.model.types import Field
from pytest_rmw_introspect.run import ros_env

#: the rules these tests trigger (tests/unit/test_drift.py checks every rule has a test)
TESTED_RULES = {"TYPE_LOCK_CHANGED", "TYPE_NOT_LOCKED"}
IMAGE = "sensor_msgs/msg/Image"
HEADER = "std_msgs/msg/Header"
TIME = "builtin_interfaces/msg/Time"


def _generated_hashes() -> dict[str, str]:
    """Every message type's hash as rosidl generated it (share/<pkg>/msg/<T>.json) in the venv, for
    the types defined by a .msg file (Kilted's test_msgs also has types defined only in IDL, which
    the tests' .msg reader does not read)."""
    out: dict[str, str] = {}
    for prefix in ros_env.detect().ament_prefixes:
        for path in sorted(Path(prefix, "share").glob("*/msg/*.json")):
            if not path.with_suffix(".msg").is_file():
                continue
            for entry in json.loads(path.read_text())["type_hashes"]:
                out[entry["type_name"]] = entry["hash_string"]
    return out


def test_computed_hashes_are_rosidls_for_every_installed_message_type():
    generated = _generated_hashes()
    assert len(generated) > 100
    roots = sorted({name for name in generated if name.count("/") == 2})
    computed = type_hash.message_hashes(type_tables.describe(*roots))
    assert computed.keys() >= set(roots)
    wrong = {name: (computed[name], generated[name]) for name in generated if computed.get(name) != generated[name]}
    assert not wrong


def test_a_type_whose_nested_type_is_not_described_has_no_hash():
    table = type_tables.describe(IMAGE)
    del table[TIME]
    with pytest.raises(UnhashableType, match=f"{HEADER} nests {TIME}, which is not described"):
        type_hash.message_hash(table, IMAGE)
    assert IMAGE not in type_hash.message_hashes(table) and HEADER not in type_hash.message_hashes(table)


def _camera(type_name: str = IMAGE) -> dict:
    return {"/camera": {"publishers": [{"name": "/image", "type": type_name}], "subscriptions": [],
                        "service_servers": [], "service_clients": [], "action_servers": [], "action_clients": []}}


def _with_field(table: dict, name: str, field: Field) -> dict:
    changed = dict(table)
    changed[name] = dataclasses.replace(table[name], fields=(*table[name].fields, field))
    return changed


def _lock(tmp_path: Path, nodes: dict, table: dict) -> type_lock.TypeLock:
    path = tmp_path / type_lock.FILE_NAME
    path.write_text(type_lock.render(type_lock.locked_hashes(nodes, table, "camera.interfaces.yaml"),
                                     [tmp_path / "camera.interfaces.yaml"], path))
    return type_lock.load(path)


def test_a_nested_type_that_changed_is_reported_with_the_path_to_it(tmp_path):
    table = type_tables.describe(IMAGE)
    lock = _lock(tmp_path, _camera(), table)
    assert set(lock.types) == {IMAGE, HEADER, TIME} and lock.contracts == ("camera.interfaces.yaml",)
    assert lock_check.lock_drift(_camera(), table, lock) == []

    header_changed = _with_field(table, HEADER, Field("seq", "uint32"))
    (item,) = lock_check.lock_drift(_camera(), header_changed, lock)
    assert (item.node, item.kind, item.name, item.rule, item.severity.name) == \
        ("/camera", "publishers", "/image", "TYPE_LOCK_CHANGED", "BREAKING")
    assert item.message.startswith(f"{IMAGE} -> {HEADER} changed since interfaces.lock.json locked it ")
    assert item.old == lock.types[HEADER] and item.new == type_hash.message_hash(header_changed, HEADER)

    time_changed = _with_field(table, TIME, Field("leap", "int8"))
    (item,) = lock_check.lock_drift(_camera(), time_changed, lock)
    assert item.message.startswith(f"{IMAGE} -> {HEADER} -> {TIME} changed")

    own_changed = _with_field(table, IMAGE, Field("gain", "float32"))
    (item,) = lock_check.lock_drift(_camera(), own_changed, lock)
    assert item.message.startswith(f"{IMAGE} changed since")


def test_a_type_the_lock_does_not_list_is_not_locked(tmp_path):
    table = type_tables.describe(IMAGE, "sensor_msgs/msg/CameraInfo")
    lock = _lock(tmp_path, _camera(), table)
    items = lock_check.lock_drift(_camera("sensor_msgs/msg/CameraInfo"), table, lock)
    assert {(i.rule, i.change) for i in items} == {
        ("TYPE_NOT_LOCKED", "type:sensor_msgs/msg/CameraInfo"),
        ("TYPE_NOT_LOCKED", "type:sensor_msgs/msg/RegionOfInterest")}
    assert all(i.severity.name == "RISKY" and "run `rmw-introspect lock` again" in i.message for i in items)


def test_the_recorded_hash_of_an_interface_is_what_is_locked_for_it():
    nodes = _camera()
    nodes["/camera"]["publishers"][0]["type_hash"] = "RIHS01_" + "a" * 64
    hashes = type_lock.locked_hashes(nodes, type_tables.describe(IMAGE), "c.yaml")
    assert hashes[IMAGE] == "RIHS01_" + "a" * 64 and hashes[HEADER] == _generated_hashes()[HEADER]


def test_a_contract_without_types_cannot_be_locked():
    with pytest.raises(TypeLockError, match=r"cannot lock c.yaml: the contract has no `types:` section.*"
                       r"rmw-introspect check --update --include-types c.yaml"):
        type_lock.locked_hashes(_camera(), None, "c.yaml")
    partial = type_tables.describe(IMAGE)
    del partial[HEADER]
    with pytest.raises(TypeLockError, match=f"does not describe {HEADER} \\(used by {IMAGE}\\)"):
        type_lock.locked_hashes(_camera(), partial, "c.yaml")


def test_the_lock_file_is_sorted_and_the_same_bytes_each_time(tmp_path):
    path = tmp_path / "pkg" / type_lock.FILE_NAME
    text = type_lock.render({"b/msg/B": "RIHS01_" + "b" * 64, "a/msg/A": "RIHS01_" + "a" * 64},
                            [tmp_path / "pkg" / "contracts" / "x.interfaces.yaml"], path)
    assert text == type_lock.render({"a/msg/A": "RIHS01_" + "a" * 64, "b/msg/B": "RIHS01_" + "b" * 64},
                                    [tmp_path / "pkg" / "contracts" / "x.interfaces.yaml"], path)
    document = json.loads(text)
    assert list(document["types"]) == ["a/msg/A", "b/msg/B"]
    assert document["contracts"] == ["contracts/x.interfaces.yaml"]


@pytest.mark.parametrize(("text", "reason"), [
    ("{", "not a readable JSON file"),
    ('{"format": "other"}', 'not a type lock (it needs "format": "rmw_introspect_type_lock")'),
    ('{"format": "rmw_introspect_type_lock", "version": 7, "types": {}}', "version 7 is not supported"),
    ('{"format": "rmw_introspect_type_lock", "version": 1, "types": []}', '"types" is not a mapping'),
    ('{"format": "rmw_introspect_type_lock", "version": 1, "types": {"a/msg/A": "RIHS01_x"}}',
     "the hash of a/msg/A is 'RIHS01_x', not RIHS01_ and 64 lowercase hex digits"),
])
def test_a_broken_lock_file_is_an_error_saying_what_to_do(tmp_path, text, reason):
    path = tmp_path / type_lock.FILE_NAME
    path.write_text(text)
    with pytest.raises(TypeLockError) as info:
        type_lock.load(path)
    assert reason in str(info.value) and "rmw-introspect lock CONTRACT... -o" in str(info.value)


def test_the_lock_is_found_above_the_contract_up_to_the_package_root(tmp_path):
    package = tmp_path / "ws" / "src" / "my_pkg"
    contract = package / "test" / "contracts" / "camera.interfaces.yaml"
    contract.parent.mkdir(parents=True)
    (package / "package.xml").write_text("<package/>")
    assert type_lock.find(contract) is None
    (tmp_path / "ws" / type_lock.FILE_NAME).write_text("{}")  # above the package root: another package's
    assert type_lock.find(contract) is None
    (package / type_lock.FILE_NAME).write_text("{}")
    assert type_lock.find(contract) == package / type_lock.FILE_NAME
    (contract.parent / type_lock.FILE_NAME).write_text("{}")
    assert type_lock.find(contract) == contract.parent / type_lock.FILE_NAME
