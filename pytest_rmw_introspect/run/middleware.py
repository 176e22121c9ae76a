"""Provide ``librmw_introspect_cpp.so``: an installed one, or the bundled sources built once.

Order of preference:

1. ``RMW_INTROSPECT_LIBRARY``: an explicit path to the library (for people who build it
   themselves, e.g. with sanitizers);
2. an installed ``rmw_introspect_cpp`` package in the ament prefixes (colcon workspace, apt);
3. the sources shipped with this Python package, built with CMake into a cache directory
   keyed by the sources' hash, the ROS distribution and the ROS prefix. A file lock makes
   concurrent pytest-xdist workers build it once; the others wait and reuse it.
"""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import stat
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

from ..errors import SetupError
from . import locks, ros_env

LIBRARY_FILE = "librmw_introspect_cpp.so"
#: seconds one step of the build (configure, build, install) may take: a cold build takes 1-5
#: minutes on a loaded 2-core machine
BUILD_STEP_TIMEOUT = 1800.0
#: seconds a process waits for another that is building the same library (the build lock); a
#: stopped or hung builder then makes it fail with that builder's pid and state instead of waiting
BUILD_LOCK_TIMEOUT = BUILD_STEP_TIMEOUT + 60.0
_PACKAGE_DIR = Path(__file__).resolve().parent.parent  # the pytest_rmw_introspect package
_BUILD_LOG_TAIL = 40


@dataclass(frozen=True)
class MiddlewareLibrary:
    path: Path
    origin: str  # "environment", "installed" or "built"


def source_dir() -> Path:
    """The middleware's ament package: inside the installed Python package, or the repository's."""
    for candidate in (_PACKAGE_DIR / "rmw_introspect_cpp", _PACKAGE_DIR.parent / "rmw_introspect_cpp"):
        if (candidate / "package.xml").is_file() and (candidate / "CMakeLists.txt").is_file():
            return candidate
    raise SetupError(
        "The rmw_introspect_cpp sources are missing from this installation of pytest-rmw-introspect "
        f"(looked in {_PACKAGE_DIR / 'rmw_introspect_cpp'}). Reinstall the package, or point "
        "RMW_INTROSPECT_LIBRARY at a built librmw_introspect_cpp.so."
    )


def cache_root() -> Path:
    explicit = os.environ.get("RMW_INTROSPECT_CACHE")
    if explicit:
        return Path(explicit)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "pytest-rmw-introspect"


def _build_inputs(src: Path) -> list[tuple[Path, os.stat_result]]:
    """Every file of the package that affects the build (tests and docs excluded), sorted."""
    inputs = []
    for path in sorted(src.rglob("*")):
        rel = path.relative_to(src)
        if rel.parts[0] in {"test", "build"} or "__pycache__" in rel.parts:
            continue
        try:
            info = path.stat()
        except OSError:  # a dangling link: nothing a build reads
            continue
        if stat.S_ISREG(info.st_mode):
            inputs.append((rel, info))
    return inputs


def sources_hash(src: Path, memo_dir: Path | None = None) -> str:
    """Hash of the contents of every file of the package that affects the build. Reading and
    hashing them is most of the time a run needs to find its (already built) library, so the
    hash is remembered in ``memo_dir`` under the files' names, sizes and modification times:
    a file changed in any way a build could see changes those too."""
    inputs = _build_inputs(src)
    memo: Path | None = None
    if memo_dir is not None:
        listing = hashlib.sha256(str(src.resolve()).encode())
        for rel, info in inputs:
            listing.update(f"\0{rel}\0{info.st_size}\0{info.st_mtime_ns}\0{info.st_ino}".encode())
        memo = memo_dir / f"sources-{listing.hexdigest()[:32]}"
        try:
            remembered = memo.read_text(encoding="ascii").strip()
            if re.fullmatch(r"[0-9a-f]{64}", remembered):
                return remembered
        except (OSError, UnicodeDecodeError):
            pass
    digest = hashlib.sha256()
    for rel, _info in inputs:
        digest.update(str(rel).encode() + b"\0" + (src / rel).read_bytes() + b"\0")
    hexdigest = digest.hexdigest()
    if memo_dir is not None and memo is not None:
        try:  # a cache: a run that cannot write it only hashes again next time
            memo_dir.mkdir(parents=True, exist_ok=True)
            partial = memo.with_name(f"{memo.name}.{os.getpid()}.tmp")
            partial.write_text(hexdigest + "\n", encoding="ascii")
            os.replace(partial, memo)
        except OSError:
            pass
    return hexdigest


def find_installed(ros: ros_env.RosEnvironment) -> Path | None:
    for prefix in ros.ament_prefixes:
        marker = prefix / "share" / "ament_index" / "resource_index" / "packages" / ros_env.MIDDLEWARE_NAME
        library = prefix / "lib" / LIBRARY_FILE
        if marker.exists() and library.is_file():
            return library
    return None


def _require_tools() -> None:
    missing = []
    if shutil.which("cmake") is None:
        missing.append("CMake (apt-get install cmake, or pip install cmake)")
    if not any(shutil.which(cxx) for cxx in (os.environ.get("CXX", "c++"), "g++", "clang++")):
        missing.append("a C++17 compiler (apt-get install g++)")
    if shutil.which("make") is None and shutil.which("ninja") is None:
        missing.append("a build tool (apt-get install make)")
    if missing:
        raise SetupError(
            "Cannot build the recording middleware rmw_introspect_cpp: missing "
            + "; ".join(missing)
            + ". Install them, or point RMW_INTROSPECT_LIBRARY at a built librmw_introspect_cpp.so."
        )


def _run_logged(cmd: list[str], log: Path, env: dict[str, str], what: str) -> None:
    with log.open("a") as out:
        out.write("$ " + " ".join(cmd) + "\n")
        out.flush()
        try:
            result = subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT, env=env, timeout=BUILD_STEP_TIMEOUT)
        except subprocess.TimeoutExpired:
            raise SetupError(f"Building the recording middleware did not finish its {what} step within "
                             f"{BUILD_STEP_TIMEOUT:g} s (BUILD_STEP_TIMEOUT) and was stopped. Full log: {log}") from None
    if result.returncode != 0:
        tail = "\n".join(log.read_text(errors="replace").splitlines()[-_BUILD_LOG_TAIL:])
        raise SetupError(
            f"Building the recording middleware failed at the {what} step "
            f"(exit status {result.returncode}). Full log: {log}\nLast lines:\n{tail}"
        )


def build(src: Path, ros: ros_env.RosEnvironment, dest: Path) -> Path:
    """Configure, build and install ``src`` into ``dest/install``; return the library path."""
    _require_tools()
    build_dir, install_dir, log = dest / "build", dest / "install", dest / "build.log"
    shutil.rmtree(build_dir, ignore_errors=True)
    dest.mkdir(parents=True, exist_ok=True)
    log.write_text("")
    env = dict(os.environ)
    env["AMENT_PREFIX_PATH"] = os.pathsep.join(str(p) for p in ros.ament_prefixes)
    env["LD_LIBRARY_PATH"] = ros.library_path(env.get("LD_LIBRARY_PATH"))
    prefix_path = os.pathsep.join(str(p) for p in ros.ament_prefixes)
    _run_logged(
        [
            "cmake", "-S", str(src), "-B", str(build_dir),
            f"-DCMAKE_PREFIX_PATH={prefix_path}",
            f"-DCMAKE_INSTALL_PREFIX={install_dir}",
            "-DCMAKE_BUILD_TYPE=Release",
            "-DBUILD_TESTING=OFF",
        ],
        log, env, "CMake configure",
    )
    _run_logged(["cmake", "--build", str(build_dir), "-j", str(os.cpu_count() or 2)], log, env, "compile")
    _run_logged(["cmake", "--install", str(build_dir)], log, env, "install")
    library = install_dir / "lib" / LIBRARY_FILE
    if not library.is_file():
        raise SetupError(f"The middleware build finished but {library} is missing. Full log: {log}")
    shutil.rmtree(build_dir, ignore_errors=True)
    return library


#: ensure_library's answers in this process, by (RMW_INTROSPECT_LIBRARY, ROS install, cache directory)
_ensured: dict[tuple[str | None, ros_env.RosEnvironment | None, str], Path] = {}


def ensure_library(ros: ros_env.RosEnvironment | None = None, cache_dir: Path | None = None) -> Path:
    """Path of the middleware library to run targets on, building it if need be. Remembered for
    the rest of the process while the file is there, as ``ros_env.detect`` is: finding a built
    library hashes the listing of the middleware's ~600 source files (4-10 ms), which
    ``capture()`` without a ``library`` paid at every capture. A source edited while a process
    runs is built by the next process (a pytest session resolves the library once anyway)."""
    key = (os.environ.get("RMW_INTROSPECT_LIBRARY"), ros, str(cache_dir if cache_dir else cache_root()))
    known = _ensured.get(key)
    if known is not None and known.is_file():
        return known
    found = _ensured[key] = resolve_library(ros, cache_dir).path
    return found


def resolve_library(ros: ros_env.RosEnvironment | None = None, cache_dir: Path | None = None) -> MiddlewareLibrary:
    """The middleware library to run targets on and where it came from, building it if need be."""
    explicit = os.environ.get("RMW_INTROSPECT_LIBRARY")
    if explicit:
        path = Path(explicit)
        if not path.is_file():
            raise SetupError(f"RMW_INTROSPECT_LIBRARY points at {path}, which does not exist.")
        return MiddlewareLibrary(path.resolve(), "environment")
    ros = ros or ros_env.detect()
    installed = find_installed(ros)
    if installed is not None:
        return MiddlewareLibrary(installed, "installed")

    src = source_dir()
    root = Path(cache_dir) if cache_dir else cache_root()
    key = hashlib.sha256(
        f"{sources_hash(src, memo_dir=root)}|{ros.distro}|{ros.prefix}".encode()
    ).hexdigest()[:16]
    dest = root / f"{ros.distro}-{key}"
    library = dest / "install" / "lib" / LIBRARY_FILE
    stamp = dest / "complete"
    if stamp.exists() and library.is_file():  # built already: no lock needed to read it
        return MiddlewareLibrary(library, "built")
    root.mkdir(parents=True, exist_ok=True)
    try:
        with locks.held(root / f"{ros.distro}-{key}.lock", BUILD_LOCK_TIMEOUT):
            if not (stamp.exists() and library.is_file()):
                build(src, ros, dest)
                stamp.write_text(str(library) + "\n")
    except locks.LockTimeout as exc:
        raise SetupError(
            f"Another process has been building the recording middleware for over {exc.timeout:g} s and holds its "
            f"build lock {exc.path} ({exc.holder}). If that process is stopped or hung, end it (kill <pid>); one "
            "that ended releases the lock by itself. Or point RMW_INTROSPECT_LIBRARY at a built library."
        ) from None
    return MiddlewareLibrary(library, "built")


def main() -> int:
    """``python -m pytest_rmw_introspect.run.middleware``: build if need be, print the library path."""
    try:
        found = resolve_library()
    except SetupError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(found.path)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
