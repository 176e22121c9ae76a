"""Appends "NAME start T" (T: time.time()) to WARM_TIMES_FILE, sleeps WARM_SLEEP seconds of real
time before it initializes ROS (a node that waits for hardware), then creates node NAME."""

import os
import time

import rclpy
from rclpy.node import Node
from std_msgs.msg import String

name = os.environ.get("WARM_NODE_NAME", "slow_start")
with open(os.environ["WARM_TIMES_FILE"], "a", encoding="utf-8") as f:
    f.write(f"{name} start {time.time()!r}\n")
time.sleep(float(os.environ.get("WARM_SLEEP", "2")))
rclpy.init()
node = Node(name)
node.create_publisher(String, "slow", 10)
rclpy.spin(node)
