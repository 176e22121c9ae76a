"""Issue 47, finding 6: an ament_python package installed with `pip install -e .` (as the README
says) and then captured with `--launch-package`. An editable install writes no `share/` and no
ament index marker (only `__editable__.*.pth`, a finder and `direct_url.json` pointing at the
source tree); the package's share files are found in that source tree as colcon's
`--symlink-install` would link them (the `data_files` of setup.py or setup.cfg).

The user's repository is a temporary git repository, as in the trial; the editable install goes
into a temporary prefix (put on PYTHONPATH) so that the project's venv is not changed."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
import yaml
from cli_helpers import Cli

DRIVER = """
import rclpy
from rclpy.node import Node
from std_msgs.msg import String


def main():
    rclpy.init()
    node = Node('driver')
    node.declare_parameter('frame', 'base')
    node.create_publisher(String, 'scan', 10)
    rclpy.spin(node)
"""

PACKAGE_XML = """\
<?xml version="1.0"?>
<package format="3">
  <name>mybot</name>
  <version>0.1.0</version>
  <description>a robot</description>
  <maintainer email="me@example.com">me</maintainer>
  <license>MIT</license>
  <export><build_type>ament_python</build_type></export>
</package>
"""

SETUP_PY = """
from glob import glob
from setuptools import setup

package_name = 'mybot'
setup(
    name=package_name, version='0.1.0', packages=[package_name],
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
        ('share/' + package_name + '/launch', glob('launch/*.launch.xml')),
        ('share/' + package_name + '/config', glob('params/*.yaml')),
    ],
    entry_points={'console_scripts': ['driver = mybot.driver:main']},
)
"""

SETUP_CFG = """
[metadata]
name = mybot
version = 0.1.0

[options]
packages = mybot

[options.entry_points]
console_scripts =
    driver = mybot.driver:main

[options.data_files]
share/ament_index/resource_index/packages = resource/mybot
share/mybot = package.xml
share/mybot/launch = launch/robot.launch.xml
share/mybot/config = params/driver.yaml
"""

LAUNCH = """\
<launch>
  <node pkg="mybot" exec="driver" name="driver">
    <param from="$(find-pkg-share mybot)/config/driver.yaml"/>
  </node>
</launch>
"""


def user_repository(root: Path, setup: str) -> Path:
    """The user's ament_python package `mybot` in a git repository: the driver node, its launch
    file (in launch/) and parameters (in params/, installed as share/mybot/config)."""
    files = {
        "mybot/__init__.py": "",
        "mybot/driver.py": DRIVER,
        "resource/mybot": "",
        "package.xml": PACKAGE_XML,
        "launch/robot.launch.xml": LAUNCH,
        "params/driver.yaml": "driver:\n  ros__parameters:\n    frame: laser\n",
    }
    if setup == "setup.cfg":
        files.update({"setup.cfg": SETUP_CFG, "setup.py": "from setuptools import setup\nsetup()\n"})
    else:
        files["setup.py"] = SETUP_PY
    for relpath, text in files.items():
        (root / relpath).parent.mkdir(parents=True, exist_ok=True)
        (root / relpath).write_text(textwrap.dedent(text))
    for command in (["init", "-q"], ["add", "."], ["-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", "mybot"]):
        subprocess.run(["git", *command], cwd=root, check=True)
    return root


def editable_install(source: Path, prefix: Path) -> Path:
    """`pip install -e SOURCE` into ``prefix``; its site-packages."""
    subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--no-build-isolation",
                    "--no-index", "-e", str(source), "--prefix", str(prefix)], check=True, capture_output=True)
    [site] = prefix.glob("lib/python*/site-packages")
    assert not (prefix / "share").exists()  # what the trial saw: no share/, no ament index marker
    return site


def user_env(site: Path, repo: Path, tmp_path: Path) -> dict[str, str]:
    """The venv with the editable install: its site-packages (and, since a .pth file on
    PYTHONPATH is not run, the source tree) on PYTHONPATH before what the tests run with."""
    path = os.pathsep.join([str(site), str(repo), *filter(None, [os.environ.get("PYTHONPATH")])])
    return {"PYTHONPATH": path, "RMW_INTROSPECT_CACHE": str(tmp_path / "cache")}


@pytest.mark.parametrize("setup", ["setup.py", "setup.cfg"])
def test_launch_package_of_an_editable_install(cli: Cli, tmp_path: Path, setup: str) -> None:
    repo = user_repository(tmp_path / "repo", setup)
    site = editable_install(repo, tmp_path / "venv-prefix")
    env = user_env(site, repo, tmp_path)
    done = cli("capture", "--launch-package", "mybot", "--launch-file", "robot.launch.xml",
               "-o", "robot.system.yaml", env=env)
    assert done.returncode == 0, done.stderr
    system = yaml.safe_load(cli.read("robot.system.yaml"))
    text = yaml.safe_dump(system)
    assert "/driver" in text and "/scan" in text, text
    assert "laser" in text, text  # the parameter file of share/mybot/config, from params/ in the source
    # a file added to the source tree is seen at once, as a symlink install sees it
    (repo / "launch" / "second.launch.xml").write_text(LAUNCH.replace('name="driver"', 'name="second"'))
    if setup == "setup.py":  # setup.py globs launch/*.launch.xml
        again = cli("capture", "--launch-package", "mybot", "--launch-file", "second.launch.xml",
                    "-o", "second.system.yaml", env=env)
        assert again.returncode == 0, again.stderr
        assert "/second" in cli.read("second.system.yaml")


def test_an_editable_install_without_package_xml_says_what_to_do(cli: Cli, tmp_path: Path) -> None:
    repo = user_repository(tmp_path / "repo", "setup.py")
    (repo / "package.xml").unlink()
    setup = (repo / "setup.py").read_text().replace("        ('share/' + package_name, ['package.xml']),\n", "")
    (repo / "setup.py").write_text(setup.replace(
        "        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),\n", ""))
    site = editable_install(repo, tmp_path / "venv-prefix")
    env = user_env(site, repo, tmp_path)
    done = cli("capture", "--launch-package", "mybot", "--launch-file", "robot.launch.xml",
               "-o", "robot.system.yaml", env=env)
    assert done.returncode == 2
    assert "mybot" in done.stderr and "pip install -e" in done.stderr and str(repo) in done.stderr, done.stderr
    assert "package.xml" in done.stderr and "ament_index/resource_index/packages" in done.stderr, done.stderr
