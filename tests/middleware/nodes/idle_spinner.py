"""A node that spins with nothing to do (no timers): its CPU use must stay ~0."""
import rclpy
from rclpy.node import Node
from std_msgs.msg import String


def main():
    rclpy.init()
    node = Node("idle")
    node.create_subscription(String, "nothing", lambda m: None, 10)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
