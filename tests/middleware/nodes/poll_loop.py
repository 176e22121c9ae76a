"""Polls with nothing to do: `while rclpy.ok(): rclpy.spin_once(node, timeout_sec=0)`, no timer and
no message ever comes - zero-timeout waits that find nothing, 100 % CPU (issue 24, like an rclcpp
`while (!done) spin_some(node)` loop waiting for an answer that never comes)."""
import rclpy
from rclpy.node import Node
from std_msgs.msg import String


def main():
    rclpy.init()
    node = Node("poller")
    node.create_publisher(String, "polled", 10)
    node.create_subscription(String, "never", lambda _msg: None, 10)
    while rclpy.ok():
        rclpy.spin_once(node, timeout_sec=0)


if __name__ == "__main__":
    main()
