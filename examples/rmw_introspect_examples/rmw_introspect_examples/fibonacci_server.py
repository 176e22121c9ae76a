"""fibonacci_server: an action server.

Interface: action server ``fibonacci`` (test_msgs/action/Fibonacci). In the graph an action is
three services (``fibonacci/_action/send_goal``, ``cancel_goal``, ``get_result``) and two topics
(``fibonacci/_action/feedback``, ``fibonacci/_action/status``); a contract lists it as one
action entry with the hashes of its goal, result and feedback parts.
"""

import time

import rclpy
from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from test_msgs.action import Fibonacci

#: F(47) no longer fits the int32 of the sequence
MAX_ORDER = 46


class FibonacciServer(Node):

    def __init__(self, **kwargs):
        super().__init__('fibonacci_server', **kwargs)
        self._action_server = ActionServer(
            self, Fibonacci, 'fibonacci', self._execute,
            goal_callback=self._on_goal, cancel_callback=self._on_cancel)

    def _on_goal(self, goal_request):
        if not 0 <= goal_request.order <= MAX_ORDER:
            self.get_logger().warn(f'Rejecting goal of order {goal_request.order}')
            return GoalResponse.REJECT
        return GoalResponse.ACCEPT

    def _on_cancel(self, goal_handle):
        return CancelResponse.ACCEPT

    def _execute(self, goal_handle):
        self.get_logger().info(f'Computing {goal_handle.request.order} Fibonacci numbers')
        feedback = Fibonacci.Feedback(sequence=[0, 1])
        for _ in range(1, goal_handle.request.order):
            if goal_handle.is_cancel_requested:
                goal_handle.canceled()
                return Fibonacci.Result(sequence=feedback.sequence)
            feedback.sequence.append(feedback.sequence[-1] + feedback.sequence[-2])
            goal_handle.publish_feedback(feedback)
            time.sleep(0.1)
        goal_handle.succeed()
        return Fibonacci.Result(sequence=feedback.sequence[:goal_handle.request.order + 1])


def main(args=None):
    rclpy.init(args=args)
    node = FibonacciServer()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
