"""A program that finishes by itself: after 2 s (ROS time) it destroys its node, shuts down
and returns 0."""
import rclpy
from rclpy.node import Node
from std_msgs.msg import String


def main():
    rclpy.init()
    node = Node("short_lived")
    node.create_publisher(String, "short", 10)
    state = {"done": False}

    def finish():
        state["done"] = True

    node.create_timer(2.0, finish)
    while rclpy.ok() and not state["done"]:
        rclpy.spin_once(node)
    node.destroy_node()
    rclpy.shutdown()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
