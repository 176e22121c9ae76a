"""Service client: waits for `set_flag`, sends one request and waits for the answer.

The subscription it creates after wait_for_service() is only reached when the middleware
reports the server as available (RMW_INTROSPECT_SERVER_AVAILABLE, default 1)."""
import rclpy
from rclpy.node import Node
from std_msgs.msg import String
from std_srvs.srv import SetBool


def main():
    rclpy.init()
    node = Node("flag_client")
    client = node.create_client(SetBool, "set_flag")
    while not client.wait_for_service(timeout_sec=0.2):
        node.get_logger().info("waiting for set_flag")
        rclpy.spin_once(node, timeout_sec=0.0)
    node.create_subscription(String, "flag_status", lambda m: None, 10)
    future = client.call_async(SetBool.Request(data=True))
    rclpy.spin_until_future_complete(node, future)


if __name__ == "__main__":
    main()
