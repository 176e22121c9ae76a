"""A talker whose interface is set by ROS parameters, so tests can make it drift on purpose.

Parameters: topic (/chatter), msg_type (String | Int32), depth (10), reliability (reliable |
best_effort), durability (volatile | transient_local), listen (''; a topic to subscribe to).
"""

import rclpy
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import Int32, String


class Talker(Node):
    def __init__(self):
        super().__init__("talker")
        topic = self.declare_parameter("topic", "chatter").value
        msg_type = {"String": String, "Int32": Int32}[self.declare_parameter("msg_type", "String").value]
        qos = QoSProfile(
            depth=self.declare_parameter("depth", 10).value,
            reliability=ReliabilityPolicy[self.declare_parameter("reliability", "reliable").value.upper()],
            durability=DurabilityPolicy[self.declare_parameter("durability", "volatile").value.upper()],
        )
        self.pub = self.create_publisher(msg_type, topic, qos)
        listen = self.declare_parameter("listen", "").value
        if listen:
            self.sub = self.create_subscription(String, listen, lambda msg: None, 10)
        self.timer = self.create_timer(0.5, self.tick)

    def tick(self):
        pass


def main():
    rclpy.init()
    node = Talker()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, rclpy.executors.ExternalShutdownException):
        pass


if __name__ == "__main__":
    main()
