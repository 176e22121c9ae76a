"""Creates a node, then dies of a signal (SIGSEGV by default; WARM_CRASH_SIGNAL names another)
or exits through os._exit(WARM_EXIT_STATUS) when that is set."""

import os
import signal

import rclpy
from rclpy.node import Node
from std_msgs.msg import String

rclpy.init()
node = Node("crasher")
node.create_publisher(String, "doomed", 10)
if "WARM_EXIT_STATUS" in os.environ:
    os._exit(int(os.environ["WARM_EXIT_STATUS"]))
os.kill(os.getpid(), getattr(signal, os.environ.get("WARM_CRASH_SIGNAL", "SIGSEGV")))
