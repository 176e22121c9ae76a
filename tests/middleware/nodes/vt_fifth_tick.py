"""Virtual time: a 1 Hz timer creates a subscription on its 5th tick and keeps ticking."""
import rclpy
from rclpy.node import Node
from std_msgs.msg import String


def main():
    rclpy.init()
    node = Node("vt_ticker")
    state = {"ticks": 0}
    pub = node.create_publisher(String, "ticks", 10)

    def tick():
        state["ticks"] += 1
        pub.publish(String(data=str(state["ticks"])))
        if state["ticks"] == 5:
            state["sub"] = node.create_subscription(String, "fifth", lambda m: None, 10)

    node.create_timer(1.0, tick)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
