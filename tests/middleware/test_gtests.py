"""The C++ unit tests (gtest, registered with ctest) as one pytest test."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import pytest
import rmwi_helpers as h

#: the gtest binaries rmw_introspect_cpp/test/CMakeLists.txt registers
REGISTERED = 18


def registered_tests(build_dir: Path) -> list[tuple[str, list[str], Path, float]]:
    """Each test ctest knows of in ``build_dir``: (name, the gtest command, its working
    directory, its timeout). ament registers each through its ``run_test.py`` wrapper run by the
    Python of the venv the build was configured with; the build is reused by later clones whose
    venv is another (tests/middleware/conftest.py `_build_key`), so the test runs the gtest
    command itself, with the current environment, not ctest's line."""
    listing = subprocess.run(["ctest", "--show-only=json-v1"], cwd=build_dir, capture_output=True, text=True,
                             check=True)
    tests = []
    for test in json.loads(listing.stdout)["tests"]:
        command = test["command"]
        properties = {p["name"]: p["value"] for p in test.get("properties", [])}
        gtest = command[command.index("--command") + 1:] if "--command" in command else command
        tests.append((test["name"], gtest, Path(properties.get("WORKING_DIRECTORY", build_dir)),
                      float(properties.get("TIMEOUT", 120))))
    return tests


# Building the 18 gtest binaries (the session fixture, cached by what they are built from) takes
# about five minutes of a loaded 2-core machine: more than the suite's 300 s per-test timeout.
@pytest.mark.timeout(1500)
def test_every_registered_gtest_passes(gtest_build_dir):
    tests = registered_tests(gtest_build_dir)
    assert len(tests) == REGISTERED, [name for name, *_ in tests]  # none silently left out
    failed = []
    for name, command, cwd, timeout in tests:
        try:
            result = subprocess.run(command, cwd=cwd, env=h.ros_environment(), capture_output=True, text=True,
                                    timeout=timeout)
        except subprocess.TimeoutExpired:
            failed.append(f"{name}: timed out after {timeout:g} s")
            continue
        if result.returncode != 0 or "[  PASSED  ]" not in result.stdout:
            failed.append(f"{name} (exit {result.returncode}):\n{result.stdout[-4000:]}{result.stderr[-2000:]}")
    assert not failed, "\n\n".join(failed)
