"""rmw_introspect_add_contract_tests(): contract files registered as CTest tests, through real
CMake builds and ctest runs (a plain CMake project, and the example ament package)."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

import pytest_rmw_introspect

REPO = Path(__file__).resolve().parents[2]
CMAKE_DIR = Path(pytest_rmw_introspect.__file__).parent / "cmake"
TALKER = REPO / "tests" / "plugin" / "nodes" / "talker.py"
VENV = Path(sys.executable).parent.parent


def contract(depth: int) -> str:
    return (
        "contract_version: 1\n"
        f"target:\n  script: {TALKER}\n"
        "nodes:\n"
        "  /talker:\n"
        "    publishers:\n"
        "      - name: /chatter\n"
        "        type: std_msgs/msg/String\n"
        f"        qos: {{history: KEEP_LAST, depth: {depth}, reliability: RELIABLE, durability: VOLATILE}}\n"
    )


def run(*args: str | Path, cwd: Path, env: dict[str, str] | None = None, timeout: float = 600) -> subprocess.CompletedProcess:
    return subprocess.run([str(a) for a in args], cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)


@pytest.fixture(autouse=True)
def _tools():
    if shutil.which("cmake") is None or shutil.which("ctest") is None:
        pytest.fail("cmake and ctest are required (apt-get install cmake)")


def test_a_plain_cmake_project_gets_one_test_per_contract(tmp_path):
    (tmp_path / "contracts").mkdir()
    (tmp_path / "contracts" / "talker.interfaces.yaml").write_text(contract(depth=10))
    (tmp_path / "contracts" / "drifted.interfaces.yaml").write_text(contract(depth=3))
    (tmp_path / "contracts" / "notes.yaml").write_text("not a contract\n")
    (tmp_path / "CMakeLists.txt").write_text(
        "cmake_minimum_required(VERSION 3.14)\nproject(demo NONE)\nenable_testing()\n"
        f'find_package(pytest_rmw_introspect REQUIRED PATHS "{CMAKE_DIR}" NO_DEFAULT_PATH)\n'
        f'rmw_introspect_add_contract_tests(DIRECTORY contracts TIMEOUT 90 PYTHON "{sys.executable}")\n'
    )
    build = tmp_path / "build"
    configured = run("cmake", "-S", tmp_path, "-B", build, cwd=tmp_path)
    assert configured.returncode == 0, configured.stderr
    listed = run("ctest", "-N", cwd=build)
    assert "contract_drifted" in listed.stdout and "contract_talker" in listed.stdout and "notes" not in listed.stdout
    tested = run("ctest", "--output-on-failure", "-j", "2", cwd=build)
    assert tested.returncode != 0, tested.stdout  # the drifted contract fails
    assert re.search(r"Test +#\d+: contract_talker \.+ +Passed", tested.stdout), tested.stdout
    assert re.search(r"Test +#\d+: contract_drifted \.+\**Failed", tested.stdout), tested.stdout
    assert "QOS_DEPTH_INCREASED" in tested.stdout
    results = build / "test_results" / "demo"
    suite = ET.parse(results / "contract_drifted.xunit.xml").getroot()
    assert suite.find(".//failure") is not None
    assert ET.parse(results / "contract_talker.xunit.xml").getroot().find(".//failure") is None


def test_unknown_arguments_and_missing_contracts_are_configure_errors(tmp_path):
    (tmp_path / "contracts").mkdir()
    (tmp_path / "CMakeLists.txt").write_text(
        "cmake_minimum_required(VERSION 3.14)\nproject(demo NONE)\nenable_testing()\n"
        f'find_package(pytest_rmw_introspect REQUIRED PATHS "{CMAKE_DIR}" NO_DEFAULT_PATH)\n'
        f'rmw_introspect_add_contract_tests(DIRECTORY contracts CONTRACTS missing.interfaces.yaml PYTHON "{sys.executable}")\n'
    )
    failed = run("cmake", "-S", tmp_path, "-B", tmp_path / "b1", cwd=tmp_path)
    message = " ".join(failed.stderr.split())  # CMake wraps its messages
    assert failed.returncode != 0 and "missing.interfaces.yaml does not exist" in message, failed.stderr
    (tmp_path / "CMakeLists.txt").write_text(
        (tmp_path / "CMakeLists.txt").read_text().replace("CONTRACTS missing.interfaces.yaml", "TIMOUT 3"))
    typo = run("cmake", "-S", tmp_path, "-B", tmp_path / "b2", cwd=tmp_path)
    assert typo.returncode != 0 and "unknown arguments TIMOUT" in " ".join(typo.stderr.split()), typo.stderr


def test_the_example_package_runs_its_contracts_through_ctest(tmp_path):
    """The example ament package calls the function: build it with tests, install it, ctest."""
    src = REPO / "examples" / "rmw_introspect_examples"
    build, prefix = tmp_path / "build", tmp_path / "install"
    env = dict(os.environ, AMENT_PREFIX_PATH=str(VENV))
    env.pop("CI", None)
    configured = run("cmake", "-S", src, "-B", build, f"-DCMAKE_PREFIX_PATH={VENV}", f"-DCMAKE_INSTALL_PREFIX={prefix}",
                     f"-DPython3_EXECUTABLE={sys.executable}", "-DBUILD_TESTING=ON", cwd=tmp_path, env=env)
    assert configured.returncode == 0, configured.stdout[-3000:] + configured.stderr[-3000:]
    built = run("cmake", "--build", build, "--parallel", "2", cwd=tmp_path, env=env)
    assert built.returncode == 0, built.stdout[-3000:] + built.stderr[-3000:]
    installed = run("cmake", "--install", build, cwd=tmp_path, env=env)
    assert installed.returncode == 0, installed.stderr
    contracts = sorted(p.name.split(".")[0] for p in (src / "contracts").glob("*.interfaces.yaml"))
    env["AMENT_PREFIX_PATH"] = f"{prefix}:{VENV}"
    tested = run("ctest", "-R", "^contract_", "-j", "2", "--output-on-failure", cwd=build, env=env, timeout=900)
    assert tested.returncode == 0, tested.stdout[-5000:]
    assert f"100% tests passed, 0 tests failed out of {len(contracts)}" in tested.stdout
    results = build / "test_results" / "rmw_introspect_examples"
    assert sorted(p.name for p in results.glob("contract_*.xunit.xml")) == [f"contract_{c}.xunit.xml" for c in contracts]
