"""Starting the warm start server for targets like a spec ahead of their captures.

The pytest plugin calls :func:`warm_up` at the start of a session so that the server imports
rclpy while the session collects and sets up; the first capture then starts warm. A server
serves targets of one environment and working directory (``warm.client.server_key``): the
environment is the one the runner gives such a target (``resolution.environment``).
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from . import middleware, ros_env
from .resolution import OUTPUT_PATTERN, environment
from .target import TargetSpec


def warm_up(spec: TargetSpec | None = None, *, library: str | Path | None = None, ros: ros_env.RosEnvironment | None = None,
            wait: float = 0.0, python: str | None = None) -> str | None:
    """Start the warm start server for targets like ``spec`` (default: a target with no `env` of
    its own, in the current directory) ahead of their captures, waiting up to ``wait`` seconds
    for it to be ready. Returns None when it is ready, else why not (still starting, or why it
    cannot be)."""
    spec = spec or TargetSpec()
    ros = ros or ros_env.detect()
    if library is None:
        library = middleware.ensure_library(ros)
    from .warm import client as warm

    env = environment(spec, Path(library), ros, Path(tempfile.gettempdir()) / OUTPUT_PATTERN)
    cwd = str(spec.cwd) if spec.cwd is not None else os.getcwd()
    server = warm.POOL.server(env, cwd, python, wait=wait)
    return None if isinstance(server, warm.WarmServer) else server
