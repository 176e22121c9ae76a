"""One node with publishers and subscriptions in several QoS flavours."""

import rclpy
from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    LivelinessPolicy,
    QoSProfile,
    ReliabilityPolicy,
    qos_profile_sensor_data,
)
from std_msgs.msg import Float64, String


def main():
    rclpy.init()
    node = Node("qos_node", namespace="/sensors")
    node.create_publisher(Float64, "scan", qos_profile_sensor_data)
    latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    node.create_publisher(String, "/map", latched)
    node.create_subscription(
        String,
        "commands",
        lambda m: None,
        QoSProfile(
            history=HistoryPolicy.KEEP_ALL,
            reliability=ReliabilityPolicy.RELIABLE,
            deadline=Duration(seconds=0.1),
            liveliness=LivelinessPolicy.AUTOMATIC,
        ),
    )
    node.create_subscription(String, "~/private", lambda m: None, 5)
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, rclpy.executors.ExternalShutdownException):
        pass


if __name__ == "__main__":
    main()
