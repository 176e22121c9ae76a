"""Kills its parent when that parent is a warm start server (so it dies with it), then runs like
a talker. Started cold it just runs."""

import os
import signal

import rclpy
from rclpy.node import Node
from std_msgs.msg import String

with open(f"/proc/{os.getppid()}/cmdline", "rb") as f:
    if b"warm_server" in f.read():
        os.kill(os.getppid(), signal.SIGKILL)

rclpy.init()
node = Node("survivor")
node.create_publisher(String, "chatter", 10)
rclpy.spin(node)
