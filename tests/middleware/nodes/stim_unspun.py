"""Two nodes, only the first spun: the second's `ignored` subscription is in no wait set, so no
executor could take a stimulus (the middleware says so instead of waiting)."""
import rclpy
from rclpy.node import Node
from std_msgs.msg import String


def main():
    rclpy.init()
    spun = Node("spun")
    spun.create_subscription(String, "heard", lambda msg: spun.create_publisher(String, "echo", 1), 1)
    idle = Node("idle")
    idle.create_subscription(String, "ignored", lambda msg: None, 1)
    rclpy.spin(spun)


if __name__ == "__main__":
    main()
