"""The C++ and launch overlay (``make overlay``) as the overlay tier's tests use it: where it is,
the environment of a process that runs on it, and the C++ example package built over it.

The tier runs only where an overlay built for this venv's ROS 2 wheels is in the cache (a
developer's machine after ``make overlay``, and so CI on it); elsewhere its tests are skipped
with one line saying how to build it.
"""

from __future__ import annotations

import hashlib
import importlib.util
import json
import os
import shutil
import signal
import subprocess
import sys
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING

from source_trees import tree_hash

if TYPE_CHECKING:
    import argparse

REPO = Path(__file__).resolve().parents[2]
CPP_EXAMPLES = REPO / "examples" / "rmw_introspect_examples_cpp"
BUILD_HINT = ("no C++ overlay for this venv in the cache: build it with "
              "`ROS_OVERLAY_SRC=<dir with the upstream checkouts> make overlay` "
              "(docs/overlay.md)")


@lru_cache(maxsize=1)
def builder() -> ModuleType:
    """scripts/overlay/build.py, whose ``overlay_env`` and ``cache_root`` are the reference."""
    spec = importlib.util.spec_from_file_location("overlay_build", REPO / "scripts" / "overlay" / "build.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@dataclass(frozen=True)
class Overlay:
    root: Path  # overlay-<distro>-<key>/
    install: Path  # its ament prefix
    info: dict

    def env(self, extra: dict[str, str] | None = None) -> dict[str, str]:
        """The environment of a process over the overlay (as ``. install/setup.sh`` makes it),
        with nothing of the middleware's or of a test's own activation left in it."""
        base = {k: v for k, v in os.environ.items()
                if not k.startswith("RMW_INTROSPECT_") and k not in {"LD_PRELOAD", "RMW_IMPLEMENTATION"}}
        env = builder().overlay_env(self.install, Path(sys.prefix), base=base)
        env["PYTHONUNBUFFERED"] = "1"
        env.update(extra or {})
        return env


def find_overlay() -> Overlay | None:
    """The newest complete overlay in the cache built for this venv's ROS 2 wheels and its Python,
    if any. (The wheels' names are the same for every Python, so an overlay built for the 3.11 venv
    was found for the 3.12 one, whose interpreter cannot import its rclpy: its rcl then refused the
    middleware, and the tier failed instead of saying there is no overlay for this venv.)"""
    root = builder().find_built(Path(sys.prefix))
    if root is None:
        return None
    info = json.loads((root / "overlay.json").read_text())
    if f"/python{sys.version_info.major}.{sys.version_info.minor}/" not in str(info.get("python_path", "")) + "/":
        return None
    return Overlay(root, Path(info["prefix"]), info)


def cmake_build(overlay: Overlay, src: Path, name: str, *args: str) -> Path:
    """``src`` configured, built and installed over ``overlay`` into the cache (keyed by its
    sources and the overlay; built once); returns the directory that holds build/ and install/."""
    from filelock import FileLock

    # the contracts are read from the sources, never from the install: a new one needs no rebuild
    sources = tree_hash(src, exclude=("contracts",)) + tree_hash(REPO / "examples" / "rmw_introspect_examples" / "cmake")
    dest = overlay.root.parent / f"{name}-{hashlib.sha256((sources + str(overlay.root)).encode()).hexdigest()[:16]}"
    stamp = dest / "complete"
    with FileLock(str(dest) + ".lock"):
        if stamp.exists():
            return dest
        # an unfinished build (an interrupted run, perhaps of another clone: CMake refuses a build tree
        # configured from another source directory) starts again
        shutil.rmtree(dest / "build", ignore_errors=True)
        log = dest / "build.log"
        dest.mkdir(parents=True, exist_ok=True)
        with log.open("w") as out:
            for cmd in (
                ["cmake", "-S", str(src), "-B", str(dest / "build"), f"-DCMAKE_INSTALL_PREFIX={dest / 'install'}",
                 "-DCMAKE_BUILD_TYPE=Release", "-DBUILD_TESTING=OFF", f"-DPython3_EXECUTABLE={sys.executable}", *args],
                ["nice", "-n", "10", "cmake", "--build", str(dest / "build"), "-j", "2"],
                ["cmake", "--install", str(dest / "build")],
            ):
                out.write("$ " + " ".join(cmd) + "\n")
                out.flush()
                if subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT, env=overlay.env()).returncode != 0:
                    tail = "\n".join(log.read_text(errors="replace").splitlines()[-40:])
                    raise RuntimeError(f"building {src} over {overlay.install} failed (log {log}):\n{tail}")
        stamp.write_text("built\n")
    return dest


def build_middleware(overlay: Overlay) -> Path:
    """The middleware library a capture over ``overlay`` runs on (the cache keys it by the
    overlay's prefix, so it is a build of its own), built before any test captures: a first
    capture would otherwise build it inside its own timeout (minutes on 2 cores after a change
    of the middleware's sources)."""
    code = "from pytest_rmw_introspect.run import middleware; print(middleware.ensure_library())"
    built = subprocess.run([sys.executable, "-c", code], env=overlay.env(), capture_output=True, text=True,
                           timeout=1800, check=False)
    assert built.returncode == 0, f"building the middleware over the overlay failed:\n{built.stderr}"
    return Path(built.stdout.strip().splitlines()[-1])


def build_cpp_examples(overlay: Overlay) -> Path:
    """The install prefix of rmw_introspect_examples_cpp built over ``overlay``."""
    return cmake_build(overlay, CPP_EXAMPLES, "examples-cpp") / "install"


def with_prefix(env: dict[str, str], prefix: Path) -> dict[str, str]:
    """``env`` with ``prefix`` sourced on top (an installed package: `package:` + `executable:` find it)."""
    env = dict(env)
    env["AMENT_PREFIX_PATH"] = f"{prefix}:{env['AMENT_PREFIX_PATH']}"
    env["LD_LIBRARY_PATH"] = f"{prefix / 'lib'}:{env['LD_LIBRARY_PATH']}"
    return env


def start_bench(name: str, doc: str | None, reps: int) -> tuple[argparse.Namespace, Overlay, Path] | None:
    """The start of a bench script over the overlay: its options (``--reps``), the overlay and the
    C++ examples' prefix built over it; None (after saying so) without an overlay. The script is
    run again in the overlay's environment with the examples sourced on top, where the plugin
    activates the middleware as on a standard install: this returns only in that second run."""
    import argparse

    parser = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--reps", type=int, default=reps)
    args = parser.parse_args()
    overlay = find_overlay()
    if overlay is None:
        print(f"{name}: skipped: {BUILD_HINT}")
        return None
    examples = build_cpp_examples(overlay)
    marker = "RMWI_BENCH_IN_OVERLAY"
    if os.environ.get(marker) != "1":
        os.execve(sys.executable, [sys.executable, *sys.orig_argv[1:]],
                  with_prefix(overlay.env({marker: "1"}), examples))
    return args, overlay, examples


def build_c_node(overlay: Overlay) -> Path:
    """The middleware tests' rcl C node (tests/middleware/c_node) built over ``overlay``: it
    links librcl by name, so the overlay's (relinked to rmw_implementation) is the one it runs."""
    import sysconfig

    dest = cmake_build(overlay, REPO / "tests" / "middleware" / "c_node", "c_node-overlay",
                       f"-DCMAKE_PREFIX_PATH={overlay.install};{sys.prefix}",
                       f"-DPYTHON_LIBDIR={sysconfig.get_config_var('LIBDIR')}",
                       f"-DPYTHON_LIBRARY_NAME=python{sysconfig.get_config_var('LDVERSION')}")
    return dest / "build" / "rmwi_c_node"


def stop(processes: list[subprocess.Popen], grace: float = 15.0) -> None:
    """SIGINT to each process group, as Ctrl-C does; SIGKILL to what is left after ``grace``
    seconds (a loaded machine; a C++ listener once spun for an hour after its SIGINT)."""
    for process in processes:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGINT)
    for process in processes:
        try:
            process.communicate(timeout=grace)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.communicate()
