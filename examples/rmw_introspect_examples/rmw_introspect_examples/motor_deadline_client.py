"""motor_deadline_client: a service client that gives up (exit status 1) after a deadline.

Interface: service client ``enable_motors`` (std_srvs/srv/SetBool).

It sends one request and waits at most ``deadline`` seconds of ROS time for the answer: with a
``motor_enable_server`` running it prints the answer and exits 0; without one it logs an error
and exits 1. Under the recording middleware no answer ever comes and virtual time lets the
deadline expire at once, so the program exits 1 within milliseconds: the capture keeps what it
created (it had settled before) and reports the exit status as information, not as a failure.

The deadline is measured on the node's ROS clock, not with ``time.monotonic()``: a deadline in
Python's own time (``spin_until_future_complete(timeout_sec=...)`` measures with it) is real
time, which virtual time cannot shorten.

Parameter: ``deadline`` (double, ``5.0``).
"""

import sys

import rclpy
from rclpy.duration import Duration
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from std_srvs.srv import SetBool


class MotorDeadlineClient(Node):

    def __init__(self, **kwargs):
        super().__init__('motor_deadline_client', **kwargs)
        self.deadline = self.declare_parameter('deadline', 5.0).value
        self.client = self.create_client(SetBool, 'enable_motors')


def main(args=None):
    rclpy.init(args=args)
    node = MotorDeadlineClient()
    status = 0
    try:
        node.client.wait_for_service(timeout_sec=node.deadline)
        future = node.client.call_async(SetBool.Request(data=True))
        clock = node.get_clock()
        give_up_at = clock.now() + Duration(seconds=node.deadline)
        while rclpy.ok() and not future.done() and clock.now() < give_up_at:
            rclpy.spin_once(node, timeout_sec=0.1)
        if future.done():
            response = future.result()
            node.get_logger().info(f'success={response.success}: {response.message}')
        else:
            node.get_logger().error(f'no answer from {node.client.srv_name} within {node.deadline} s')
            status = 1
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
    return status


if __name__ == '__main__':
    sys.exit(main())
