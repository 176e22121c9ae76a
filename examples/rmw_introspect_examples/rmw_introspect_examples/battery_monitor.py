"""battery_monitor: creates its publisher only after a start-up calibration, from a timer.

Interface, from ``calibration_time`` seconds after start (3 s by default): publisher
``battery_state`` (sensor_msgs/msg/BatteryState) with the default QoS (KEEP_LAST 10, RELIABLE,
VOLATILE), published once a second. Before that the node has no publisher at all.

This is the common "late interface" pattern: a driver that creates its topics once its
hardware answered, a planner that subscribes once its map arrived, a node that waits out a
warm-up. A capture that stopped when the node first went quiet would miss the publisher; the
recording middleware's virtual time (target option ``horizon``, 10 s by default) lets the node
live its first seconds in a few milliseconds, so the capture has it without waiting 3 s.

Parameter: ``calibration_time`` (double, ``3.0``): seconds before the publisher is created.
"""

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from sensor_msgs.msg import BatteryState


class BatteryMonitor(Node):

    def __init__(self, **kwargs):
        super().__init__('battery_monitor', **kwargs)
        self.calibration_time = self.declare_parameter('calibration_time', 3.0).value
        self._publisher = None
        self._publish_timer = None
        # rclpy has no one-shot timer: the callback destroys its own timer.
        self._calibration = self.create_timer(self.calibration_time, self._on_calibrated)

    def _on_calibrated(self):
        self.destroy_timer(self._calibration)
        self._publisher = self.create_publisher(BatteryState, 'battery_state', 10)
        self._publish_timer = self.create_timer(1.0, self._publish)
        self.get_logger().info('calibrated: publishing battery state')

    def _publish(self):
        self._publisher.publish(BatteryState(voltage=24.0, percentage=0.8, present=True))


def main(args=None):
    rclpy.init(args=args)
    node = BatteryMonitor()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
