"""Talker: one std_msgs/String publisher on `chatter`, published from a 0.5 s timer."""
import rclpy
from rclpy.node import Node
from std_msgs.msg import String


def main():
    rclpy.init()
    node = Node("talker")
    publisher = node.create_publisher(String, "chatter", 10)
    count = [0]

    def tick():
        msg = String()
        msg.data = f"hello {count[0]}"
        count[0] += 1
        publisher.publish(msg)

    node.create_timer(0.5, tick)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
