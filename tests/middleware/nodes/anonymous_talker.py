"""A node that names itself anew every run, as programs that want a unique name do (neither
rclpy nor rclcpp makes anonymous names): `anonymous_talker_<16 random hex digits>` with a
publisher on `chatter` and a service under its own name (`~/reset`). `--name NAME` names it
NAME instead (a real rename); `--two` starts a second such node in the process."""
import secrets
import sys

import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from std_msgs.msg import String
from std_srvs.srv import Trigger


def make(name):
    node = Node(name)
    node.create_publisher(String, "chatter", 10)
    node.create_service(Trigger, "~/reset", lambda request, response: response)
    return node


def main():
    rclpy.init()
    base = sys.argv[sys.argv.index("--name") + 1] if "--name" in sys.argv else "anonymous_talker"
    executor = SingleThreadedExecutor()
    executor.add_node(make(f"{base}_{secrets.token_hex(8)}"))
    if "--two" in sys.argv:
        executor.add_node(make(f"{base}_{secrets.token_hex(8)}"))
    executor.spin()


if __name__ == "__main__":
    main()
