"""Two nodes in one process under a MultiThreadedExecutor."""
import rclpy
from rclpy.executors import MultiThreadedExecutor
from rclpy.node import Node
from std_msgs.msg import Int32, String


def main():
    rclpy.init()
    alpha = Node("alpha")
    beta = Node("beta", namespace="team")
    pub = alpha.create_publisher(Int32, "numbers", 10)
    alpha.create_timer(0.2, lambda: pub.publish(Int32(data=1)))
    beta.create_subscription(Int32, "/numbers", lambda m: None, 10)
    beta.create_publisher(String, "report", 10)
    executor = MultiThreadedExecutor(num_threads=2)
    executor.add_node(alpha)
    executor.add_node(beta)
    executor.spin()


if __name__ == "__main__":
    main()
