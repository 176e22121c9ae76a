"""`rmw-introspect lock` and `check` against the lock, on a real rclpy node that publishes
sensor_msgs/msg/Image (which nests std_msgs/msg/Header, which nests builtin_interfaces/msg/Time)."""

from __future__ import annotations

import json

CAMERA = """\
import rclpy
from rclpy.node import Node
from sensor_msgs.msg import Image

rclpy.init()
node = Node("camera")
node.create_publisher(Image, "image", 10)
rclpy.spin(node)
"""
IMAGE, HEADER, TIME = "sensor_msgs/msg/Image", "std_msgs/msg/Header", "builtin_interfaces/msg/Time"


def test_lock_pins_nested_types_and_check_names_the_one_that_changed(cli):
    cli.write("camera.py", CAMERA)
    created = cli("check", "--update", "--include-types", "--script", "camera.py", "camera.interfaces.yaml")
    assert created.returncode == 0, created
    contract = cli.read("camera.interfaces.yaml")
    assert f"  {HEADER}:" in contract and f"  {TIME}:" in contract

    locked = cli("lock", "camera.interfaces.yaml")
    assert locked.returncode == 0, locked
    assert locked.stderr.startswith("wrote interfaces.lock.json: 3 type(s) of 1 contract(s)"), locked.stderr
    document = json.loads(cli.read("interfaces.lock.json"))
    assert set(document["types"]) == {IMAGE, HEADER, TIME}
    assert f"type_hash: {document['types'][IMAGE]}" in contract  # the middleware's hash of the interface's type
    again = cli("lock", "camera.interfaces.yaml")
    assert again.stderr.startswith("unchanged interfaces.lock.json"), again.stderr

    matching = cli("check", "camera.interfaces.yaml")
    assert matching.returncode == 0 and matching.stdout == "camera.interfaces.yaml: matches (/camera)\n", matching

    # the Header the package was locked against is not the one it is built with now
    document["types"][HEADER] = "RIHS01_" + "0" * 64
    (cli.path / "interfaces.lock.json").write_text(json.dumps(document))
    drifted = cli("check", "camera.interfaces.yaml", "--format", "json")
    assert drifted.returncode == 1, drifted
    (item,) = json.loads(drifted.stdout)
    assert (item["rule"], item["severity"], item["name"], item["change"]) == \
        ("TYPE_LOCK_CHANGED", "BREAKING", "/image", f"type:{HEADER}")
    assert item["message"].startswith(f"{IMAGE} -> {HEADER} changed since interfaces.lock.json locked it")
    text = cli("check", "camera.interfaces.yaml")
    assert f"[TYPE_LOCK_CHANGED] {IMAGE} -> {HEADER} changed" in text.stdout, text
    assert cli("check", "camera.interfaces.yaml", "--ignore-type-hash").returncode == 0


def test_lock_refuses_a_contract_without_types_and_check_a_broken_lock(cli):
    cli.write("camera.py", CAMERA)
    assert cli("check", "--update", "--script", "camera.py", "camera.interfaces.yaml").returncode == 0
    refused = cli("lock", "camera.interfaces.yaml")
    assert refused.returncode == 2, refused
    assert ("cannot lock camera.interfaces.yaml: the contract has no `types:` section, so its nested types are "
            "not known. To lock them, write it with `rmw-introspect check --update --include-types "
            "camera.interfaces.yaml`, then lock again.") in refused.stderr
    cli.write("interfaces.lock.json", "{not json")
    broken = cli("check", "camera.interfaces.yaml")
    assert broken.returncode == 2 and "type lock " in broken.stderr and "not a readable JSON file" in broken.stderr


def test_lock_refuses_a_nodl_document(cli_nodes_only):
    cli_nodes_only.write("camera.nodl.yaml", "nodl_version: 2\n")
    refused = cli_nodes_only("lock", "camera.nodl.yaml")
    assert refused.returncode == 2 and "cannot lock camera.nodl.yaml: a NoDL document cannot hold" in refused.stderr
