"""motor_enable_server: a service server.

Interface: service server ``enable_motors`` (std_srvs/srv/SetBool). Services have no QoS in a
contract: what matters is the name and the type (and its hash), which every client must match.
"""

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from std_srvs.srv import SetBool


class MotorEnableServer(Node):

    def __init__(self, **kwargs):
        super().__init__('motor_enable_server', **kwargs)
        self._enabled = False
        self._service = self.create_service(SetBool, 'enable_motors', self._on_request)

    def _on_request(self, request, response):
        changed = request.data != self._enabled
        self._enabled = request.data
        state = 'enabled' if self._enabled else 'disabled'
        response.success = True
        response.message = f'motors {state}' if changed else f'motors already {state}'
        self.get_logger().info(response.message)
        return response


def main(args=None):
    rclpy.init(args=args)
    node = MotorEnableServer()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
