"""Action client: test_msgs/action/Fibonacci on `fibonacci`; sends one goal."""
import rclpy
from rclpy.action import ActionClient
from rclpy.node import Node
from test_msgs.action import Fibonacci


def main():
    rclpy.init()
    node = Node("fibonacci_client")
    client = ActionClient(node, Fibonacci, "fibonacci")
    client.wait_for_server()
    future = client.send_goal_async(Fibonacci.Goal(order=5))
    rclpy.spin_until_future_complete(node, future)


if __name__ == "__main__":
    main()
