"""A node whose interfaces use the richest types of test_msgs (nested types, fixed arrays,
bounded and unbounded sequences, bounded strings, wide strings, constants), a service, a
client of a service with constants and an action server: what the capture's `types` table
describes."""
import rclpy
from action_msgs.srv import CancelGoal
from rclpy.action import ActionServer
from rclpy.node import Node
from test_msgs.action import Fibonacci
from test_msgs.msg import MultiNested, Strings, WStrings
from test_msgs.srv import BasicTypes


def main():
    rclpy.init()
    node = Node("types_node")
    node.create_publisher(MultiNested, "multi_nested", 10)
    node.create_publisher(WStrings, "wstrings", 10)
    node.create_subscription(Strings, "strings", lambda m: None, 10)
    node.create_service(BasicTypes, "basic_types", lambda req, resp: resp)
    node.create_client(CancelGoal, "cancel")
    ActionServer(node, Fibonacci, "fibonacci", lambda goal_handle: Fibonacci.Result())
    rclpy.spin(node)


if __name__ == "__main__":
    main()
