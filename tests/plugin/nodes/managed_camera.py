"""A lifecycle camera driver with many parameters: a driver's usual mix of descriptors (read-only,
ranges with steps, an additional constraint, dynamic typing, arrays, nested names), parameters
declared in on_configure, and the QoS override parameters of its image publisher
(QoSOverridingOptions: ``qos_overrides./image.publisher.*``, declared when the publisher is
created on configure). Configured: publisher /image; activated: subscription /camera/trigger,
service /camera/calibrate and a timer that creates /camera/status 0.5 s (ROS time) later.
Argument `fail_activate`: on_activate returns FAILURE."""
import sys

import rclpy
from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
from rclpy.lifecycle import LifecycleNode, TransitionCallbackReturn
from rclpy.parameter import Parameter
from rclpy.qos_overriding_options import QoSOverridingOptions
from std_msgs.msg import Empty, String
from std_srvs.srv import Trigger


class ManagedCamera(LifecycleNode):
    def __init__(self, mode):
        super().__init__("camera")
        self.mode = mode
        self.declare_parameter("frame_id", "camera_optical", ParameterDescriptor(
            read_only=True, description="TF frame of the images"))
        self.declare_parameter("rate", 30.0, ParameterDescriptor(
            description="frames per second",
            floating_point_range=[FloatingPointRange(from_value=1.0, to_value=60.0, step=0.0)]))
        self.declare_parameter("exposure_us", 1000, ParameterDescriptor(
            integer_range=[IntegerRange(from_value=100, to_value=20000, step=100)],
            additional_constraints="a multiple of 100"))
        self.declare_parameter("enable_color", True)
        self.declare_parameter("gains", [1.0, 1.0, 1.0])
        self.declare_parameter("roi.offset", [0, 0])
        self.declare_parameter("roi.size", [640, 480])
        self.declare_parameter("serial", Parameter.Type.STRING)  # no default: a deployment sets it
        self.declare_parameter("mode", "auto", ParameterDescriptor(dynamic_typing=True))
        self.timer = None
        self.status = None

    def on_configure(self, state):
        self.declare_parameter("calibration_file", "", ParameterDescriptor(description="camera_info YAML"))
        self.declare_parameter("buffers", 4, ParameterDescriptor(
            integer_range=[IntegerRange(from_value=1, to_value=16, step=1)]))
        self.image = self.create_lifecycle_publisher(
            String, "image", 5, qos_overriding_options=QoSOverridingOptions.with_default_policies())
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state):
        if self.mode == "fail_activate":
            return TransitionCallbackReturn.FAILURE
        self.trigger = self.create_subscription(Empty, "~/trigger", lambda msg: None, 10)
        self.calibrate = self.create_service(Trigger, "~/calibrate", lambda req, res: res)
        self.timer = self.create_timer(0.5, self.report)
        return super().on_activate(state)

    def report(self):
        if self.status is None:
            self.status = self.create_publisher(String, "~/status", 10)
            self.timer.cancel()


def main():
    args = rclpy.utilities.remove_ros_args(sys.argv)
    rclpy.init()
    rclpy.spin(ManagedCamera(args[1] if len(args) > 1 else ""))


if __name__ == "__main__":
    main()
