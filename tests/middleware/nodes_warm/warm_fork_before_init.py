"""Reaches the preloaded middleware before forking (rcutils_steady_time_now makes its runtime, as
any import-time ROS log line would in a warm start server), then forks: the child sets its own
RMW_INTROSPECT_* variables, initializes rclpy and runs a talker; the parent never initializes and
waits for it. The child's capture must follow the child's settings, written with the child's pid."""

import ctypes
import os
import sys

import rclpy
from rclpy.node import Node
from std_msgs.msg import String

stamp = ctypes.c_int64()
assert ctypes.CDLL(None).rcutils_steady_time_now(ctypes.byref(stamp)) == 0  # the runtime exists now

pid = os.fork()
if pid == 0:
    for key, value in os.environ.items():
        if key.startswith("CHILD_RMW_INTROSPECT_"):
            os.environ[key[len("CHILD_"):]] = value
    rclpy.init()
    node = Node("forked_talker")
    node.create_publisher(String, "forked_chatter", 10)
    node.create_timer(0.05, lambda: None)
    rclpy.spin(node)
    os._exit(3)  # EXIT=1 ends the process when it settles: never reached
_, status = os.waitpid(pid, 0)
print(f"child {pid} status {os.waitstatus_to_exitcode(status)}")
sys.stdout.flush()
