"""Two nodes, only the first spun: the second's parameter services are in no wait set, so
the middleware cannot ask them (and says so instead of waiting for an answer)."""
import rclpy
from rclpy.node import Node


def main():
    rclpy.init()
    spun = Node("spun")
    spun.declare_parameter("here", 1)
    idle = Node("idle")
    idle.declare_parameter("never_read", 2)
    rclpy.spin(spun)


if __name__ == "__main__":
    main()
