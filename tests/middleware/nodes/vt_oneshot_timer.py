"""Virtual time: a one-shot timer creates a publisher 3 s (ROS time) after start-up."""
import rclpy
from rclpy.node import Node
from std_msgs.msg import String


def main():
    rclpy.init()
    node = Node("vt_oneshot")
    state = {}

    def later():
        state["timer"].cancel()
        state["pub"] = node.create_publisher(String, "late3", 10)

    state["timer"] = node.create_timer(3.0, later)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
