"""Interfaces that only input reveals (stimuli): a camera processor that creates its output
publisher on the first `camera_info`, a raw (serialized) subscription that creates a publisher
on its first message, and a `calibrate` service whose handler creates a client and a
publisher and starts a one-shot timer that creates a report publisher 1 s (ROS time) later.
Each callback prints what it received on stderr, so that a test sees that the
middleware delivered one default-constructed message or request. `cmd_vel` reacts with
nothing."""
import sys

import rclpy
from geometry_msgs.msg import Twist
from rclpy.node import Node
from sensor_msgs.msg import CameraInfo, Image
from std_msgs.msg import String
from std_srvs.srv import Trigger


def say(text):
    print(text, file=sys.stderr, flush=True)


def main():
    rclpy.init()
    node = Node("camera_proc")
    made = {}

    def on_camera_info(msg):
        say(f"camera_info: width={msg.width} height={msg.height} frame_id={msg.header.frame_id!r} "
            f"k={list(msg.k)} d={list(msg.d)} model={msg.distortion_model!r}")
        if "image" not in made:
            made["image"] = node.create_publisher(Image, "image_rect", 5)

    def on_raw(data):
        say(f"raw_in: {type(data).__name__} of {len(data)} bytes")
        if "raw" not in made:
            made["raw"] = node.create_publisher(String, "raw_seen", 10)

    def on_calibrate(request, response):
        say(f"calibrate: {type(request).__name__}")
        made["client"] = node.create_client(Trigger, "save_calibration")
        made["status"] = node.create_publisher(String, "calibration_status", 10)

        def report():
            made["report_timer"].cancel()
            made["report"] = node.create_publisher(String, "calibration_report", 1)

        made["report_timer"] = node.create_timer(1.0, report)
        response.success = True
        response.message = "calibrated"
        return response

    node.create_subscription(CameraInfo, "camera_info", on_camera_info, 10)
    node.create_subscription(String, "raw_in", on_raw, 10, raw=True)
    node.create_subscription(Twist, "cmd_vel", lambda msg: say(f"cmd_vel: {msg.linear.x}"), 10)
    node.create_service(Trigger, "calibrate", on_calibrate)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
