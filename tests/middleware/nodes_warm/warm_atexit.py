"""Registers atexit handlers and ends by itself (status 0) before it settles: the handlers run
at interpreter exit and record, in WARM_ATEXIT_FILE, the order they ran in and the process."""

import atexit
import os

import rclpy
from rclpy.node import Node
from std_msgs.msg import String

OUT = os.environ["WARM_ATEXIT_FILE"]


def record(what):
    with open(OUT, "a", encoding="utf-8") as f:
        f.write(f"{what} {os.getpid()}\n")


atexit.register(record, "first-registered")


def main():
    rclpy.init()
    node = Node("warm_atexit")
    node.create_publisher(String, "bye", 10)
    atexit.register(record, "last-registered")
    rclpy.spin_once(node, timeout_sec=0)
    node.destroy_node()
    rclpy.shutdown()


if __name__ == "__main__":
    main()
