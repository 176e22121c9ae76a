"""Virtual time: a timer creates a service server 30 s after start-up."""
import rclpy
from rclpy.node import Node
from std_srvs.srv import Trigger


def main():
    rclpy.init()
    node = Node("vt_slow_server")
    state = {}

    def later():
        state["timer"].cancel()
        state["srv"] = node.create_service(Trigger, "ready_after_30s", lambda req, res: res)

    state["timer"] = node.create_timer(30.0, later)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
