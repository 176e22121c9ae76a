"""Initialises ROS 2 and exits without creating a node."""

import rclpy

rclpy.init()
print("nothing to see here")
rclpy.shutdown()
