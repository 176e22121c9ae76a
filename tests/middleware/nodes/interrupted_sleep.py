"""Publishes once, then sleeps 60 s with Python's time.sleep; on SIGINT it prints "interrupted"
and exits 0: a sleep of the middleware's (src/sleep.cpp) must still end on a signal, as the C
library's does (EINTR, then Python raises KeyboardInterrupt)."""
import sys
import time

import rclpy
from std_msgs.msg import String


def main():
    rclpy.init()
    node = rclpy.create_node("long_sleeper")
    node.create_publisher(String, "once", 10).publish(String(data="hello"))
    print("sleeping", flush=True)
    try:
        time.sleep(60)
    except KeyboardInterrupt:
        print("interrupted", flush=True)
        sys.exit(0)
    sys.exit(3)


if __name__ == "__main__":
    main()
