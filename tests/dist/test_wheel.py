"""The Linux x86_64 wheel (issue 40, item 1): it carries the middleware prebuilt against the
Jazzy wheels' rmw and bundles no library that ROS provides; installed into a fresh venv with the
Jazzy wheels, it captures a node for a user who has neither CMake nor a compiler, and builds
nothing."""

from __future__ import annotations

import io
import json
import os
import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import pytest
from wheel_support import KILTED_VENV, wheel_distros

#: the wheel is built and installed by the first test that needs it (minutes on a loaded machine)
pytestmark = [pytest.mark.slow, pytest.mark.timeout(1200)]  # marked here too: `-m slow` selects before the tier hook runs

PREBUILT = "pytest_rmw_introspect/prebuilt/jazzy/librmw_introspect_cpp.so"

TALKER = '''import rclpy
from std_msgs.msg import String

rclpy.init()
node = rclpy.create_node("talker")
node.create_publisher(String, "chatter", 10)
rclpy.spin(node)
'''


def _dynamic(library: bytes) -> dict[str, list[str]]:
    # pyelftools comes with auditwheel (requirements/tools.in): not in every venv that collects this file
    from elftools.elf.dynamic import DynamicSection
    from elftools.elf.elffile import ELFFile

    tags: dict[str, list[str]] = {}
    for section in ELFFile(io.BytesIO(library)).iter_sections():
        if isinstance(section, DynamicSection):
            for tag in section.iter_tags():
                if tag.entry.d_tag == "DT_NEEDED":
                    tags.setdefault("needed", []).append(tag.needed)
                elif tag.entry.d_tag in ("DT_RPATH", "DT_RUNPATH"):
                    tags.setdefault(tag.entry.d_tag, []).append(tag.rpath if tag.entry.d_tag == "DT_RPATH" else tag.runpath)
    return tags


def test_the_wheel_carries_the_prebuilt_middleware_and_bundles_nothing_of_ros(built_wheel: Path):
    # the manylinux tag auditwheel gave it: the library's own glibc/libstdc++ symbol versions
    assert re.fullmatch(r"pytest_rmw_introspect-[^-]+-py3-none-manylinux_2_\d+_x86_64\.whl", built_wheel.name)
    with zipfile.ZipFile(built_wheel) as archive:
        names = archive.namelist()
        libraries = sorted(name for name in names if re.search(r"\.so(\.|$)", name))
        expected = sorted(PREBUILT.replace("jazzy", distro) for distro in wheel_distros())
        assert libraries == expected, "the wheel bundles shared libraries besides the middleware (unzip -l)"
        assert not [name for name in names if ".libs/" in name], "auditwheel grafted libraries into the wheel"
        # the sources stay: the fallback build of other distributions and standard installs
        assert "pytest_rmw_introspect/rmw_introspect_cpp/CMakeLists.txt" in names
        (wheel_info,) = [name for name in names if name.endswith(".dist-info/WHEEL")]
        assert "Root-Is-Purelib: false" in archive.read(wheel_info).decode()
        dynamic = _dynamic(archive.read(PREBUILT))
    # it needs the Jazzy wheels' libraries and finds them in the lib/ of the venv it lands in
    assert {"librmw.so", "librcutils.so", "librosidl_runtime_c.so"} <= set(dynamic["needed"])
    assert dynamic.get("DT_RPATH") == ["$ORIGIN/../../../../.."] and "DT_RUNPATH" not in dynamic


def test_a_user_without_a_compiler_captures_a_node_on_the_prebuilt_middleware(installed_wheel, tmp_path: Path):
    cache = tmp_path / "cache"
    env = installed_wheel.env(RMW_INTROSPECT_CACHE=str(cache))
    for tool in ("cmake", "c++", "g++", "make"):
        assert shutil.which(tool, path=env["PATH"]) is None, f"{tool} is on the user's PATH"
    (tmp_path / "talker.py").write_text(TALKER)

    result = subprocess.run([installed_wheel.bin("rmw-introspect"), "capture", "--format", "json", "--script", "talker.py"],
                            cwd=tmp_path, env=env, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    nodes = json.loads(result.stdout)
    assert [pub["name"] for pub in nodes["/talker"]["publishers"]] == ["/chatter"]
    assert "building" not in result.stderr and "waiting" not in result.stderr, result.stderr
    assert not list(cache.glob("jazzy-*")), "the middleware was built although the wheel carries it"

    found = subprocess.run([installed_wheel.bin("python"), "-c", "from pytest_rmw_introspect.run import middleware; "
                            "found = middleware.resolve_library(); print(found.origin, found.path)"],
                           cwd=tmp_path, env=env, capture_output=True, text=True, timeout=60)
    origin, path = found.stdout.split()
    assert origin == "prebuilt" and Path(path).is_relative_to(installed_wheel.venv), found


def test_the_wheels_kilted_library_captures_a_node_on_the_kilted_wheels(built_wheel: Path, tmp_path: Path):
    """The Kilted library of the wheel, built against Kilted's rmw, on the Kilted wheels of
    `make bootstrap DISTRO=kilted` (taken out of the wheel: the venv has this checkout installed)."""
    if "kilted" not in wheel_distros():
        pytest.skip(f"no Kilted venv at {KILTED_VENV} (`make bootstrap DISTRO=kilted`): the wheel was built for Jazzy only")
    library = tmp_path / "librmw_introspect_cpp.so"
    with zipfile.ZipFile(built_wheel) as archive:
        library.write_bytes(archive.read(PREBUILT.replace("jazzy", "kilted")))
    (tmp_path / "talker.py").write_text(TALKER)
    env = {k: v for k, v in os.environ.items() if not k.startswith(("RMW_INTROSPECT", "_ROS_WHEELS", "AMENT_"))}
    env.update(RMW_INTROSPECT_LIBRARY=str(library), RMW_INTROSPECT_CACHE=str(tmp_path / "cache"))
    result = subprocess.run([str(KILTED_VENV / "bin" / "rmw-introspect"), "capture", "--format", "json", "--script", "talker.py"],
                            cwd=tmp_path, env=env, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert [pub["name"] for pub in json.loads(result.stdout)["/talker"]["publishers"]] == ["/chatter"]
