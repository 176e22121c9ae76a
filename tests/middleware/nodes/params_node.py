"""Parameters of every type with their descriptors: integer and floating point ranges,
read_only, dynamic typing, descriptions, additional constraints, nested names, a parameter
declared with a type only; overridden by a params file and `-p` (--ros-args)."""
import rclpy
from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
from rclpy.node import Node
from rclpy.parameter import Parameter
from std_msgs.msg import String


class Params(Node):
    def __init__(self):
        super().__init__("params_node")
        self.declare_parameter("flag", True)
        self.declare_parameter("count", 42, ParameterDescriptor(
            description="how many", integer_range=[IntegerRange(from_value=0, to_value=100, step=2)]))
        self.declare_parameter("gain", 0.5, ParameterDescriptor(
            floating_point_range=[FloatingPointRange(from_value=0.0, to_value=1.0, step=0.0)],
            additional_constraints="tuned on the robot"))
        self.declare_parameter("frame", "base_link", ParameterDescriptor(read_only=True, description="TF frame"))
        self.declare_parameter("blob", [b"\x00", b"\x01", b"\xff"])
        self.declare_parameter("flags", [True, False, True])
        self.declare_parameter("ids", [1, -2, 3])
        self.declare_parameter("weights", [0.25, 1.0, -1e300])
        self.declare_parameter("names", ["a", "b c", "ü"])
        self.declare_parameter("limits.max_speed", 2.0)
        self.declare_parameter("limits.nested.deep", 7)
        self.declare_parameter("anything", 1, ParameterDescriptor(dynamic_typing=True))
        self.declare_parameter("typed_only", Parameter.Type.STRING)
        self.create_publisher(String, "chatter", 10)


def main():
    rclpy.init()
    rclpy.spin(Params())


if __name__ == "__main__":
    main()
