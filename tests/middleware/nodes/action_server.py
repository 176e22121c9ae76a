"""Action server: test_msgs/action/Fibonacci on `fibonacci`."""
import rclpy
from rclpy.action import ActionServer
from rclpy.node import Node
from test_msgs.action import Fibonacci


def main():
    rclpy.init()
    node = Node("fibonacci_server")

    def execute(goal_handle):
        goal_handle.succeed()
        return Fibonacci.Result()

    ActionServer(node, Fibonacci, "fibonacci", execute)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
