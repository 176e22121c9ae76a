"""A client that gives up: no response within 5 s -> exit status 1."""
import sys

import rclpy
from rclpy.node import Node
from std_msgs.msg import String
from std_srvs.srv import SetBool


def main():
    rclpy.init()
    node = Node("impatient_client")
    client = node.create_client(SetBool, "set_flag")
    client.wait_for_service()
    node.create_publisher(String, "asked", 10)
    future = client.call_async(SetBool.Request(data=True))
    rclpy.spin_until_future_complete(node, future, timeout_sec=5.0)
    if not future.done():
        node.get_logger().error("no answer from set_flag within 5 s: giving up")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
