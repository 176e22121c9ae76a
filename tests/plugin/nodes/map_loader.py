"""A node that takes a file by path, as map servers and calibration loaders do: it declares the
string parameter ``map_file`` (default ''), reports whether the file is there, and publishes
nothing. The system rules judge the path (PARAM_PATH_MISSING), the node does not fail on it."""

import os

import rclpy
from rclpy.node import Node


def main():
    rclpy.init()
    node = Node("map_loader")
    path = node.declare_parameter("map_file", "").value
    node.get_logger().info(f"map_file {path!r} {'exists' if os.path.exists(path) else 'is missing'}")
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, rclpy.executors.ExternalShutdownException):
        pass


if __name__ == "__main__":
    main()
