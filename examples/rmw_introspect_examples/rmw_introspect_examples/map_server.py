"""map_server: publishes a map once, for late joiners too.

Interface: publisher ``map`` (nav_msgs/msg/OccupancyGrid) with the map QoS of REP-2003:
KEEP_LAST 1, RELIABLE, TRANSIENT_LOCAL. The map is published once at start-up; TRANSIENT_LOCAL
keeps it for subscriptions that join later (which must ask for TRANSIENT_LOCAL themselves).
A VOLATILE publisher here would silently starve every TRANSIENT_LOCAL subscriber: exactly the
kind of change a contract test catches.

Parameters: ``frame_id`` (``map``), ``resolution`` (m/cell, ``0.05``), ``width`` and
``height`` (cells, ``100``).
"""

import rclpy
from nav_msgs.msg import OccupancyGrid
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

MAP_QOS = QoSProfile(
    history=HistoryPolicy.KEEP_LAST,
    depth=1,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
)


class MapServer(Node):

    def __init__(self, **kwargs):
        super().__init__('map_server', **kwargs)
        frame_id = self.declare_parameter('frame_id', 'map').value
        resolution = self.declare_parameter('resolution', 0.05).value
        width = self.declare_parameter('width', 100).value
        height = self.declare_parameter('height', 100).value
        self._publisher = self.create_publisher(OccupancyGrid, 'map', MAP_QOS)
        self._publisher.publish(self._make_map(frame_id, resolution, width, height))
        self.get_logger().info(f'Published a {width}x{height} map at {resolution} m/cell')

    def _make_map(self, frame_id, resolution, width, height):
        grid = OccupancyGrid()
        grid.header.stamp = self.get_clock().now().to_msg()
        grid.header.frame_id = frame_id
        grid.info.map_load_time = grid.header.stamp
        grid.info.resolution = float(resolution)
        grid.info.width = width
        grid.info.height = height
        grid.info.origin.orientation.w = 1.0
        # free space inside, occupied border
        grid.data = [
            100 if x in (0, width - 1) or y in (0, height - 1) else 0
            for y in range(height) for x in range(width)
        ]
        return grid


def main(args=None):
    rclpy.init(args=args)
    node = MapServer()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
