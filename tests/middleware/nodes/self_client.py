"""A node that calls a service of its own and waits for the answer before it creates the rest of
its interfaces (a pattern of real programs: a node reading its own parameters through a client).
In a capture nothing is delivered: the answer never comes and `/after_answer` is never created."""
import rclpy
from rclpy.node import Node
from std_msgs.msg import String
from std_srvs.srv import Trigger


def main():
    rclpy.init()
    node = Node("self_caller")
    node.create_service(Trigger, "ping", lambda request, response: response)
    client = node.create_client(Trigger, "ping")
    future = client.call_async(Trigger.Request())
    rclpy.spin_until_future_complete(node, future)
    node.create_publisher(String, "after_answer", 10)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
