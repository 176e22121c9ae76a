"""Endpoints with non-default QoS: sensor data, a latched map, keep-all, deadline/lifespan/liveliness."""
import rclpy
from nav_msgs.msg import OccupancyGrid
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
from sensor_msgs.msg import LaserScan
from std_msgs.msg import Header, String


def main():
    rclpy.init()
    node = Node("qos_node")
    node.create_publisher(LaserScan, "scan", qos_profile_sensor_data)
    node.create_subscription(LaserScan, "scan_in", lambda m: None, qos_profile_sensor_data)
    latched = QoSProfile(
        depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    node.create_publisher(OccupancyGrid, "map", latched)
    keep_all = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE)
    node.create_subscription(String, "events", lambda m: None, keep_all)
    timed = QoSProfile(
        depth=5,
        deadline=Duration(seconds=1, nanoseconds=500_000_000),
        lifespan=Duration(seconds=2),
        liveliness=LivelinessPolicy.MANUAL_BY_TOPIC,
        liveliness_lease_duration=Duration(seconds=3),
    )
    node.create_publisher(Header, "heartbeat", timed)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
