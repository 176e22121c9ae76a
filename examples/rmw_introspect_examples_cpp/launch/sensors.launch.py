"""The robot's sensors, included by robot.launch.py with its arguments: a driver that creates
its publisher 2 s after start (late_publisher), started only when `with_late_driver` is true."""

from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('with_late_driver', default_value='true',
                              description='start the driver that publishes after 2 s'),
        Node(package='rmw_introspect_examples_cpp', executable='late_publisher', name='late_driver',
             condition=IfCondition(LaunchConfiguration('with_late_driver'))),
    ])
