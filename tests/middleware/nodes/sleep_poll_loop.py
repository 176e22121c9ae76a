"""A sleep loop: publish, sleep 10 ms on Python's (real) clock, poll the executor - no timer, and
no wait with a timeout that virtual time could jump (issue 24, like an rclcpp
`publish; sleep_for(10ms); spin_some` loop)."""
import time

import rclpy
from rclpy.node import Node
from std_msgs.msg import String


def main():
    rclpy.init()
    node = Node("sleep_poller")
    pub = node.create_publisher(String, "looped", 10)
    while rclpy.ok():
        pub.publish(String(data="tick"))
        time.sleep(0.01)
        rclpy.spin_once(node, timeout_sec=0)


if __name__ == "__main__":
    main()
