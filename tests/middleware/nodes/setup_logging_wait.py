"""A driver that logs while it waits 3 s (real time) for its device, then creates its publisher
and spins (issue 24 item 7): the waiting loop only logs, it is not the steady state."""
import time

import rclpy
from rclpy.node import Node
from std_msgs.msg import String


def main():
    rclpy.init()
    node = Node("device_driver")
    start = time.monotonic()
    while time.monotonic() - start < 3.0:
        node.get_logger().info("waiting for the device...")
        time.sleep(0.05)
    node.create_publisher(String, "scan", 10)
    node.create_timer(0.5, lambda: None)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
