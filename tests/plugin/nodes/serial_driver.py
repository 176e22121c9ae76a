"""A hardware driver as real bring-ups start them: it declares its ``port`` parameter (a serial
device, default ``/dev/ttyUSB0``), then opens the device and, like a real driver, exits with an
error naming the device when the machine does not have it (before creating any interface). With
the device there it publishes ``imu`` (sensor_msgs/msg/Imu) and serves ``~/reset``."""

import os
import sys

import rclpy
from rclpy.node import Node
from sensor_msgs.msg import Imu
from std_srvs.srv import Trigger


def main():
    rclpy.init()
    node = Node("serial_driver")
    port = node.declare_parameter("port", "/dev/ttyUSB0").value
    device = port.split(":")[0]
    if not os.path.exists(device):
        print(f"[serial_driver] could not open {device}: No such file or directory", file=sys.stderr, flush=True)
        node.destroy_node()
        rclpy.shutdown()
        sys.exit(1)
    node.create_publisher(Imu, "imu", 10)
    node.create_service(Trigger, "~/reset", lambda request, response: response)
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, rclpy.executors.ExternalShutdownException):
        pass


if __name__ == "__main__":
    main()
