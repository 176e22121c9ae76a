"""talker: a timer-driven publisher.

Interface: publisher ``chatter`` (std_msgs/msg/String) with the default QoS. Creating it with
a plain depth (``10``) gives KEEP_LAST 10, RELIABLE, VOLATILE.
"""

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from std_msgs.msg import String


class Talker(Node):

    def __init__(self, **kwargs):
        super().__init__('talker', **kwargs)
        self._count = 0
        self._publisher = self.create_publisher(String, 'chatter', 10)
        self._timer = self.create_timer(0.5, self._on_timer)

    def _on_timer(self):
        msg = String(data=f'Hello World: {self._count}')
        self._count += 1
        self.get_logger().info(f'Publishing: "{msg.data}"')
        self._publisher.publish(msg)


def main(args=None):
    rclpy.init(args=args)
    node = Talker()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
