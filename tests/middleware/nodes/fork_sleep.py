"""Publishes, sleeps 0.5 s (proven idle there: the warp starts and jumps that sleep), then forks
while its capture warps: the child's sleeps are not the parent's session's (the middleware's
runtime belongs to the process whose rmw_init started it), so the child sleeps 0.2 s for real.
Prints the child's slept time."""
import os
import sys
import time

import rclpy
from std_msgs.msg import String


def main():
    rclpy.init()
    node = rclpy.create_node("forker")
    node.create_publisher(String, "before_fork", 10).publish(String(data="hello"))
    time.sleep(0.5)
    pid = os.fork()
    if pid == 0:
        t = time.monotonic()
        time.sleep(0.2)
        print(f"child slept {time.monotonic() - t:.3f}", flush=True)
        os._exit(0)
    _, status = os.waitpid(pid, 0)
    sys.exit(os.waitstatus_to_exitcode(status))


if __name__ == "__main__":
    main()
