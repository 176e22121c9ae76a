"""A node that declares many parameters (PARAMETER_COUNT, default 15000) before it creates its
publisher and spins (issue 24 item 7): each declaration publishes a parameter event, which is not
the steady state either."""
import os

import rclpy
from rclpy.node import Node
from std_msgs.msg import String


def main():
    rclpy.init()
    node = Node("big_config")
    for index in range(int(os.environ.get("PARAMETER_COUNT", "15000"))):
        node.declare_parameter(f"cell_{index}", index)
    node.create_publisher(String, "configured", 10)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
