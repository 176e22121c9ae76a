"""The C++ example robot, written the way real packages write their launch files.

- an included launch file with arguments (sensors.launch.py);
- launch arguments (`LaunchConfiguration`) and conditions: `use_components` chooses between the
  talker and listener as components of one container and as processes of their own;
- `GroupAction` + `PushRosNamespace` (everything runs in /robot), `SetRemap` (chatter is
  `status` throughout), `SetParameter` (`use_sim_time` for every node of the group);
- a `Node` with a parameters file (config/talker.yaml), an `OpaqueFunction` that adds a node,
  a `ComposableNodeContainer` with `LoadComposableNodes`, a `LifecycleNode`, and an action server;
- `RegisterEventHandler(OnProcessExit(... Shutdown))`, the usual "stop when this one stops".

    ros2 launch rmw_introspect_examples_cpp robot.launch.py use_components:=false
    rmw-introspect check robot.system.yaml      (contracts/robot.system.yaml)
"""

import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, EmitEvent, GroupAction, IncludeLaunchDescription, OpaqueFunction, RegisterEventHandler
from launch.conditions import IfCondition, UnlessCondition
from launch.event_handlers import OnProcessExit
from launch.events import Shutdown
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import ComposableNodeContainer, LifecycleNode, LoadComposableNodes, Node, PushRosNamespace, SetParameter, SetRemap
from launch_ros.descriptions import ComposableNode

PACKAGE = 'rmw_introspect_examples_cpp'


def status_listener(context):
    """A listener whose name comes from a launch argument (an OpaqueFunction, as real files do)."""
    name = LaunchConfiguration('listener_name').perform(context)
    return [Node(package=PACKAGE, executable='listener', name=name,
                 condition=UnlessCondition(LaunchConfiguration('use_components')))]


def generate_launch_description():
    share = get_package_share_directory(PACKAGE)
    use_components = LaunchConfiguration('use_components')
    container = ComposableNodeContainer(
        name='components', namespace='', package='rclcpp_components', executable='component_container',
        condition=IfCondition(use_components),
        composable_node_descriptions=[
            ComposableNode(package=PACKAGE, plugin='rmw_introspect_examples_cpp::Talker', name='talker',
                           parameters=[os.path.join(share, 'config', 'talker.yaml')]),
        ])
    talker = Node(package=PACKAGE, executable='talker', name='talker',
                  parameters=[os.path.join(share, 'config', 'talker.yaml')], condition=UnlessCondition(use_components))
    return LaunchDescription([
        DeclareLaunchArgument('use_components', default_value='true',
                              description='talker and listener as components of one container'),
        DeclareLaunchArgument('listener_name', default_value='status_listener'),
        GroupAction([
            PushRosNamespace('robot'),
            SetRemap(src='chatter', dst='status'),
            SetParameter(name='use_sim_time', value=False),
            IncludeLaunchDescription(PythonLaunchDescriptionSource(os.path.join(share, 'launch', 'sensors.launch.py')),
                                     launch_arguments={'with_late_driver': 'true'}.items()),
            talker,
            OpaqueFunction(function=status_listener),
            container,
            LoadComposableNodes(target_container='/robot/components', condition=IfCondition(use_components),
                                composable_node_descriptions=[
                                    ComposableNode(package=PACKAGE, plugin='rmw_introspect_examples_cpp::Listener',
                                                   name=LaunchConfiguration('listener_name')),
                                ]),
            LifecycleNode(package=PACKAGE, executable='lifecycle_talker', name='lifecycle_talker', namespace=''),
            Node(package=PACKAGE, executable='fibonacci_server', name='fibonacci'),
        ]),
        RegisterEventHandler(OnProcessExit(target_action=talker, on_exit=[EmitEvent(event=Shutdown())])),
    ])
