"""self_test: a program that runs, reports and ends by itself (exit status 0).

Interface: publisher ``self_test/report`` (std_msgs/msg/String, KEEP_LAST 1, RELIABLE,
TRANSIENT_LOCAL: late joiners still get the last report) and service client
``enable_motors`` (std_srvs/srv/SetBool), for as long as the program runs.

The node checks its surroundings for ``duration`` seconds (a one-shot timer on the ROS
clock), publishes its verdict, destroys itself and returns 0. Nothing is left alive when the
process ends, so a capture takes what was alive just before the program's own final teardown
and marks the capture "ended by itself".

Parameter: ``duration`` (double, ``2.0``).
"""

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile
from std_msgs.msg import String
from std_srvs.srv import SetBool


class SelfTest(Node):

    def __init__(self, **kwargs):
        super().__init__('self_test', **kwargs)
        self.duration = self.declare_parameter('duration', 2.0).value
        self.done = False
        latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self._report = self.create_publisher(String, '~/report', latched)
        self._motors = self.create_client(SetBool, 'enable_motors')
        self._timer = self.create_timer(self.duration, self._finish)

    def _finish(self):
        self.destroy_timer(self._timer)
        verdict = 'motor driver present' if self._motors.service_is_ready() else 'no motor driver'
        self._report.publish(String(data=verdict))
        self.get_logger().info(f'self test done: {verdict}')
        self.done = True


def main(args=None):
    rclpy.init(args=args)
    node = SelfTest()
    try:
        while rclpy.ok() and not node.done:
            rclpy.spin_once(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
    return 0
