#!/usr/bin/env bash
# Build the C++ and launch overlay (rclcpp, components, launch_ros, RMW_IMPLEMENTATION selection)
# over the venv's ROS 2 wheels: `ROS_OVERLAY_SRC=/dir/with/checkouts scripts/build-ros-overlay.sh`.
# The work is scripts/overlay/build.py's (its docstring says what is built and why); prints the
# overlay's install prefix. Same as `make overlay` without the bootstrap step.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
exec "${VENV:-$root/.venv}/bin/python" "$root/scripts/overlay/build.py" "$@"
