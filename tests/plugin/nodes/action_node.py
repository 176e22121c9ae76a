"""An action server (test_msgs/action/Fibonacci on /fibonacci) and an action client (/count)."""

import rclpy
from rclpy.action import ActionClient, ActionServer
from rclpy.node import Node
from test_msgs.action import Fibonacci


def main():
    rclpy.init()
    node = Node("fibonacci_server")
    ActionServer(node, Fibonacci, "fibonacci", lambda goal: Fibonacci.Result())
    ActionClient(node, Fibonacci, "count")
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, rclpy.executors.ExternalShutdownException):
        pass


if __name__ == "__main__":
    main()
