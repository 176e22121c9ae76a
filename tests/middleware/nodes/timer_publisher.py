"""Creates a publisher from a one-shot timer 0.5 s after start-up."""
import rclpy
from rclpy.node import Node
from std_msgs.msg import String


def main():
    rclpy.init()
    node = Node("late_starter")
    state = {}

    def later():
        state["timer"].cancel()
        state["pub"] = node.create_publisher(String, "late", 10)

    state["timer"] = node.create_timer(0.5, later)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
