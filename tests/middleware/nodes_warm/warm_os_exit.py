"""Creates its node and a publisher, then ends at once with os._exit() (no atexit handlers, no
interpreter finalization, no shutdown of rclpy): the capture is the middleware's progress
snapshot, due 20 ms after its last change. Also forks a child that ends with os._exit() without
ROS, as multiprocessing's workers do: that one must not wait for a capture."""

import os

import rclpy
from std_msgs.msg import String

child = os.fork()
if child == 0:
    os._exit(0)
os.waitpid(child, 0)
rclpy.init()
node = rclpy.create_node("quitter")
node.create_publisher(String, "last_words", 1)
os._exit(0)
