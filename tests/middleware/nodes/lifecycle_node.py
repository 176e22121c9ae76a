"""Lifecycle node: configures (creating a lifecycle publisher and a scratch publisher that
on_activate destroys again), then activates itself and spins."""
import rclpy
from rclpy.lifecycle import LifecycleNode, TransitionCallbackReturn
from std_msgs.msg import String


class Managed(LifecycleNode):
    def __init__(self):
        super().__init__("lc_node")
        self.pub = None
        self.scratch = None

    def on_configure(self, state):
        self.pub = self.create_lifecycle_publisher(String, "lc_chatter", 10)
        self.scratch = self.create_publisher(String, "scratch", 10)
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state):
        self.destroy_publisher(self.scratch)
        self.scratch = None
        return super().on_activate(state)


def main():
    rclpy.init()
    node = Managed()
    node.trigger_configure()
    node.trigger_activate()
    rclpy.spin(node)


if __name__ == "__main__":
    main()
