"""Launch files of sample systems: many processes, for the scale tests and the scale benchmark
(issue 42): ``count`` processes of the installed example package, talkers and listeners in turn,
each pair in a namespace of its own (``/r0/talker0``, ``/r0/listener1``, ``/r1/talker0``, ...);
and a robot whose IMU driver needs a device, for the hardware stand-in tests (``stand_ins:``)."""

from __future__ import annotations

import sys
from pathlib import Path

#: the rclpy node scripts of the plugin and CLI tests (serial_driver.py, imu_monitor.py, ...)
TEST_NODES = Path(__file__).resolve().parents[1] / "plugin" / "nodes"


def many_processes(count: int) -> str:
    """A launch file (XML) starting ``count`` example processes."""
    nodes = []
    for i in range(count):
        executable = "talker" if i % 2 == 0 else "listener"
        nodes.append(f'  <group><push-ros-namespace namespace="r{i // 2}"/>'
                     f'<node pkg="rmw_introspect_examples" exec="{executable}" name="{executable}{i % 2}"/></group>')
    return "<launch>\n" + "\n".join(nodes) + "\n</launch>\n"


def node_names(count: int) -> list[str]:
    """The nodes of :func:`many_processes` ``(count)``, sorted."""
    return sorted(f"/r{i // 2}/{'talker' if i % 2 == 0 else 'listener'}{i % 2}" for i in range(count))


def in_namespace(namespace: str, *nodes: str) -> str:
    """A launch file (XML) starting ``nodes`` (:func:`script_node`) in ``namespace``."""
    return (f'<launch>\n  <group>\n    <push-ros-namespace namespace="{namespace}"/>\n' + "".join(nodes)
            + "  </group>\n</launch>\n")


def script_node(script: str, name: str, *inside: str) -> str:
    """A ``<node>`` running the test node ``script`` as ``name``, with the elements ``inside``."""
    start = f'    <node exec="{sys.executable}" args="{TEST_NODES / script}" name="{name}"'
    if not inside:
        return start + "/>\n"
    return start + ">\n" + "".join(f"      {element}\n" for element in inside) + "    </node>\n"


def imu_robot(device: str = "/dev/ttyFAKE") -> str:
    """A launch file (XML): in /robot1, an IMU driver (``imu_driver``, parameter ``port``: ``device``
    at 115200 baud; it exits when it cannot open the device) and a monitor of its /robot1/imu."""
    return in_namespace("robot1", script_node("serial_driver.py", "imu_driver", f'<param name="port" value="{device}:115200"/>'),
                        script_node("imu_monitor.py", "imu_monitor"))


def half_remapped_robot(device: str = "/dev/ttyFAKE") -> str:
    """A launch file (XML) of issue 47's trial: in /robot, a teleop talker whose ``chatter`` is
    remapped to ``cmd_vel`` and a base that still listens on ``chatter`` (the remapping given on
    one side only: its subscription dangles), and a driver that runs fine without its device
    (parameter ``port``: ``device`` at 115200 baud; it opens nothing)."""
    return in_namespace("robot", script_node("talker.py", "teleop", '<remap from="chatter" to="cmd_vel"/>'),
                        script_node("talker.py", "base", '<param name="topic" value="odom"/>',
                                    '<param name="listen" value="chatter"/>'),
                        script_node("configured_node.py", "driver", f'<param name="port" value="{device}:115200"/>'))
