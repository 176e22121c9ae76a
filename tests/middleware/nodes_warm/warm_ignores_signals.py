"""Creates a node, then ignores SIGINT and SIGTERM and never spins: only SIGKILL ends it."""

import signal
import time

import rclpy
from rclpy.node import Node
from std_msgs.msg import String

signal.signal(signal.SIGINT, signal.SIG_IGN)
signal.signal(signal.SIGTERM, signal.SIG_IGN)
rclpy.init()
node = Node("stubborn")
node.create_publisher(String, "stubborn", 10)
while True:
    time.sleep(0.1)
