"""fibonacci_client: an action client that sends one goal and exits with the result.

Interface: action client ``fibonacci`` (test_msgs/action/Fibonacci): the mirror image of the
server's set (clients of the three ``fibonacci/_action/*`` services, subscriptions to its
feedback and status topics), all created by the ``ActionClient`` constructor.

Unlike ``motor_enable_client``, which blocks in ``wait_for_service()``, this client waits
without blocking: a timer checks ``server_is_ready()`` while the node spins, and sends the
goal once the server is there. The node therefore always waits inside the executor, which is
where the recording middleware sees it settle, whatever the middleware answers about the
server (an action server counts as ready only when its three services are available *and*
its feedback and status topics have publishers).

Both of its requests are asked again until they are answered: on DDS a service response can be
lost when it is sent before the server has matched the client's response reader (seen in this
package's smoke test: all the feedback arrived, the result never did; and in this project's CI,
where the goal's answer never came). The goal is sent again, as a new goal, when no answer comes
within five seconds (the first accepted goal wins; the server finishes any other one on its
own), and the result is asked for every two seconds until it comes (a result request is
idempotent; the first answer wins).

Parameter: ``order`` (int, ``10``).
"""

import rclpy
from rclpy.action import ActionClient
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.task import Future
from test_msgs.action import Fibonacci

#: seconds to wait for the server's answer to a goal before sending the goal again
GOAL_ANSWER_TIMEOUT = 5.0


class FibonacciClient(Node):

    def __init__(self, **kwargs):
        super().__init__('fibonacci_client', **kwargs)
        self.order = self.declare_parameter('order', 10).value
        #: done with the result sequence, or with None when the goal was rejected
        self.result = Future()
        self._action_client = ActionClient(self, Fibonacci, 'fibonacci')
        self._wait_timer = self.create_timer(0.5, self._send_goal_when_ready)
        self._goal_handle = None
        self._goal_timer = None
        self._result_timer = None

    def _send_goal_when_ready(self):
        if not self._action_client.server_is_ready():
            self.get_logger().info(
                'waiting for the fibonacci action server...', throttle_duration_sec=5.0)
            return
        self._wait_timer.cancel()
        self._goal_timer = self.create_timer(GOAL_ANSWER_TIMEOUT, self._send_goal)
        self._send_goal()

    def _send_goal(self):
        if self._goal_handle is not None or self.result.done():
            self._goal_timer.cancel()
            return
        self.get_logger().info(f'Sending goal: order {self.order}')
        self._action_client.send_goal_async(
            Fibonacci.Goal(order=self.order), feedback_callback=self._on_feedback,
        ).add_done_callback(self._on_goal_response)

    def _on_goal_response(self, goal_future):
        goal_handle = goal_future.result()
        if self._goal_handle is not None or self.result.done():
            return  # a goal sent again: the first answer counts
        self._goal_timer.cancel()
        if not goal_handle.accepted:
            self.get_logger().warn('Goal rejected')
            self.result.set_result(None)
            return
        self._goal_handle = goal_handle
        self._result_timer = self.create_timer(2.0, self._request_result)
        self._request_result()

    def _request_result(self):
        if self.result.done():
            self._result_timer.cancel()
            return
        self._goal_handle.get_result_async().add_done_callback(self._on_result)

    def _on_result(self, future):
        if not self.result.done():
            self.result.set_result(list(future.result().result.sequence))

    def _on_feedback(self, feedback_msg):
        self.get_logger().info(f'Feedback: {list(feedback_msg.feedback.sequence)}')


def main(args=None):
    rclpy.init(args=args)
    node = FibonacciClient()
    try:
        rclpy.spin_until_future_complete(node, node.result)
        if node.result.result() is not None:
            node.get_logger().info(f'Result: {node.result.result()}')
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
