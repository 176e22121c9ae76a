"""A consumer of a driver's data: subscribes ``imu`` (sensor_msgs/msg/Imu) and logs what comes."""

import rclpy
from rclpy.node import Node
from sensor_msgs.msg import Imu


def main():
    rclpy.init()
    node = Node("imu_monitor")
    node.create_subscription(Imu, "imu", lambda message: node.get_logger().info("imu"), 10)
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, rclpy.executors.ExternalShutdownException):
        pass


if __name__ == "__main__":
    main()
