"""fibonacci_client: an action client that sends one goal and exits with the result.

Interface: action client ``fibonacci`` (test_msgs/action/Fibonacci): the mirror image of the
server's set (clients of the three ``fibonacci/_action/*`` services, subscriptions to its
feedback and status topics).

As with ``motor_enable_client``, the recording middleware answers "available" to
``wait_for_server()``; the goal then waits forever for an acceptance, and the process settles
while waiting.

Parameter: ``order`` (int, ``10``).
"""

import rclpy
from rclpy.action import ActionClient
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.task import Future
from test_msgs.action import Fibonacci


class FibonacciClient(Node):

    def __init__(self, **kwargs):
        super().__init__('fibonacci_client', **kwargs)
        self.order = self.declare_parameter('order', 10).value
        self._action_client = ActionClient(self, Fibonacci, 'fibonacci')

    def send_goal(self):
        """Wait for the server, send the goal; returns a future of the result (or None)."""
        while not self._action_client.wait_for_server(timeout_sec=1.0):
            self.get_logger().info('fibonacci action server not available, waiting...')
        self.get_logger().info(f'Sending goal: order {self.order}')
        result = Future()
        goal_future = self._action_client.send_goal_async(
            Fibonacci.Goal(order=self.order), feedback_callback=self._on_feedback)
        goal_future.add_done_callback(lambda future: self._on_goal_response(future, result))
        return result

    def _on_goal_response(self, goal_future, result):
        goal_handle = goal_future.result()
        if not goal_handle.accepted:
            self.get_logger().warn('Goal rejected')
            result.set_result(None)
            return
        goal_handle.get_result_async().add_done_callback(
            lambda future: result.set_result(future.result().result))

    def _on_feedback(self, feedback_msg):
        self.get_logger().info(f'Feedback: {list(feedback_msg.feedback.sequence)}')


def main(args=None):
    rclpy.init(args=args)
    node = FibonacciClient()
    try:
        result = node.send_goal()
        rclpy.spin_until_future_complete(node, result)
        if result.result() is not None:
            node.get_logger().info(f'Result: {list(result.result().sequence)}')
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
