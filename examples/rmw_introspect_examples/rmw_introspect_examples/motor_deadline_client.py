"""motor_deadline_client: a service client that gives up (exit status 1) after a deadline.

Interface: service client ``enable_motors`` (std_srvs/srv/SetBool).

It sends one request and waits at most ``deadline`` seconds (ROS time) for the answer: with a
``motor_enable_server`` running it prints the answer and exits 0; without one it logs an error
and exits 1. Under the recording middleware no answer ever comes and virtual time lets the
deadline expire at once, so the program exits 1 within milliseconds: the capture keeps what it
created (it had settled before) and reports the exit status as information, not as a failure.

Parameter: ``deadline`` (double, ``5.0``).
"""

import sys

import rclpy
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
        rclpy.spin_until_future_complete(node, future, timeout_sec=node.deadline)
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
