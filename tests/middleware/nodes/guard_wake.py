"""Spins with no timer; a thread triggers an rclpy guard condition after 0.3 s, whose
callback creates a publisher. Only a wait that wakes on the trigger records it."""
import threading
import time

import rclpy
from rclpy.node import Node
from std_msgs.msg import String


def main():
    rclpy.init()
    node = Node("guard_wake")
    created = {}

    def on_trigger():
        if "pub" not in created:
            created["pub"] = node.create_publisher(String, "woken", 10)

    guard = node.create_guard_condition(on_trigger)

    def later():
        time.sleep(0.3)
        guard.trigger()

    threading.Thread(target=later, daemon=True).start()
    rclpy.spin(node)


if __name__ == "__main__":
    main()
