"""Provide ``librmw_introspect_cpp.so``: an installed one, a prebuilt one, or the bundled sources
built once.

Order of preference:

1. ``RMW_INTROSPECT_LIBRARY``: an explicit path to the library (for people who build it
   themselves, e.g. with sanitizers);
2. an installed ``rmw_introspect_cpp`` package in the ament prefixes (colcon workspace, apt);
3. the library prebuilt for the ROS distribution of the PyPI wheels, shipped in the Linux x86_64
   wheel of this package (``prebuilt/<distro>/``, put there by ``make dist``: built against that
   distribution's rmw, whose ABI does not change within a distribution);
4. the sources shipped with this Python package, built with CMake into a cache directory
   keyed by the sources' hash, the ROS distribution and the ROS prefix. A file lock makes
   concurrent pytest-xdist workers build it once; the others wait and reuse it. The build says
   on the terminal why it runs, how far it got and where its log is (``run.progress``), and so
   does a process that waits for another's build.
"""

from __future__ import annotations

import hashlib
import os
import re
import select
import shutil
import stat
import struct
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

from ..errors import LockTimeout, SetupError
from ..model import ament_index
from . import locks, progress, ros_env
from .cache import cache_root
from .process import process_state

LIBRARY_FILE = "librmw_introspect_cpp.so"
#: seconds one step of the build (configure, build, install) may take: a cold build takes 1-5
#: minutes on a loaded 2-core machine
BUILD_STEP_TIMEOUT = 1800.0
#: seconds a process waits for another that is building the same library (the build lock); a
#: stopped or hung builder then makes it fail with that builder's pid and state instead of waiting
BUILD_LOCK_TIMEOUT = BUILD_STEP_TIMEOUT + 60.0
_PACKAGE_DIR = Path(__file__).resolve().parent.parent  # the pytest_rmw_introspect package
#: the libraries of the Linux x86_64 wheel, one directory per ROS distribution (``make dist``)
PREBUILT_DIR = _PACKAGE_DIR / "prebuilt"
_BUILD_LOG_TAIL = 40
#: what a build takes, as the build's first line says (measured, docs/install.md)
BUILD_TIME = "45-61 s on 2 idle cores, minutes on a loaded machine"
#: seconds between two lines of a build's progress
PROGRESS_EVERY = 5.0
#: seconds on another process's build lock before the user is told why nothing happens
WAIT_NOTICE_AFTER = 1.0
_PERCENT = re.compile(r"^\[\s*(\d+)%\]")


@dataclass(frozen=True)
class MiddlewareLibrary:
    path: Path
    origin: str  # "environment", "installed", "prebuilt" or "built"


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
        marker = ament_index.resource(prefix, ros_env.MIDDLEWARE_NAME)
        library = prefix / "lib" / LIBRARY_FILE
        if marker.exists() and library.is_file():
            return library
    return None


def prebuilt_distros() -> list[str]:
    """The ROS distributions this installation carries a prebuilt library for."""
    try:
        return sorted(d.name for d in PREBUILT_DIR.iterdir() if (d / LIBRARY_FILE).is_file())
    except OSError:
        return []


def find_prebuilt(ros: ros_env.RosEnvironment) -> Path | None:
    """The prebuilt library for ``ros``: only for the PyPI wheels' kind of install, whose
    libraries are the ones it was built against (a standard install builds against its own)."""
    if ros.kind != ros_env.WHEELS:
        return None
    library = PREBUILT_DIR / ros.distro / LIBRARY_FILE
    return library if library.is_file() else None


def source_build_reason(ros: ros_env.RosEnvironment) -> str:
    """Why the middleware is built from source for ``ros`` (said when the build starts)."""
    if ros.kind != ros_env.WHEELS:
        return f"a standard ROS 2 install at {ros.prefix}: the middleware is built against its own rmw"
    shipped = prebuilt_distros()
    if not shipped:
        return ("no prebuilt middleware in this installation: a source checkout, an sdist or the "
                "platform-independent wheel (the Linux x86_64 wheel has one)")
    return f"the prebuilt middleware of this installation is for {', '.join(shipped)}, not {ros.distro}"


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


class _Progress:
    """A build's progress lines: the step it is at and, while compiling, CMake's last ``[NN%]``,
    every ``PROGRESS_EVERY`` seconds (also while a long compile prints nothing)."""

    def __init__(self, elapsed: Callable[[], float]) -> None:
        self.elapsed = elapsed
        self.throttle = progress.Throttle(PROGRESS_EVERY)
        self.percent: str | None = None

    def output(self, line: str) -> None:
        match = _PERCENT.match(line)
        if match:
            self.percent = match.group(1)

    def tick(self, what: str) -> None:
        if self.throttle.due():
            done = f" {self.percent}%" if what == "compile" and self.percent else ""
            progress.say(f"building the middleware: {what}{done}, {progress.seconds(self.elapsed())} so far")


def _run_logged(cmd: list[str], log: Path, env: dict[str, str], what: str, shown: _Progress | None = None) -> None:
    with log.open("ab") as out:
        out.write(("$ " + " ".join(cmd) + "\n").encode())
        out.flush()
        with subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, env=env) as proc:
            assert proc.stdout is not None
            if not _follow(proc.stdout.fileno(), out, what, shown, time.monotonic() + BUILD_STEP_TIMEOUT):
                proc.kill()
                proc.wait()
                raise SetupError(f"Building the recording middleware did not finish its {what} step within "
                                 f"{BUILD_STEP_TIMEOUT:g} s (BUILD_STEP_TIMEOUT) and was stopped. Full log: {log}")
        returncode = proc.wait()
    if returncode != 0:
        tail = "\n".join(log.read_text(errors="replace").splitlines()[-_BUILD_LOG_TAIL:])
        raise SetupError(
            f"Building the recording middleware failed at the {what} step "
            f"(exit status {returncode}). Full log: {log}\nLast lines:\n{tail}"
        )


def _follow(fd: int, out: BinaryIO, what: str, shown: _Progress | None, deadline: float) -> bool:
    """Copy a build step's output to its log until it ends, feeding ``shown`` its lines and a
    tick at least every second (a progress line is due every few seconds, output or not).
    False: the step's output was still open at ``deadline`` (time.monotonic)."""
    pending = b""
    while True:
        if time.monotonic() > deadline:
            return False
        readable, _, _ = select.select([fd], [], [], 1.0)
        if readable:
            chunk = os.read(fd, 65536)
            if not chunk:
                return True
            out.write(chunk)
            pending += chunk
            *lines, pending = pending.split(b"\n")
            if shown is not None:
                for line in lines:
                    shown.output(line.decode(errors="replace"))
        if shown is not None:
            shown.tick(what)


def build(src: Path, ros: ros_env.RosEnvironment, dest: Path, reason: str = "") -> Path:
    """Configure, build and install ``src`` into ``dest/install``; return the library path. Says
    on the terminal that it starts (and why: ``reason``), how far it got, and that it ended."""
    _require_tools()
    build_dir, install_dir, log = dest / "build", dest / "install", dest / "build.log"
    shutil.rmtree(build_dir, ignore_errors=True)
    dest.mkdir(parents=True, exist_ok=True)
    log.write_text("")
    why = f" ({reason})" if reason else ""
    with progress.step(
        f"building the recording middleware for ROS 2 {ros.distro}{why}; once per source version, "
        f"usually {BUILD_TIME}; log: {log}",
        "built the recording middleware in {time}",
        "building the recording middleware failed",
    ) as elapsed:
        library = _configure_build_install(src, ros, build_dir, install_dir, log, _Progress(elapsed))
    shutil.rmtree(build_dir, ignore_errors=True)
    return library


def _configure_build_install(src: Path, ros: ros_env.RosEnvironment, build_dir: Path, install_dir: Path,
                             log: Path, shown: _Progress) -> Path:
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
        log, env, "CMake configure", shown,
    )
    _run_logged(["cmake", "--build", str(build_dir), "-j", str(os.cpu_count() or 2)], log, env, "compile", shown)
    _run_logged(["cmake", "--install", str(build_dir)], log, env, "install", shown)
    library = install_dir / "lib" / LIBRARY_FILE
    if not library.is_file():
        raise SetupError(f"The middleware build finished but {library} is missing. Full log: {log}")
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
    """The middleware library to run targets on and where it came from, building it if need be;
    a library that is not a whole ELF shared object is a SetupError (:func:`check_library`)."""
    found = _resolve_library(ros, cache_dir)
    check_library(found)
    return found


#: the ELF header fields read (64-bit and 32-bit layouts): e_type, then e_phoff, e_shoff, and
#: e_phentsize, e_phnum, e_shentsize, e_shnum
_ELF_HEADER = {1: ("H10xI I 6xHHHH", 16), 2: ("H14xQ Q 6xHHHH", 16)}
_ET_DYN = 3


def library_damage(path: Path) -> str | None:
    """Why the file at ``path`` is no whole ELF shared object (the loader would skip it and every
    target would run on another middleware: rcl's exit status 102, or a SIGBUS for a truncated
    one), or None. Reads its first 64 bytes."""
    try:
        size = path.stat().st_size
        with path.open("rb") as f:
            head = f.read(64)
    except OSError as exc:
        return f"it cannot be read ({exc.strerror or exc})"
    if len(head) < 52 or head[:4] != b"\x7fELF" or head[4] not in _ELF_HEADER or head[5] not in (1, 2):
        return f"it is not an ELF shared library ({size} bytes that do not start like one)"
    layout, offset = _ELF_HEADER[head[4]]
    try:
        e_type, phoff, shoff, phentsize, phnum, shentsize, shnum = struct.unpack_from(
            ("<" if head[5] == 1 else ">") + layout, head, offset)
    except struct.error:
        return f"it is truncated ({size} bytes, not even a whole ELF header)"
    if e_type != _ET_DYN:
        return "it is an ELF file but not a shared library"
    needed = max(phoff + phentsize * phnum, shoff + shentsize * shnum)
    if needed > size:
        return f"it is truncated ({size} bytes; its ELF headers describe at least {needed})"
    return None


def check_library(found: MiddlewareLibrary) -> None:
    """Raise a SetupError that names a damaged library (:func:`library_damage`) and says what
    to do: delete a cached build (the next run builds it again), fix the others' source."""
    damage = library_damage(found.path)
    if damage is None:
        return
    if found.origin == "built":
        entry = found.path.parent.parent.parent
        advice = f"Delete its cache directory {entry} (rm -r) and run again: the middleware is built anew."
    elif found.origin == "environment":
        advice = "Point RMW_INTROSPECT_LIBRARY at a whole build of it, or unset the variable."
    else:
        advice = "Reinstall the package it comes from, or point RMW_INTROSPECT_LIBRARY at a built library."
    raise SetupError(f"The recording middleware library {found.path} ({found.origin}) is damaged: {damage}. {advice}")


def _resolve_library(ros: ros_env.RosEnvironment | None, cache_dir: Path | None) -> MiddlewareLibrary:
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
    prebuilt = find_prebuilt(ros)
    if prebuilt is not None:
        return MiddlewareLibrary(prebuilt, "prebuilt")
    return MiddlewareLibrary(source_build(ros, cache_dir, source_build_reason(ros)), "built")


def cache_entry(ros: ros_env.RosEnvironment, cache_dir: Path | None = None) -> Path:
    """The cache directory of the build for ``ros`` of the bundled sources as they are now (its
    lock ``<entry>.lock`` and, while a process holds it, ``<entry>.lock.pid`` beside it)."""
    root = Path(cache_dir) if cache_dir else cache_root()
    key = hashlib.sha256(f"{sources_hash(source_dir(), memo_dir=root)}|{ros.distro}|{ros.prefix}".encode()).hexdigest()[:16]
    return root / f"{ros.distro}-{key}"


def source_build(ros: ros_env.RosEnvironment, cache_dir: Path | None = None, reason: str = "") -> Path:
    """The library built from the bundled sources for ``ros`` in the cache, building it (or
    waiting for another process that builds it) if need be."""
    src = source_dir()
    dest = cache_entry(ros, cache_dir)
    root = dest.parent
    library = dest / "install" / "lib" / LIBRARY_FILE
    stamp = dest / "complete"
    if stamp.exists() and library.is_file():  # built already: no lock needed to read it
        return library
    try:
        root.mkdir(parents=True, exist_ok=True)
        with _build_lock(root / f"{dest.name}.lock", dest, ros):
            if not (stamp.exists() and library.is_file()):
                build(src, ros, dest, reason)
                stamp.write_text(str(library) + "\n")
    except OSError as exc:  # a read-only cache, a cache path that is a file (issue 50, N28)
        raise SetupError(
            f"The recording middleware must be built, but its cache directory {root} cannot be written: "
            f"{_unwritable(root, exc)}. Point RMW_INTROSPECT_CACHE at a writable directory (or make {root} "
            "one), or point RMW_INTROSPECT_LIBRARY at a built librmw_introspect_cpp.so.") from None
    return library


def _unwritable(root: Path, exc: OSError) -> str:
    """Why the cache directory ``root`` cannot be written, from the error that said so."""
    for place in (root, *root.parents):
        if place.exists() and not place.is_dir():
            return f"{place} is a file, not a directory"
    where = f" ({exc.filename})" if exc.filename else ""
    return f"{exc.strerror or exc}{where}"


@contextmanager
def _build_lock(path: Path, dest: Path, ros: ros_env.RosEnvironment) -> Iterator[None]:
    """Hold the build lock of ``dest`` (its holder's info: the run it belongs to,
    ``progress.scope``). Waiting for it (another process builds) says so after
    ``WAIT_NOTICE_AFTER`` seconds, with the builder's log, unless the builder is a worker of
    this same run (it tells the user itself); workers of one run say it once."""

    @contextmanager
    def waiting(builder: locks.Holder) -> Iterator[None]:
        scope = None if builder.info in ("", "-") else builder.info
        told = scope is None or scope != progress.scope()
        if told:
            pid = "unknown" if builder.pid is None else builder.pid
            progress.say_once(f"wait-{dest.name}", f"waiting for another process (pid {pid}) that builds the "
                              f"recording middleware for ROS 2 {ros.distro}; its log: {dest / 'build.log'}")
        began = time.monotonic()
        yield
        if told:
            progress.say_once(f"waited-{dest.name}", "the other process's middleware build ended after "
                              f"{progress.seconds(time.monotonic() - began)} of waiting")

    try:
        with locks.held(path, BUILD_LOCK_TIMEOUT, info=progress.scope() or "-", waiting=waiting,
                        notice_after=WAIT_NOTICE_AFTER):
            yield
    except LockTimeout as exc:  # only taking the lock times out: the build takes none
        pid = "unknown" if exc.pid is None else exc.pid
        state = "unknown" if exc.pid is None else process_state(exc.pid)
        raise SetupError(
            f"Another process (pid {pid}, {state}) has been building the recording middleware for over "
            f"{BUILD_LOCK_TIMEOUT:g} s and holds its build lock {path}. If that process is stopped or hung, "
            "end it (kill <pid>); one that ended releases the lock by itself. Or point "
            "RMW_INTROSPECT_LIBRARY at a built library.") from None


def main(argv: list[str] | None = None) -> int:
    """``python -m pytest_rmw_introspect.run.middleware [--source-build]``: find the library
    (``--source-build``: the one built from the bundled sources, as ``make dist`` ships it),
    building it if need be; print its path."""
    args = sys.argv[1:] if argv is None else argv
    try:
        if args == ["--source-build"]:
            print(source_build(ros_env.detect(), reason="requested with --source-build"))
            return 0
        found = resolve_library()
    except SetupError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(found.path)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
