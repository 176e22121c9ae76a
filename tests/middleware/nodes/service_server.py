"""Service server: std_srvs/SetBool on `set_flag`."""
import rclpy
from rclpy.node import Node
from std_srvs.srv import SetBool


def main():
    rclpy.init()
    node = Node("flag_server")

    def handle(request, response):
        response.success = True
        response.message = "ok"
        return response

    node.create_service(SetBool, "set_flag", handle)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
