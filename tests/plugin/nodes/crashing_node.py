"""Creates a node and a publisher, then crashes before spinning."""

import rclpy
from rclpy.node import Node
from std_msgs.msg import String

rclpy.init()
node = Node("crasher")
node.create_publisher(String, "doomed", 10)
raise RuntimeError("sensor driver failed to open /dev/ttyUSB0")
