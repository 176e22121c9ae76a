"""A node whose own service callback never returns once called (issue 24 item 7): the stimulus
/stuck_service calls it, and the callback waits forever for hardware (STUCK_HOW=sleep: a
time.sleep loop; else an Event.wait without a timeout)."""
import os
import threading
import time

import rclpy
from rclpy.node import Node
from std_srvs.srv import Trigger


def main():
    rclpy.init()
    node = Node("stuck_service_node")

    def handle(request, response):
        if os.environ.get("STUCK_HOW") == "sleep":
            while True:
                time.sleep(0.05)
        threading.Event().wait()
        return response

    node.create_service(Trigger, "stuck_service", handle)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
