"""colcon for real over the overlay: in a temporary workspace, `colcon build` and `colcon test`
of the C++ example package (contract tests through rmw_introspect_add_contract_tests) and of an
ament_python package (its contract files collected by pytest through the plugin), `colcon
test-result` reporting them, and a deliberately drifted contract failing `colcon test`."""

from __future__ import annotations

import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from overlay_support import CPP_EXAMPLES, Overlay
from sample_contracts import STRING_HASH

# building the C++ example package from scratch takes minutes on 2 cores
pytestmark = pytest.mark.timeout(2400)


def colcon(overlay: Overlay, ws: Path, *args: str) -> subprocess.CompletedProcess:
    env = overlay.env({"ROS_DOMAIN_ID": "57", "COLCON_HOME": str(ws / ".colcon")})
    return subprocess.run(["nice", "-n", "10", str(overlay.install / "bin" / "colcon"), "--log-base", str(ws / "log"),
                           *args], cwd=ws, env=env, capture_output=True, text=True, timeout=2000)


def write_ament_python_package(src: Path) -> Path:
    """A one-node ament_python package with a contract file of its node."""
    pkg = src / "py_beacon"
    (pkg / "py_beacon").mkdir(parents=True)
    (pkg / "resource").mkdir()
    (pkg / "resource" / "py_beacon").write_text("")
    (pkg / "contracts").mkdir()
    (pkg / "py_beacon" / "__init__.py").write_text("")
    (pkg / "py_beacon" / "beacon.py").write_text(textwrap.dedent("""\
        import rclpy
        from rclpy.node import Node
        from std_msgs.msg import String


        def main():
            rclpy.init()
            node = Node("beacon")
            node.create_publisher(String, "beacon", 5)
            rclpy.spin(node)
        """))
    (pkg / "package.xml").write_text(textwrap.dedent("""\
        <?xml version="1.0"?>
        <package format="3">
          <name>py_beacon</name>
          <version>0.0.1</version>
          <description>one rclpy node</description>
          <maintainer email="nobody@example.com">nobody</maintainer>
          <license>Apache-2.0</license>
          <exec_depend>rclpy</exec_depend>
          <exec_depend>std_msgs</exec_depend>
          <export><build_type>ament_python</build_type></export>
        </package>
        """))
    (pkg / "setup.cfg").write_text("[develop]\nscript_dir=$base/lib/py_beacon\n[install]\ninstall_scripts=$base/lib/py_beacon\n")
    (pkg / "setup.py").write_text(textwrap.dedent("""\
        from setuptools import setup

        setup(
            name="py_beacon",
            version="0.0.1",
            packages=["py_beacon"],
            data_files=[("share/ament_index/resource_index/packages", ["resource/py_beacon"]),
                        ("share/py_beacon", ["package.xml"])],
            entry_points={"console_scripts": ["beacon = py_beacon.beacon:main"]},
            extras_require={"test": ["pytest"]},  # colcon test runs pytest (not unittest) for it
        )
        """))
    (pkg / "contracts" / "beacon.interfaces.yaml").write_text(textwrap.dedent(f"""\
        contract_version: 1
        target:
          package: py_beacon
          executable: beacon
        nodes:
          /beacon:
            publishers:
              - name: /beacon
                type: std_msgs/msg/String
                type_hash: {STRING_HASH}
                qos: {{history: KEEP_LAST, depth: 5, reliability: RELIABLE, durability: VOLATILE}}
            subscriptions: []
            service_servers: []
            service_clients: []
            action_servers: []
            action_clients: []
            parameters: []
        """))
    return pkg


@pytest.fixture(scope="module")
def workspace(overlay, tmp_path_factory) -> Path:
    """A workspace with a copy of the C++ example package (and, beside it, the CMake helper of
    the other example package, which it includes: not a package of the workspace) and the
    ament_python package, built with colcon over the overlay."""
    ws = tmp_path_factory.mktemp("ws")
    # the middleware for the overlay, built before (not inside) the 120 s contract tests
    library = subprocess.run([sys.executable, "-m", "pytest_rmw_introspect.run.middleware"], env=overlay.env(),
                             capture_output=True, text=True, timeout=1200)
    assert library.returncode == 0, library.stderr
    shutil.copytree(CPP_EXAMPLES, ws / "src" / CPP_EXAMPLES.name, ignore=shutil.ignore_patterns("__pycache__"))
    helper = CPP_EXAMPLES.parent / "rmw_introspect_examples" / "cmake"
    shutil.copytree(helper, ws / "src" / "rmw_introspect_examples" / "cmake")
    write_ament_python_package(ws / "src")
    built = colcon(overlay, ws, "build", "--executor", "sequential",
                   "--cmake-args", f"-DPython3_EXECUTABLE={sys.executable}", "-DCMAKE_BUILD_TYPE=Release")
    assert built.returncode == 0, built.stdout[-4000:] + built.stderr[-4000:]
    assert sorted(p.name for p in (ws / "install").iterdir() if p.is_dir()) == ["py_beacon", "rmw_introspect_examples_cpp"]
    return ws


def test_colcon_test_runs_the_contract_tests_and_test_result_reports_them(overlay, workspace):
    tested = colcon(overlay, workspace, "test", "--pytest-args", "contracts")
    assert tested.returncode == 0, tested.stdout[-4000:] + tested.stderr[-4000:]
    result = colcon(overlay, workspace, "test-result", "--test-result-base", str(workspace / "build"), "--all")
    assert result.returncode == 0, result.stdout + result.stderr
    assert "0 errors, 0 failures" in result.stdout
    reported = result.stdout
    for contract in ("talker", "listener", "lifecycle_talker", "fibonacci_server", "late_publisher"):
        assert contract in reported, reported
    assert "beacon" in reported, reported


def test_a_drifted_contract_fails_colcon_test(overlay, workspace):
    for path, old, new in (
        (workspace / "src" / "rmw_introspect_examples_cpp" / "contracts" / "talker.interfaces.yaml", "depth: 10", "depth: 3"),
        (workspace / "src" / "py_beacon" / "contracts" / "beacon.interfaces.yaml", "depth: 5", "depth: 3"),
    ):
        path.write_text(path.read_text().replace(old, new))
    try:
        colcon(overlay, workspace, "test", "--pytest-args", "contracts")
        result = colcon(overlay, workspace, "test-result", "--test-result-base", str(workspace / "build"))
        assert result.returncode != 0, result.stdout
        failed = result.stdout
        assert "talker" in failed and "beacon" in failed, failed
    finally:
        shutil.rmtree(workspace / "build" / "py_beacon" / "pytest_cache", ignore_errors=True)
