"""pytest-rmw-introspect: interface contract tests for ROS 2 nodes."""

__version__ = "0.1.0"
