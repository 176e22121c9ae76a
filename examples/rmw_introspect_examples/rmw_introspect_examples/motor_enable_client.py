"""motor_enable_client: a service client that waits for its server, calls it once and exits.

Interface: service client ``enable_motors`` (std_srvs/srv/SetBool).

The client exists as soon as the node is constructed, but a program like this one only gets
past ``wait_for_service()`` once a server is available. Under the recording middleware every
service counts as available (``RMW_INTROSPECT_SERVER_AVAILABLE=1``, the default), so the
client sends its request and then waits for an answer that never comes: the process settles
while it waits, and the capture holds everything it created. With a real middleware and a
running ``motor_enable_server`` it prints the answer and exits.

It asks again when no answer comes within five seconds: on DDS a response is lost when the
server sends it before it has matched this client's response reader (Fast DDS waits 100 ms for
that match, and discovery on a loaded machine can take longer; seen in this project's CI, where
the client then waited forever). Setting the motors is idempotent, so asking twice is safe.

Parameter: ``enable`` (bool, ``true``): the value to request.
"""

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from std_srvs.srv import SetBool

#: seconds to wait for an answer before asking again
ANSWER_TIMEOUT = 5.0


class MotorEnableClient(Node):

    def __init__(self, **kwargs):
        super().__init__('motor_enable_client', **kwargs)
        self.enable = self.declare_parameter('enable', True).value
        self.client = self.create_client(SetBool, 'enable_motors')

    def call(self):
        """Wait for the server, then send the request; returns the response future."""
        while not self.client.wait_for_service(timeout_sec=1.0):
            self.get_logger().info(f'{self.client.srv_name} not available, waiting...')
        return self.client.call_async(SetBool.Request(data=self.enable))

    def call_until_answered(self):
        """Call the server and wait for its answer, asking again after ``ANSWER_TIMEOUT``."""
        while True:
            future = self.call()
            rclpy.spin_until_future_complete(self, future, timeout_sec=ANSWER_TIMEOUT)
            if future.done():
                return future.result()
            self.client.remove_pending_request(future)
            self.get_logger().warn(
                f'no answer from {self.client.srv_name} in {ANSWER_TIMEOUT:.0f} s, asking again')


def main(args=None):
    rclpy.init(args=args)
    node = MotorEnableClient()
    try:
        response = node.call_until_answered()
        node.get_logger().info(f'success={response.success}: {response.message}')
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
