"""scan_consumer: a consumer of sensor data, following REP-2003.

Interface: subscription ``scan`` (sensor_msgs/msg/LaserScan) with the sensor-data QoS
(``qos_profile_sensor_data``: KEEP_LAST 5, BEST_EFFORT, VOLATILE). A BEST_EFFORT subscription
is compatible with both a RELIABLE and a BEST_EFFORT publisher, so it works with any driver
that publishes with the system defaults (see ``laser_driver``).
"""

import math

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.qos import qos_profile_sensor_data
from sensor_msgs.msg import LaserScan


class ScanConsumer(Node):

    def __init__(self, **kwargs):
        super().__init__('scan_consumer', **kwargs)
        self._subscription = self.create_subscription(
            LaserScan, 'scan', self._on_scan, qos_profile_sensor_data)

    def _on_scan(self, scan):
        valid = [r for r in scan.ranges if scan.range_min <= r <= scan.range_max]
        closest = min(valid) if valid else math.inf
        self.get_logger().info(
            f'closest obstacle: {closest:.2f} m', throttle_duration_sec=2.0)


def main(args=None):
    rclpy.init(args=args)
    node = ScanConsumer()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
