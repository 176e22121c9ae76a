"""Creates a node and a publisher, then sleeps forever without ever spinning (never settles)."""

import time

import rclpy
from rclpy.node import Node
from std_msgs.msg import String

rclpy.init()
node = Node("sleeper")
node.create_publisher(String, "snore", 10)
while True:
    time.sleep(0.1)
