"""Appends "pid ppid" to WARM_PID_FILE, creates a node, then spins (or, with WARM_HANG=1,
sleeps for ever without spinning: it never settles). With WARM_CHILD=1 it first starts a
`sleep` in its own process group and appends that pid too ("child PID")."""

import os
import subprocess
import time

import rclpy
from rclpy.node import Node
from std_msgs.msg import String

with open(os.environ["WARM_PID_FILE"], "a", encoding="utf-8") as f:
    f.write(f"{os.getpid()} {os.getppid()}\n")
    if os.environ.get("WARM_CHILD") == "1":
        child = subprocess.Popen(["sleep", "300"])
        f.write(f"child {child.pid}\n")

rclpy.init()
node = Node(os.environ.get("WARM_NODE_NAME", "pid_reporter"))
node.create_publisher(String, "pids", 10)
if os.environ.get("WARM_HANG") == "1":
    while True:
        time.sleep(0.1)
rclpy.spin(node)
