"""A node configured from outside, as drivers and loaders are: it declares every parameter the
launch file gives it (``automatically_declare_parameters_from_overrides``), whatever its name,
and publishes ``~/status`` (std_msgs/msg/String). It opens none of the files or devices its
parameters name: the system rules judge those values."""

import rclpy
from rclpy.node import Node
from std_msgs.msg import String


def main():
    rclpy.init()
    node = Node("configured_node", automatically_declare_parameters_from_overrides=True)
    node.create_publisher(String, "~/status", 10)
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, rclpy.executors.ExternalShutdownException):
        pass


if __name__ == "__main__":
    main()
