"""For RMW_INTROSPECT_EXIT=0: creates `first` at start, `second` after 0.6 s, keeps spinning."""
import rclpy
from rclpy.node import Node
from std_msgs.msg import String


def main():
    rclpy.init()
    node = Node("changer")
    node.create_publisher(String, "first", 10)
    state = {}

    def later():
        state["timer"].cancel()
        state["second"] = node.create_publisher(String, "second", 10)

    state["timer"] = node.create_timer(0.6, later)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
