"""listener: the talker's counterpart.

Interface: subscription ``chatter`` (std_msgs/msg/String) with the default QoS (KEEP_LAST 10,
RELIABLE, VOLATILE), compatible with the talker's publisher.
"""

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from std_msgs.msg import String


class Listener(Node):

    def __init__(self, **kwargs):
        super().__init__('listener', **kwargs)
        self._subscription = self.create_subscription(String, 'chatter', self._on_message, 10)

    def _on_message(self, msg):
        self.get_logger().info(f'I heard: "{msg.data}"')


def main(args=None):
    rclpy.init(args=args)
    node = Listener()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
