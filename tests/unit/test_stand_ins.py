"""Stand-ins for hardware processes (model.stand_ins, run.system_capture): which launched
process an entry names, the files that stand in, and the block proposed for a process that
lacks its device."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from pytest_rmw_introspect.errors import ContractError, TargetConfigError
from pytest_rmw_introspect.launch.result import LaunchedNode, LaunchParameter, LaunchResult, Where
from pytest_rmw_introspect.model import stand_ins, system_contract
from pytest_rmw_introspect.run import system_capture

HEADER = "system_version: 1\nlaunch: {path: robot.launch.xml}\n"
DRIVER = "contract_version: 1\nnodes:\n  /robot1/lidar:\n    publishers: [{name: /robot1/scan, type: sensor_msgs/msg/LaserScan}]\n"


def test_an_entry_names_a_process_by_executable_package_and_node_name():
    entry = stand_ins.StandIn(executable="lidar_driver", contract="c.yaml", package="drivers", name="/robot1/lidar")
    assert entry.matches("drivers", "lidar_driver", "/robot1/lidar")
    assert not entry.matches("drivers", "lidar_driver", "/robot2/lidar")
    assert not entry.matches("other", "lidar_driver", "/robot1/lidar")
    loose = stand_ins.StandIn(executable="python", contract="c.yaml")
    assert loose.matches(None, "/usr/bin/python", None) and loose.matches("p", "python", "/x")
    assert not loose.matches(None, "/usr/bin/python3", None)
    assert entry.describe() == "drivers/lidar_driver (/robot1/lidar)" and loose.describe() == "python"


def test_a_system_contract_with_stand_ins_loads_and_rejects_bad_entries(tmp_path):
    text = HEADER + "stand_ins:\n  - {executable: lidar_driver, contract: contracts/lidar.interfaces.yaml, reason: lidar}\n"
    loaded = system_contract.loads(text, path=tmp_path / "robot.system.yaml")
    assert loaded.stand_ins == (stand_ins.StandIn("lidar_driver", "contracts/lidar.interfaces.yaml", reason="lidar",
                                                  line=4),)
    for bad, why in [("  - {executable: lidar_driver}\n", "'contract' is required"),
                     ("  - {executable: d, contract: c.yaml, device: /dev/x}\n", "unknown key(s) 'device'"),
                     ("  - {executable: d, contract: c.yaml, name: lidar}\n", "does not match '^/'")]:
        with pytest.raises(ContractError, match="stand_ins") as caught:
            system_contract.loads(HEADER + "stand_ins:\n" + bad, path=tmp_path / "robot.system.yaml")
        assert why in str(caught.value)


def test_the_stand_in_files_are_read_and_validated(tmp_path):
    (tmp_path / "contracts").mkdir()
    (tmp_path / "contracts" / "lidar.interfaces.yaml").write_text(DRIVER)
    (tmp_path / "contracts" / "lidar.nodl.yaml").write_text(
        "nodl_version: 2\npublishers:\n  - {name: scan, type: sensor_msgs/msg/LaserScan}\n")
    system = tmp_path / "robot.system.yaml"
    loaded = stand_ins.load(stand_ins.StandIn("lidar_driver", "contracts/lidar.interfaces.yaml"), 0, system)
    assert list(loaded.nodes) == ["/robot1/lidar"] and loaded.path == tmp_path / "contracts" / "lidar.interfaces.yaml"
    # a NoDL document that names no node describes the node the entry names
    nodl = stand_ins.load(stand_ins.StandIn("lidar_driver", "contracts/lidar.nodl.yaml", name="/robot1/lidar"), 0,
                          system)
    assert [e["name"] for e in nodl.nodes["/robot1/lidar"]["publishers"]] == ["/robot1/scan"]
    with pytest.raises(ContractError) as missing:
        stand_ins.load(stand_ins.StandIn("lidar_driver", "contracts/none.yaml", line=7), 2, system)
    assert str(missing.value).startswith(f"invalid contract {system}:7: at stand_ins[2].contract: the stand-in for "
                                         "lidar_driver, ")
    assert "none.yaml, does not exist" in str(missing.value)


@pytest.mark.parametrize(("kind", "said"), [("fifo", "is a FIFO (named pipe), not a regular file"),
                                            ("directory", "is a directory, not a file")])
def test_a_stand_in_that_is_a_fifo_or_a_directory_is_said_as_such(tmp_path, kind, said):
    """Issue 50, N27: a stand-in contract that was a FIFO or a directory was reported as "does not exist"."""
    stand_in_path = tmp_path / "lidar.interfaces.yaml"
    if kind == "fifo":
        os.mkfifo(stand_in_path)
    else:
        stand_in_path.mkdir()
    system = tmp_path / "robot.system.yaml"
    with pytest.raises(ContractError) as refused:  # a FIFO is refused from its stat, never opened (no hang)
        stand_ins.load(stand_ins.StandIn("lidar_driver", "lidar.interfaces.yaml", line=5), 0, system)
    message = str(refused.value)
    assert message.startswith(f"invalid contract {system}:5: at stand_ins[0].contract: the stand-in for lidar_driver, ")
    assert f"lidar.interfaces.yaml, {said}: point `contract:` at the node contract" in message
    assert "does not exist" not in message


def launched(executable="driver", name="/robot1/driver", parameters=()):
    return LaunchedNode(executable=executable, package="drivers", where=Where(Path("robot.launch.xml"), 3),
                        name=name.rsplit("/", 1)[1], namespace=name.rsplit("/", 1)[0] or "/", parameters=parameters)


def test_the_device_a_failed_process_lacks(tmp_path):
    params = tmp_path / "driver.yaml"
    params.write_text("/**:\n  ros__parameters:\n    port: /dev/ttyNOPE9\n")
    assert system_capture.device_of(launched(), "could not open /dev/ttyNOPE1: No such file") == "/dev/ttyNOPE1"
    assert system_capture.device_of(launched(parameters=(LaunchParameter("port", "/dev/ttyNOPE2:57600"),)), "") == \
        "/dev/ttyNOPE2"
    assert system_capture.device_of(launched(parameters=(LaunchParameter(file=params),)), "boom") == "/dev/ttyNOPE9"
    # a device the machine has is not what it lacks; no device at all: nothing to propose
    assert system_capture.device_of(launched(), "reading /dev/null failed") is None
    assert system_capture.device_of(launched(), "Segmentation fault") is None


def test_the_proposed_block_is_yaml_for_the_system_contract():
    text = stand_ins.proposal([("drivers", "lidar_driver", "/robot1/lidar", "/dev/ttyUSB0"),
                               (None, "/usr/bin/python3", None, "/dev/input/js0")])
    assert text == ("stand_ins:\n- package: drivers\n  executable: lidar_driver\n  name: /robot1/lidar\n"
                    "  contract: contracts/robot1_lidar.interfaces.yaml\n  reason: needs /dev/ttyUSB0\n"
                    "- executable: /usr/bin/python3\n  contract: contracts/python3.interfaces.yaml\n"
                    "  reason: needs /dev/input/js0\n")
    loaded = system_contract.loads(HEADER + text)
    assert [s.executable for s in loaded.stand_ins] == ["lidar_driver", "/usr/bin/python3"]


def test_a_stood_in_process_is_not_run_and_gives_its_nodes(tmp_path):
    (tmp_path / "lidar.interfaces.yaml").write_text(DRIVER)
    stood_in = stand_ins.load(stand_ins.StandIn("driver", "lidar.interfaces.yaml", reason="needs the lidar"), 0,
                              tmp_path / "robot.system.yaml")
    launch = LaunchResult(tmp_path / "robot.launch.xml", {}, nodes=[launched(name="/robot1/lidar")])
    spec = system_capture.LaunchSpec(path=tmp_path / "robot.launch.xml")
    # no process left to run: no library or ROS environment is needed
    capture = system_capture.capture_system(spec, library="unused.so", ros=object(), launch=launch,
                                            stand_ins=[stood_in])
    assert capture.node_names == ["/robot1/lidar"] and [p.label for p in capture.stood_in] == ["drivers/driver"]
    assert capture.to_contract_nodes()["/robot1/lidar"]["publishers"][0]["name"] == "/robot1/scan"
    assert capture.notes() == [f"drivers/driver (robot.launch.xml:3) stood in for: not run here (needs the lidar): "
                               f"its nodes /robot1/lidar are taken from {stood_in.shown}"]
    other = stand_ins.load(stand_ins.StandIn("gps", "lidar.interfaces.yaml"), 0, tmp_path / "robot.system.yaml")
    with pytest.raises(TargetConfigError, match=r"the stand-in for gps \(.*\) names no process that `launch "):
        system_capture.capture_system(spec, library="unused.so", ros=object(), launch=launch, stand_ins=[other])
