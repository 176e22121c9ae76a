"""How the kind of ROS 2 install is detected and how the middleware is activated in each."""

from __future__ import annotations

import importlib.metadata
import sys
from pathlib import Path

import pytest

from pytest_rmw_introspect.errors import SetupError
from pytest_rmw_introspect.run import ros_env

PYVER = f"python{sys.version_info.major}.{sys.version_info.minor}"


def make_wheels_prefix(root: Path) -> Path:
    (root / "lib").mkdir(parents=True)
    (root / "lib" / "librmw_fastrtps_cpp.so").write_bytes(b"")
    site = root / "lib" / PYVER / "site-packages"
    (site / "ros_wheels_bootstrapper").mkdir(parents=True)
    (site / "ros_rcl.libs").mkdir()
    (site / "ros_fastrtps.libs").mkdir()
    return root


def make_system_prefix(root: Path) -> Path:
    (root / "lib").mkdir(parents=True)
    (root / "lib" / "librmw_implementation.so").write_bytes(b"")
    return root


@pytest.fixture(autouse=True)
def fresh_detection():
    ros_env.detect.cache_clear()
    yield
    ros_env.detect.cache_clear()


def test_wheels_venv_is_detected_with_its_library_dirs(tmp_path, monkeypatch):
    prefix = make_wheels_prefix(tmp_path / "venv")
    monkeypatch.setattr(sys, "prefix", str(prefix))
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    found = ros_env.detect()
    assert found.kind == ros_env.WHEELS
    assert found.prefix == prefix
    assert found.ament_prefixes == (prefix,)
    site = prefix / "lib" / PYVER / "site-packages"
    assert found.library_dirs == (prefix / "lib", (site / "ros_fastrtps.libs").resolve(), (site / "ros_rcl.libs").resolve())


def test_real_venv_of_this_suite_is_a_wheels_install_of_its_locked_distribution():
    found = ros_env.detect()
    if found.kind != ros_env.WHEELS:
        pytest.skip("the suite runs on a standard ROS install, not the PyPI wheels")
    # the venv's distribution as its ros-<distro>-rclpy meta-package says (jazzy in .venv,
    # kilted in .venv-kilted), found here without the code under test
    metas = [d.metadata["Name"].lower().replace("_", "-") for d in importlib.metadata.distributions()]
    distros = {name.split("-")[1] for name in metas if name.startswith("ros-") and name.endswith("-rclpy")
               and name.count("-") == 2}
    assert len(distros) == 1, distros
    assert found.distro == distros.pop()
    assert (found.prefix / "lib" / "librcl.so").exists()


def test_prefix_with_runtime_selection_is_a_system_install(tmp_path, monkeypatch):
    wheels_like = make_wheels_prefix(tmp_path / "venv")
    (wheels_like / "lib" / "librmw_implementation.so").write_bytes(b"")
    monkeypatch.setattr(sys, "prefix", str(wheels_like))
    monkeypatch.setenv("AMENT_PREFIX_PATH", str(wheels_like))
    monkeypatch.setenv("ROS_DISTRO", "jazzy")
    found = ros_env.detect()
    assert found.kind == ros_env.SYSTEM
    assert found.distro == "jazzy"


def test_no_ros_at_all_says_how_to_install_it(tmp_path, monkeypatch):
    monkeypatch.setattr(sys, "prefix", str(tmp_path))
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    with pytest.raises(SetupError) as info:
        ros_env.detect()
    message = str(info.value)
    assert "ROS 2 was not found" in message
    assert "pip install 'pytest-rmw-introspect[jazzy]'" in message and "ros-wheels" not in message
    assert "source /opt/ros/jazzy/setup.bash" in message


def test_wheels_activation_preloads_the_library_and_skips_the_bootstrap_reexec(tmp_path):
    prefix = make_wheels_prefix(tmp_path / "venv")
    ros = ros_env.RosEnvironment(ros_env.WHEELS, prefix, "jazzy", (prefix,), (prefix / "lib",))
    lib = tmp_path / "librmw_introspect_cpp.so"
    lib.write_bytes(b"")
    env = ros_env.activation_env(lib, ros, base={"LD_PRELOAD": "/other.so", "LD_LIBRARY_PATH": "/x"})
    assert env["LD_PRELOAD"] == f"{lib.resolve()} /other.so"
    assert env["LD_LIBRARY_PATH"].split(":") == [str(prefix / "lib"), "/x"]
    assert env["_ROS_WHEELS_BOOTSTRAP_COMPLETE"] == "1"
    # named too: a user's RMW_IMPLEMENTATION=rmw_fastrtps_cpp would make rcl refuse the preload
    assert env["RMW_IMPLEMENTATION"] == "rmw_introspect_cpp"


def test_sanitizer_runtimes_stay_first_and_the_library_follows(tmp_path):
    prefix = make_wheels_prefix(tmp_path / "venv")
    ros = ros_env.RosEnvironment(ros_env.WHEELS, prefix, "jazzy", (prefix,), (prefix / "lib",))
    lib = tmp_path / "librmw_introspect_cpp.so"
    lib.write_bytes(b"")
    base = {"LD_PRELOAD": "/opt/libfoo.so:/usr/lib/x86_64-linux-gnu/libasan.so.8"}
    env = ros_env.activation_env(lib, ros, base=base)
    assert env["LD_PRELOAD"].split() == ["/usr/lib/x86_64-linux-gnu/libasan.so.8", str(lib.resolve()),
                                         "/opt/libfoo.so"]


@pytest.mark.parametrize("kind", [ros_env.WHEELS, ros_env.SYSTEM])
def test_a_library_whose_path_holds_a_space_is_preloaded_by_name_from_its_directory(tmp_path, kind):
    """Issue 50, N16: the loader splits LD_PRELOAD at spaces (a venv in "My Projects" captured
    nothing); the library is named by its file name, found first in LD_LIBRARY_PATH."""
    prefix = make_wheels_prefix(tmp_path / "venv") if kind == ros_env.WHEELS else make_system_prefix(tmp_path / "opt")
    ros = ros_env.RosEnvironment(kind, prefix, "jazzy", (prefix,), (prefix / "lib",))
    lib = tmp_path / "My Projects" / "install" / "lib" / "librmw_introspect_cpp.so"
    lib.parent.mkdir(parents=True)
    lib.write_bytes(b"")
    env = ros_env.activation_env(lib, ros, base={"LD_PRELOAD": "/other.so", "LD_LIBRARY_PATH": "/x"})
    assert env["LD_PRELOAD"] == "librmw_introspect_cpp.so /other.so"
    assert ros_env.activation_env(lib, ros, base=env)["LD_PRELOAD"] == env["LD_PRELOAD"]  # activated twice: once
    assert env["LD_LIBRARY_PATH"].split(":")[0] == str(lib.parent.resolve())
    assert env["LD_LIBRARY_PATH"].split(":")[1:] == [str(prefix / "lib"), "/x"]


def test_a_library_in_a_directory_with_a_colon_cannot_be_preloaded_and_says_so(tmp_path):
    prefix = make_wheels_prefix(tmp_path / "venv")
    ros = ros_env.RosEnvironment(ros_env.WHEELS, prefix, "jazzy", (prefix,), (prefix / "lib",))
    lib = tmp_path / "a:b" / "librmw_introspect_cpp.so"
    lib.parent.mkdir()
    lib.write_bytes(b"")
    with pytest.raises(SetupError, match=r"a:b/librmw_introspect_cpp\.so cannot be preloaded: .* must not hold a colon"):
        ros_env.activation_env(lib, ros, base={})


def test_the_process_own_ament_prefixes_come_first(tmp_path):
    prefix = make_wheels_prefix(tmp_path / "venv")
    ros = ros_env.RosEnvironment(ros_env.WHEELS, prefix, "jazzy", (prefix,), (prefix / "lib",))
    lib = tmp_path / "librmw_introspect_cpp.so"
    lib.write_bytes(b"")
    env = ros_env.activation_env(lib, ros, base={"AMENT_PREFIX_PATH": f"/overlay:{prefix}"})
    assert env["AMENT_PREFIX_PATH"].split(":") == ["/overlay", str(prefix)]


def test_system_activation_selects_by_name_and_adds_the_install_prefix(tmp_path):
    underlay = make_system_prefix(tmp_path / "opt")
    install = tmp_path / "install"
    (install / "lib").mkdir(parents=True)
    lib = install / "lib" / "librmw_introspect_cpp.so"
    lib.write_bytes(b"")
    ros = ros_env.RosEnvironment(ros_env.SYSTEM, underlay, "jazzy", (underlay,), (underlay / "lib",))
    env = ros_env.activation_env(lib, ros, base={})
    assert env["RMW_IMPLEMENTATION"] == "rmw_introspect_cpp"
    assert env["AMENT_PREFIX_PATH"].split(":") == [str(install.resolve()), str(underlay)]
    assert env["LD_LIBRARY_PATH"].split(":")[0] == str(install.resolve() / "lib")
    # preloaded as well: virtual time needs the library's rcutils clocks to win over librcutils'
    assert env["LD_PRELOAD"].split()[0] == str(lib.resolve())


def test_the_wheels_distro_is_read_from_the_meta_packages_dist_info(tmp_path, monkeypatch):
    prefix = make_wheels_prefix(tmp_path / "venv")
    site = prefix / "lib" / PYVER / "site-packages"
    (site / "ros_rclpy-9.0.0.dist-info").mkdir()  # the real wheel: no distro in its name
    (site / "ros_kilted_rclpy-9.0.0.dist-info").mkdir()
    monkeypatch.setattr(sys, "prefix", str(prefix))
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    assert ros_env.detect().distro == "kilted"


# ---------------------------------------------------------------- the overlay over the wheels
def test_a_runtime_selection_prefix_ahead_of_the_venv_is_a_system_install_over_the_wheels(tmp_path, monkeypatch):
    venv = make_wheels_prefix(tmp_path / "venv")
    overlay = make_system_prefix(tmp_path / "overlay")
    monkeypatch.setattr(sys, "prefix", str(venv))
    monkeypatch.setenv("AMENT_PREFIX_PATH", f"{overlay}:{venv}")
    found = ros_env.detect()
    assert found.kind == ros_env.SYSTEM
    assert found.prefix == overlay
    assert found.wheels_underlay
    assert found.ament_prefixes == (overlay, venv)
    site = venv / "lib" / PYVER / "site-packages"
    # the overlay's relinked librcl must be found before the wheels' own
    assert found.library_dirs == (overlay / "lib", venv / "lib", (site / "ros_fastrtps.libs").resolve(),
                                  (site / "ros_rcl.libs").resolve())


@pytest.mark.parametrize("order", ["venv first", "venv not named"])
def test_runtime_selection_that_is_not_ahead_of_the_venv_leaves_the_wheels_kind(tmp_path, monkeypatch, order):
    # the interpreter's rclpy is then the wheels' own, linked to Fast DDS: only the preload works
    venv = make_wheels_prefix(tmp_path / "venv")
    other = make_system_prefix(tmp_path / "opt")
    monkeypatch.setattr(sys, "prefix", str(venv))
    monkeypatch.setenv("AMENT_PREFIX_PATH", f"{venv}:{other}" if order == "venv first" else str(other))
    found = ros_env.detect()
    assert found.kind == ros_env.WHEELS
    assert found.prefix == venv


def test_activation_over_the_wheels_keeps_the_library_order_from_the_bootstrapper(tmp_path):
    venv = make_wheels_prefix(tmp_path / "venv")
    overlay = make_system_prefix(tmp_path / "overlay")
    lib = tmp_path / "install" / "lib" / "librmw_introspect_cpp.so"
    lib.parent.mkdir(parents=True)
    lib.write_bytes(b"")
    ros = ros_env.RosEnvironment(ros_env.SYSTEM, overlay, "jazzy", (overlay, venv), (overlay / "lib", venv / "lib"),
                                 wheels_underlay=True)
    env = ros_env.activation_env(lib, ros, base={})
    assert env["_ROS_WHEELS_BOOTSTRAP_COMPLETE"] == "1"
    assert env["LD_LIBRARY_PATH"].split(":") == [str(lib.parent.resolve()), str(overlay / "lib"), str(venv / "lib")]
    assert env["AMENT_PREFIX_PATH"].split(":") == [str(lib.parent.parent.resolve()), str(overlay), str(venv)]
    plain = ros_env.RosEnvironment(ros_env.SYSTEM, overlay, "jazzy", (overlay,), (overlay / "lib",))
    assert "_ROS_WHEELS_BOOTSTRAP_COMPLETE" not in ros_env.activation_env(lib, plain, base={})
