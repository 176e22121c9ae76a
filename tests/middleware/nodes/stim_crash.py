"""A node that cannot cope with a default message: its `image` callback reads the first pixel,
which an empty (default-constructed) sensor_msgs/Image does not have."""
import rclpy
from rclpy.node import Node
from sensor_msgs.msg import Image


def main():
    rclpy.init()
    node = Node("fragile")
    node.create_subscription(Image, "image", lambda msg: node.get_logger().info(f"pixel {msg.data[0]}"), 1)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
