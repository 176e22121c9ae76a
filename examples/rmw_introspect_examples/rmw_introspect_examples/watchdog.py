"""watchdog: a supervisor that gives the system a grace period before it subscribes.

Interface, from its 5th tick on (5 s after start with the default ``period``): subscription
``heartbeat`` (std_msgs/msg/Header) with the default QoS. A 1 Hz timer counts ticks; on the
``grace_ticks``-th it subscribes and from then on warns when heartbeats stop.

Like ``battery_monitor``, the interface exists only after some seconds of the node's life;
the recording middleware's virtual time makes those seconds pass at once during a capture.

Parameters: ``period`` (double, ``1.0``), ``grace_ticks`` (integer, ``5``).
"""

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from std_msgs.msg import Header


class Watchdog(Node):

    def __init__(self, **kwargs):
        super().__init__('watchdog', **kwargs)
        self.period = self.declare_parameter('period', 1.0).value
        self.grace_ticks = self.declare_parameter('grace_ticks', 5).value
        self._ticks = 0
        self._beats = 0
        self._subscription = None
        self._timer = self.create_timer(self.period, self._on_tick)

    def _on_tick(self):
        self._ticks += 1
        if self._subscription is None:
            if self._ticks >= self.grace_ticks:
                self._subscription = self.create_subscription(Header, 'heartbeat', self._on_beat, 10)
                self.get_logger().info('grace period over: watching heartbeat')
            return
        if self._beats == 0:
            self.get_logger().warn('no heartbeat', throttle_duration_sec=10.0)
        self._beats = 0

    def _on_beat(self, msg):
        self._beats += 1


def main(args=None):
    rclpy.init(args=args)
    node = Watchdog()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
