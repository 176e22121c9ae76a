"""The ROS 2 environment and the middleware library of a command-line run, found on first use."""

from __future__ import annotations

from pathlib import Path

from ..run import middleware, ros_env
from ..run.ros_env import RosEnvironment


class Setup:
    """ROS environment and middleware library, found on first use (only when a target runs)."""

    def __init__(self) -> None:
        self._ros: RosEnvironment | None = None
        self._library: Path | None = None

    def ros(self) -> RosEnvironment:
        if self._ros is None:
            self._ros = ros_env.detect()
        return self._ros

    def library(self) -> Path:
        if self._library is None:
            self._library = Path(middleware.ensure_library(self.ros()))
        return self._library
