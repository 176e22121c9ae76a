"""A thread parked in rmw_wait from the start (a node spun by a MultiThreadedExecutor in its own
thread, as rclcpp's sim-time clock thread or a TransformListener's spin thread is) while the
main thread waits on the real clock before it declares its parameters and creates its
publishers (issue 50 item 1): first time.sleep (a sleep the middleware defines), then
threading.Event.wait (a timed wait it does not: the thread census reads it). Then it hands its
node to the executor already spinning and waits for ever."""
import threading
import time

import rclpy
from rclpy.executors import MultiThreadedExecutor
from std_msgs.msg import String


def main():
    rclpy.init()
    parked = rclpy.create_node("parked")
    parked.create_subscription(String, "/clock_like", lambda m: None, 10)
    executor = MultiThreadedExecutor(num_threads=2)
    executor.add_node(parked)
    threading.Thread(target=executor.spin, daemon=True).start()
    node = rclpy.create_node("late")
    time.sleep(0.3)
    node.declare_parameter("rate", 2.5)
    node.create_publisher(String, "after_sleep", 10)
    threading.Event().wait(0.3)
    node.declare_parameter("gain", 7)
    node.create_publisher(String, "after_wait", 10)
    executor.add_node(node)
    threading.Event().wait()


if __name__ == "__main__":
    main()
