"""Reads its environment and arguments at import time: node name from WARM_NODE_NAME, topic
from the first argument, and a topic per argument count."""

import os
import sys

import rclpy
from rclpy.node import Node
from std_msgs.msg import String

NAME = os.environ.get("WARM_NODE_NAME", "unnamed")
TOPIC = sys.argv[1] if len(sys.argv) > 1 and not sys.argv[1].startswith("-") else "no_argument"
ARGC = len(sys.argv)


def main():
    rclpy.init()
    node = Node(NAME)
    node.create_publisher(String, TOPIC, 10)
    node.create_publisher(String, f"argc_{ARGC}", 10)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
