"""Creates a node and a publisher, then raises before spinning."""
import rclpy
from rclpy.node import Node
from std_msgs.msg import String


def main():
    rclpy.init()
    node = Node("raiser")
    node.create_publisher(String, "doomed", 10)
    raise RuntimeError("failing before spin")


if __name__ == "__main__":
    main()
