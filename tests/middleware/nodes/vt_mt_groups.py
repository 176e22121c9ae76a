"""Virtual time: a MultiThreadedExecutor, timers in two callback groups; one creates a
publisher at 2 s, the other a subscription at 4 s."""
import rclpy
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup
from rclpy.executors import MultiThreadedExecutor
from rclpy.node import Node
from std_msgs.msg import String


def main():
    rclpy.init()
    node = Node("vt_mt")
    state = {}
    group_a = MutuallyExclusiveCallbackGroup()
    group_b = MutuallyExclusiveCallbackGroup()

    def at_2s():
        state["a"].cancel()
        state["pub"] = node.create_publisher(String, "from_group_a", 10)

    def at_4s():
        state["b"].cancel()
        state["sub"] = node.create_subscription(String, "from_group_b", lambda m: None, 10)

    state["a"] = node.create_timer(2.0, at_2s, callback_group=group_a)
    state["b"] = node.create_timer(4.0, at_4s, callback_group=group_b)
    executor = MultiThreadedExecutor(num_threads=2)
    executor.add_node(node)
    executor.spin()


if __name__ == "__main__":
    main()
