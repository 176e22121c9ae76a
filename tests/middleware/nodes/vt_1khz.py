"""Virtual time: a periodic 1 kHz timer publishing (the warp must stay bounded in real time)."""
import rclpy
from rclpy.node import Node
from std_msgs.msg import String


def main():
    rclpy.init()
    node = Node("vt_fast")
    pub = node.create_publisher(String, "fast", 10)
    msg = String(data="x")
    node.create_timer(0.001, lambda: pub.publish(msg))
    rclpy.spin(node)


if __name__ == "__main__":
    main()
