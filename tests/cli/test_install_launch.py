"""Issue 47, finding 8: Python launch files with the ROS 2 PyPI wheels, which have no launch or
launch_ros. Without them, a `.launch.py` is an error that names the one command that brings them
(`rmw-introspect install-launch`); after that command (here `--from` the upstream checkouts, into
a temporary `--target` so the project's venv is not changed) the same capture works.

The user's repository is a temporary git repository, as in the trial. The install needs
checkouts of ros2/launch and ros2/launch_ros (jazzy) in $ROS_OVERLAY_SRC or the cache's
sources/overlay-src, as the overlay tier does; elsewhere it is skipped with one line."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
import yaml
from cli_helpers import Cli

from pytest_rmw_introspect.cli import install_launch
from pytest_rmw_introspect.launch import python_file
from pytest_rmw_introspect.run.cache import cache_root

ROBOT = """
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, GroupAction
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node, PushRosNamespace


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('robot', default_value='robot1'),
        GroupAction([
            PushRosNamespace(LaunchConfiguration('robot')),
            Node(package='rmw_introspect_examples', executable='talker', name='status_reporter',
                 remappings=[('chatter', 'status')]),
            Node(package='rmw_introspect_examples', executable='listener', name='status_monitor',
                 remappings=[('chatter', 'status')]),
        ]),
    ])
"""


def _launch_importable() -> bool:
    try:
        python_file.modules()
    except ImportError:
        return False
    return True


def checkouts() -> Path | None:
    """Where the upstream checkouts are (ROS_OVERLAY_SRC, else the cache's sources/overlay-src)."""
    for candidate in (os.environ.get("ROS_OVERLAY_SRC"), str(cache_root() / "sources" / "overlay-src")):
        if candidate and (Path(candidate) / "launch" / "launch" / "setup.py").is_file() \
                and (Path(candidate) / "launch_ros" / "launch_ros" / "setup.py").is_file():
            return Path(candidate)
    return None


def user_repository(root: Path) -> Path:
    (root / "launch").mkdir(parents=True)
    (root / "launch" / "robot.launch.py").write_text(textwrap.dedent(ROBOT))
    for command in (["init", "-q"], ["add", "."], ["-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", "robot"]):
        subprocess.run(["git", *command], cwd=root, check=True)
    return root


def test_the_pip_command_of_a_distribution_and_of_checkouts(tmp_path: Path) -> None:
    command = install_launch.pip_command("kilted", None, None, python="python")
    assert command[:5] == ["python", "-m", "pip", "install", "--no-deps"]
    assert command[-4:] == [
        "launch @ git+https://github.com/ros2/launch.git@kilted#subdirectory=launch",
        "launch_xml @ git+https://github.com/ros2/launch.git@kilted#subdirectory=launch_xml",
        "launch_yaml @ git+https://github.com/ros2/launch.git@kilted#subdirectory=launch_yaml",
        "launch_ros @ git+https://github.com/ros2/launch_ros.git@kilted#subdirectory=launch_ros"]
    for package in ("launch/launch", "launch/launch_xml", "launch/launch_yaml", "launch_ros/launch_ros"):
        (tmp_path / package).mkdir(parents=True)
        (tmp_path / package / "setup.py").write_text("")
    command = install_launch.pip_command(None, tmp_path, tmp_path / "t", python="python")
    assert command[-4:] == [str(tmp_path / p) for p in ("launch/launch", "launch/launch_xml", "launch/launch_yaml",
                                                       "launch_ros/launch_ros")]
    assert ["--target", str(tmp_path / "t")] == command[command.index("--target"):command.index("--target") + 2]


def test_install_launch_says_what_is_missing_from_the_checkouts(cli_nodes_only: Cli, tmp_path: Path) -> None:
    (tmp_path / "src" / "launch" / "launch").mkdir(parents=True)
    (tmp_path / "src" / "launch" / "launch" / "setup.py").write_text("")
    done = cli_nodes_only("install-launch", "--from", "src", "--dry-run")
    assert done.returncode == 2
    assert "missing launch_xml" in done.stderr and "launch_ros (looked for" in done.stderr, done.stderr
    assert "git clone -b jazzy https://github.com/ros2/launch_ros.git" in done.stderr, done.stderr


@pytest.mark.skipif(_launch_importable(), reason="launch and launch_ros are importable here: nothing to install")
def test_a_python_launch_file_works_after_install_launch(cli: Cli, tmp_path: Path) -> None:
    repo = user_repository(tmp_path / "repo")
    # the trial: a .launch.py with the wheels alone is an error; it names the one command
    before = cli("capture", "--launch", repo / "launch" / "robot.launch.py", "-o", "robot.system.yaml")
    assert before.returncode == 2
    assert "run `rmw-introspect install-launch` once" in before.stderr, before.stderr
    src = checkouts()
    if src is None:
        pytest.skip("no checkouts of ros2/launch and ros2/launch_ros: set ROS_OVERLAY_SRC (docs/overlay.md clones them)")
    target = tmp_path / "launch-packages"
    env = {}
    osrf = sorted(cache_root().glob("overlay-*/install/lib/python*/site-packages/osrf_pycommon"))
    if osrf:  # osrf-pycommon from the overlay's install, as a directory of its own: no download
        (tmp_path / "helpers").mkdir()
        (tmp_path / "helpers" / "osrf_pycommon").symlink_to(osrf[-1], target_is_directory=True)
        env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(tmp_path / "helpers"), os.environ.get("PYTHONPATH")]))
    installed = cli("install-launch", "--from", src, "--target", target, env=env, timeout=300)
    assert installed.returncode == 0, installed.stdout + installed.stderr
    assert "Python launch files can be read" in installed.stdout
    assert (target / "share" / "launch" / "frontend" / "grammar.lark").is_file()
    env = {"PYTHONPATH": os.pathsep.join(filter(None, [str(target), env.get("PYTHONPATH") or os.environ.get("PYTHONPATH")])),
           "AMENT_PREFIX_PATH": os.pathsep.join(filter(None, [str(target), os.environ.get("AMENT_PREFIX_PATH")]))}
    after = cli("capture", "--launch", repo / "launch" / "robot.launch.py", "-o", "robot.system.yaml", env=env)
    assert after.returncode == 0, after.stderr
    text = yaml.safe_dump(yaml.safe_load(cli.read("robot.system.yaml")))
    assert "/robot1/status_reporter" in text and "/robot1/status_monitor" in text and "/robot1/status" in text, text
    # the walker's own tests, skipped without launch_ros, run on what the command installed
    walker = subprocess.run([sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-q",
                             str(Path(__file__).parents[1] / "unit" / "test_launch_python.py")],
                            env={**cli.env, **env}, capture_output=True, text=True, check=False, timeout=300)
    assert walker.returncode == 0 and " passed" in walker.stdout and "skipped" not in walker.stdout, walker.stdout
