"""A publish loop on Python's time.sleep that, after 6 sleeps of 0.5 s (3 s), also creates a
second publisher and goes on (issue 24): what a sleep loop creates later belongs to its
interface. The middleware's sleeps (src/sleep.cpp) let the warp step it like a timer."""
import time

import rclpy
from std_msgs.msg import String


def main():
    rclpy.init()
    node = rclpy.create_node("sleeper")
    first = node.create_publisher(String, "first", 10)
    sleeps = 0
    while rclpy.ok():
        first.publish(String(data="tick"))
        time.sleep(0.5)
        sleeps += 1
        if sleeps == 6:
            node.create_publisher(String, "after_sleeps", 10)


if __name__ == "__main__":
    main()
