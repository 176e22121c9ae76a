"""relay: two nodes in one process, spun by one MultiThreadedExecutor.

Interface: node ``relay_subscriber`` with subscription ``chatter`` (std_msgs/msg/String) and
node ``relay_publisher`` with publisher ``chatter_relayed`` (std_msgs/msg/String), both with
the default QoS (KEEP_LAST 10, RELIABLE, VOLATILE). Messages pass between the nodes as Python
objects, not through the middleware. One capture holds both nodes, so one contract describes
both (the ``nodes`` mapping has two entries).
"""

import rclpy
from rclpy.executors import ExternalShutdownException, MultiThreadedExecutor
from rclpy.node import Node
from std_msgs.msg import String


class RelayPublisher(Node):

    def __init__(self, **kwargs):
        super().__init__('relay_publisher', **kwargs)
        self._publisher = self.create_publisher(String, 'chatter_relayed', 10)

    def forward(self, msg):
        self._publisher.publish(msg)


class RelaySubscriber(Node):

    def __init__(self, forward, **kwargs):
        super().__init__('relay_subscriber', **kwargs)
        self._forward = forward
        self._subscription = self.create_subscription(String, 'chatter', self._on_message, 10)

    def _on_message(self, msg):
        self.get_logger().info('relaying chatter to chatter_relayed', once=True)
        self._forward(msg)


def main(args=None):
    rclpy.init(args=args)
    publisher = RelayPublisher()
    subscriber = RelaySubscriber(publisher.forward)
    executor = MultiThreadedExecutor()
    executor.add_node(publisher)
    executor.add_node(subscriber)
    try:
        executor.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        executor.shutdown()
        subscriber.destroy_node()
        publisher.destroy_node()
        rclpy.try_shutdown()
