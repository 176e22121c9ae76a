"""A lifecycle node driven by its own timer: configure at 1 s, activate at 2 s (ROS time)."""
import rclpy
from rclpy.lifecycle import LifecycleNode, TransitionCallbackReturn
from std_msgs.msg import String


class SelfDriven(LifecycleNode):
    def __init__(self):
        super().__init__("vt_lc")
        self.pub = None
        self.step = 0
        self.timer = self.create_timer(1.0, self.drive)

    def drive(self):
        self.step += 1
        if self.step == 1:
            self.trigger_configure()
        elif self.step == 2:
            self.trigger_activate()
            self.timer.cancel()

    def on_configure(self, state):
        self.pub = self.create_lifecycle_publisher(String, "lc_vt", 10)
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state):
        self.create_subscription(String, "lc_vt_cmd", lambda m: None, 10)
        return super().on_activate(state)


def main():
    rclpy.init()
    rclpy.spin(SelfDriven())


if __name__ == "__main__":
    main()
