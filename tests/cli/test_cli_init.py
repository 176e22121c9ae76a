"""`rmw-introspect init --package P`: a contract per executable of an installed package."""

from __future__ import annotations

import os
import shutil
import sys
from pathlib import Path

from cli_helpers import NODES

REPO = Path(__file__).resolve().parents[2]
EXAMPLE = REPO / "examples" / "rmw_introspect_examples"


def test_init_on_the_example_package_writes_a_contract_per_executable(cli):
    shutil.copy(EXAMPLE / "package.xml", cli.path / "package.xml")
    result = cli("init", "--package", "rmw_introspect_examples", timeout=300)
    assert result.returncode == 0, result
    installed = sorted(p.name for p in (Path(sys.executable).parent.parent / "lib" / "rmw_introspect_examples").iterdir())
    written = sorted(p.name.removesuffix(".interfaces.yaml") for p in (cli.path / "contracts").iterdir())
    assert written == installed
    assert "add to CMakeLists.txt" in result.stdout and "rmw_introspect_add_contract_tests" in result.stdout
    # the same interfaces as the example's own contracts (captured with the same defaults)
    for name in ("talker", "listener", "c_talker", "battery_monitor"):
        diff = cli("diff", EXAMPLE / "contracts" / f"{name}.interfaces.yaml", f"contracts/{name}.interfaces.yaml")
        assert diff.returncode == 0, diff
    check = cli("check", "contracts/talker.interfaces.yaml")
    assert check.returncode == 0, check
    again = cli("init", "--package", "rmw_introspect_examples", timeout=300)
    assert again.returncode == 0 and "kept  contracts/talker.interfaces.yaml (exists; --force overwrites it)" in again.stdout


def test_init_reports_what_it_could_not_capture(cli, tmp_path):
    prefix = tmp_path / "prefix"
    (prefix / "share" / "ament_index" / "resource_index" / "packages").mkdir(parents=True)
    (prefix / "share" / "ament_index" / "resource_index" / "packages" / "demo_pkg").write_text("")
    lib = prefix / "lib" / "demo_pkg"
    lib.mkdir(parents=True)
    talker = lib / "talker"
    talker.write_text(f"#!{sys.executable}\n" + (NODES / "talker.py").read_text())
    broken = lib / "needs_hardware"
    broken.write_text("#!/bin/sh\necho 'cannot open /dev/ttyUSB0' >&2\nexit 3\n")
    # two executables that hang: they time out side by side, not one after the other
    starts = tmp_path / "starts.txt"
    hung = [lib / "hangs_a", lib / "hangs_b"]
    for exe in hung:
        exe.write_text(f"#!/bin/sh\ndate +%s.%N >> {starts}\nexec sleep 60\n")
    for exe in (talker, broken, *hung):
        exe.chmod(0o755)
    # the installed package.xml says what kind of package it is (the output directory has none)
    (prefix / "share" / "demo_pkg").mkdir(parents=True)
    (prefix / "share" / "demo_pkg" / "package.xml").write_text(
        '<package format="3"><name>demo_pkg</name><export><build_type>ament_python</build_type></export></package>')
    env = {"AMENT_PREFIX_PATH": f"{prefix}{os.pathsep}{os.environ.get('AMENT_PREFIX_PATH', '')}"}
    out = cli.path / "demo"
    result = cli("init", "--package", "demo_pkg", "--output-dir", out, "--timeout", "6", env=env, timeout=300)
    assert result.returncode == 2, result
    assert (out / "contracts" / "talker.interfaces.yaml").is_file()
    assert not (out / "contracts" / "needs_hardware.interfaces.yaml").exists()
    assert "could not capture demo_pkg/needs_hardware: The target demo_pkg/needs_hardware exited with status 3" in result.stderr
    assert "    Last lines of its stderr:\n        cannot open /dev/ttyUSB0" in result.stderr  # why it failed
    for exe in hung:
        assert f"could not capture demo_pkg/{exe.name}: The target demo_pkg/{exe.name} did not settle within 6 s" \
            in result.stderr
    first, second = sorted(float(t) for t in starts.read_text().split())
    assert second - first < 5, (first, second)  # in turn, the second would start after the first's 6 s
    assert "Run the contracts with `pytest" in result.stdout
    assert "CMakeLists" not in result.stdout and "rmw_introspect_add_contract_tests" not in result.stdout


def test_init_of_an_unknown_package_is_an_error(cli):
    result = cli("init", "--package", "no_such_package_here")
    assert result.returncode == 2, result
    assert "package 'no_such_package_here' installs no executables" in result.stderr and "Traceback" not in result.stderr
