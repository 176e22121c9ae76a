"""Fixtures of the plugin's end-to-end tests: real pytest sessions (pytester, in subprocesses so
that the installed plugin loads through its entry point) capturing real rclpy nodes on the
real recording middleware."""

from __future__ import annotations

import sys
import textwrap
from pathlib import Path

import pytest

NODES = Path(__file__).parent / "nodes"


class Project:
    """A pytester project with helpers to write tests and contracts and run pytest on them."""

    def __init__(self, pytester: pytest.Pytester) -> None:
        self.pytester = pytester
        self.path = pytester.path

    def node(self, name: str) -> str:
        return str(NODES / name)

    def write(self, relpath: str, text: str) -> Path:
        path = self.path / relpath
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(textwrap.dedent(text))
        return path

    def test(self, source: str, name: str = "test_nodes.py") -> Path:
        header = f"import pytest\nNODES = {str(NODES)!r}\n\n"
        return self.write(name, header + textwrap.dedent(source))

    def read(self, relpath: str) -> str:
        return (self.path / relpath).read_text()

    def robot_launch(self, more: str = "") -> Path:
        """launch/robot.launch.xml: the talker node script as /<ns>/talker (argument ``ns``, default
        robot), and ``more`` (XML lines) in the same group."""
        return self.write("launch/robot.launch.xml", f"""\
            <launch>
              <arg name="ns" default="robot"/>
              <group>
                <push-ros-namespace namespace="$(var ns)"/>
                <node exec="{sys.executable}" args="{self.node('talker.py')}" name="talker"/>
            {more}  </group>
            </launch>
            """)

    def run(self, *args: str, timeout: float = 120) -> pytest.RunResult:
        return self.pytester.runpytest_subprocess("-p", "no:cacheprovider", "-p", "no:randomly", *args,
                                                  timeout=timeout)


@pytest.fixture
def project(pytester: pytest.Pytester, middleware_library: Path, monkeypatch: pytest.MonkeyPatch) -> Project:
    monkeypatch.setenv("RMW_INTROSPECT_LIBRARY", str(middleware_library))
    for name in ("CI", "PYTEST_ADDOPTS", "PYTEST_DISABLE_PLUGIN_AUTOLOAD", "PYTEST_XDIST_AUTO_NUM_WORKERS"):
        monkeypatch.delenv(name, raising=False)
    # no ini file of this repository applies to the child sessions
    pytester.makeini("[pytest]\n")
    return Project(pytester)
