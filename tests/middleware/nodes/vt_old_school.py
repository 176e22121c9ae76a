"""The "old school" loop of the rclpy examples: no executor, no rmw_wait, ever."""
import time

import rclpy
from std_msgs.msg import String


def main():
    rclpy.init()
    node = rclpy.create_node("old_school")
    pub = node.create_publisher(String, "topic", 10)
    msg = String(data="hello")
    while rclpy.ok():
        pub.publish(msg)
        time.sleep(0.2)


if __name__ == "__main__":
    main()
