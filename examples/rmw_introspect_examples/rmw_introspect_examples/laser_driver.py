"""laser_driver: a (simulated) laser scanner driver, following REP-2003.

Interface: publisher ``scan`` (sensor_msgs/msg/LaserScan) with the *system default* QoS
(``qos_profile_system_default``: every policy SYSTEM_DEFAULT). REP-2003 asks sensor drivers to
publish with the system defaults so that the deployment, not the driver, decides how sensor
data travels; consumers subscribe with the sensor-data profile (see ``scan_consumer``), which
matches whatever the driver ends up offering.

Parameters: ``frame_id`` (string, ``laser``), ``rate`` (Hz, ``10.0``).
"""

import math

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.qos import qos_profile_system_default
from sensor_msgs.msg import LaserScan

BEAMS = 360


class LaserDriver(Node):

    def __init__(self, **kwargs):
        super().__init__('laser_driver', **kwargs)
        self._frame_id = self.declare_parameter('frame_id', 'laser').value
        rate = self.declare_parameter('rate', 10.0).value
        self._period = 1.0 / rate
        self._publisher = self.create_publisher(LaserScan, 'scan', qos_profile_system_default)
        self._timer = self.create_timer(self._period, self._on_timer)
        self._phase = 0.0
        self.get_logger().info(f'Publishing simulated scans in frame {self._frame_id!r} at {rate} Hz')

    def _on_timer(self):
        scan = LaserScan()
        scan.header.stamp = self.get_clock().now().to_msg()
        scan.header.frame_id = self._frame_id
        scan.angle_min = -math.pi
        scan.angle_max = math.pi - 2.0 * math.pi / BEAMS
        scan.angle_increment = 2.0 * math.pi / BEAMS
        scan.scan_time = self._period
        scan.time_increment = self._period / BEAMS
        scan.range_min = 0.1
        scan.range_max = 10.0
        # a room whose walls breathe a little: enough to look alive in a plot
        self._phase += 0.1
        scan.ranges = [
            2.0 + 0.5 * math.sin(3.0 * (scan.angle_min + i * scan.angle_increment) + self._phase)
            for i in range(BEAMS)
        ]
        self._publisher.publish(scan)


def main(args=None):
    rclpy.init(args=args)
    node = LaserDriver()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
