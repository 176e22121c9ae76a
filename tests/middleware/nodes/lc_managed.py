"""A lifecycle node with parameters that the middleware drives: a parameter at start, two
declared in on_configure; a lifecycle publisher on configure; a subscription, a service and
a timer on activate, the timer creating one more publisher 0.5 s (ROS time) later.
Argument `fail`: on_configure returns FAILURE; `raise`: on_configure raises."""
import sys

import rclpy
from rcl_interfaces.msg import IntegerRange, ParameterDescriptor
from rclpy.lifecycle import LifecycleNode, TransitionCallbackReturn
from std_msgs.msg import String
from std_srvs.srv import Trigger


class Managed(LifecycleNode):
    def __init__(self, mode):
        super().__init__("managed")
        self.mode = mode
        self.declare_parameter("rate", 10.0, ParameterDescriptor(description="Hz"))
        self.late_pub = None
        self.timer = None

    def on_configure(self, state):
        if self.mode == "fail":
            return TransitionCallbackReturn.FAILURE
        if self.mode == "raise":
            raise RuntimeError("cannot configure")
        self.declare_parameter("topic", "status", ParameterDescriptor(description="where to publish"))
        self.declare_parameter("depth", 5, ParameterDescriptor(
            integer_range=[IntegerRange(from_value=1, to_value=10, step=1)]))
        self.pub = self.create_lifecycle_publisher(
            String, self.get_parameter("topic").value, self.get_parameter("depth").value)
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state):
        self.sub = self.create_subscription(String, "cmd", lambda msg: None, 10)
        self.srv = self.create_service(Trigger, "reset", lambda req, res: res)
        self.timer = self.create_timer(0.5, self.late)
        return super().on_activate(state)

    def late(self):
        if self.late_pub is None:
            self.late_pub = self.create_publisher(String, "late_status", 10)
            self.timer.cancel()


def main():
    args = rclpy.utilities.remove_ros_args(sys.argv)
    rclpy.init()
    rclpy.spin(Managed(args[1] if len(args) > 1 else ""))


if __name__ == "__main__":
    main()
