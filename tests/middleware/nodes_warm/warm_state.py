"""Module-level state: its own helper module counts imports; a module the warm start server
imported already (std_msgs.msg) gets an attribute. Each run must see a first time."""

import rclpy
import std_msgs.msg
import warm_state_helper
from rclpy.node import Node
from std_msgs.msg import Empty

std_msgs.msg.warm_marks = getattr(std_msgs.msg, "warm_marks", 0) + 1
COUNTER = [0]


def main():
    COUNTER[0] += 1
    rclpy.init()
    node = Node("warm_state")
    node.create_publisher(Empty, f"/state/loads_v_{len(warm_state_helper.LOADS)}", 1)
    node.create_publisher(Empty, f"/state/marks_v_{std_msgs.msg.warm_marks}", 1)
    node.create_publisher(Empty, f"/state/counter_v_{COUNTER[0]}", 1)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
