"""A service server (/reset) and a client of another node's service (/other/trigger)."""

import rclpy
from rclpy.node import Node
from std_srvs.srv import Empty, Trigger


def main():
    rclpy.init()
    node = Node("service_node")
    node.create_service(Empty, "reset", lambda req, resp: resp)
    node.create_client(Trigger, "/other/trigger")
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, rclpy.executors.ExternalShutdownException):
        pass


if __name__ == "__main__":
    main()
