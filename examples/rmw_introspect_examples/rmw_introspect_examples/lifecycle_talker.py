"""lifecycle_talker: a managed (lifecycle) node whose publisher appears on ``configure``.

Interface, once configured: lifecycle publisher ``lifecycle_chatter`` (std_msgs/msg/String,
default QoS: KEEP_LAST 10, RELIABLE, VOLATILE), which publishes only while the node is active.
Always: the lifecycle services ``lifecycle_talker/{change_state, get_state, ...}`` and the
topic ``lifecycle_talker/transition_event`` (infrastructure, left out of contracts unless
``include_infrastructure`` is set).

Like any managed node it waits, unconfigured, for a lifecycle manager to configure and activate
it. A capture needs no manager: after the node settles, the recording middleware calls its
``change_state`` service itself (configure, then activate; the target option ``lifecycle``),
so the contract describes the active node.

Parameter: ``period`` (double, seconds between messages, 0.5).
"""

import rclpy
from rcl_interfaces.msg import ParameterDescriptor
from rclpy.executors import ExternalShutdownException
from rclpy.lifecycle import LifecycleNode, TransitionCallbackReturn
from std_msgs.msg import String


class LifecycleTalker(LifecycleNode):

    def __init__(self, **kwargs):
        super().__init__('lifecycle_talker', **kwargs)
        self._period = self.declare_parameter('period', 0.5, ParameterDescriptor(
            description='seconds between messages while active')).value
        self._publisher = None
        self._timer = None
        self._count = 0

    def on_configure(self, state):
        self._publisher = self.create_lifecycle_publisher(String, 'lifecycle_chatter', 10)
        self._timer = self.create_timer(self._period, self._on_timer)
        self.get_logger().info('configured')
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state):
        self.get_logger().info('activated')
        return super().on_activate(state)  # activates the lifecycle publisher

    def on_deactivate(self, state):
        self.get_logger().info('deactivated')
        return super().on_deactivate(state)

    def on_cleanup(self, state):
        self._release()
        return TransitionCallbackReturn.SUCCESS

    def on_shutdown(self, state):
        self._release()
        return TransitionCallbackReturn.SUCCESS

    def _release(self):
        if self._timer is not None:
            self.destroy_timer(self._timer)
            self._timer = None
        if self._publisher is not None:
            self.destroy_lifecycle_publisher(self._publisher)
            self._publisher = None

    def _on_timer(self):
        if self._publisher is None or not self._publisher.is_activated:
            return
        msg = String(data=f'Lifecycle hello: {self._count}')
        self._count += 1
        self._publisher.publish(msg)


def main(args=None):
    rclpy.init(args=args)
    node = LifecycleTalker()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
