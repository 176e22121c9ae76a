"""Virtual time: a demo that simulates a publisher dying (issue 24 item 4). Node /survivor
publishes /status and /alive; node /doomed publishes /heartbeat and serves /doomed/ping. A
one-shot timer 8 s (ROS time) after start-up destroys /survivor's /status publisher and the whole
/doomed node; the program then spins until it is stopped."""
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from std_msgs.msg import String
from std_srvs.srv import Empty


def main():
    rclpy.init()
    survivor = Node("survivor")
    doomed = Node("doomed")
    status = survivor.create_publisher(String, "status", 10)
    survivor.create_publisher(String, "alive", 10)
    doomed.create_publisher(String, "heartbeat", 10)
    doomed.create_service(Empty, "~/ping", lambda request, response: response)
    executor = SingleThreadedExecutor()
    executor.add_node(survivor)
    executor.add_node(doomed)
    state = {}

    def die():
        state["timer"].cancel()
        survivor.destroy_publisher(status)
        executor.remove_node(doomed)
        doomed.destroy_node()

    state["timer"] = survivor.create_timer(8.0, die)
    executor.spin()


if __name__ == "__main__":
    main()
