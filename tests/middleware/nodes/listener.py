"""Listener: one std_msgs/String subscription on `chatter`."""
import rclpy
from rclpy.node import Node
from std_msgs.msg import String


def main():
    rclpy.init()
    node = Node("listener")
    node.create_subscription(String, "chatter", lambda msg: node.get_logger().info(msg.data), 10)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
