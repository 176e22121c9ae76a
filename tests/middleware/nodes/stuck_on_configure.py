"""A lifecycle node whose on_configure never returns (issue 24 item 7): it waits for a device
that never answers (STUCK_HOW=sleep: a time.sleep loop; else an Event.wait without a timeout).
A capture must say it is blocked in a callback, not that it kept changing its interfaces."""
import os
import threading
import time

import rclpy
from rclpy.lifecycle import LifecycleNode, TransitionCallbackReturn
from std_msgs.msg import String


class Stuck(LifecycleNode):
    def __init__(self):
        super().__init__("stuck_configure")

    def on_configure(self, state):
        self.create_lifecycle_publisher(String, "never_configured", 10)
        if os.environ.get("STUCK_HOW") == "sleep":
            while True:
                time.sleep(0.05)
        threading.Event().wait()
        return TransitionCallbackReturn.SUCCESS


def main():
    rclpy.init()
    rclpy.spin(Stuck())


if __name__ == "__main__":
    main()
