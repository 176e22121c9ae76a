"""Which kind of ROS 2 install this is, and how the recording middleware is activated in it.

Two kinds are supported:

* ``wheels``: ROS 2 Jazzy installed from PyPI wheels into a virtual environment. The venv is
  the ROS prefix. ``librcl`` and rclpy name ``librmw_fastrtps_cpp.so`` directly (runtime
  selection through ``RMW_IMPLEMENTATION`` is compiled out), so the middleware can only take
  over through ``LD_PRELOAD``. Processes that are not the venv's Python (C nodes) need the
  venv's ``LD_LIBRARY_PATH`` set for them.
* ``system``: a standard install (``/opt/ros/jazzy`` or a sourced workspace) where
  ``librmw_implementation.so`` loads the middleware named by ``RMW_IMPLEMENTATION`` through the
  ament index. The wheels' venv under a prefix that adds that runtime selection (the C++ and
  launch overlay, ``make overlay``: ``AMENT_PREFIX_PATH=<overlay>:<venv>``) is one too: there rcl
  and rclpy come from the overlay, which links them to rmw_implementation.
"""

from __future__ import annotations

import functools
import os
import sys
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import SetupError
from ..model import ament_index
from . import editable

WHEELS = "wheels"
SYSTEM = "system"

MIDDLEWARE_NAME = "rmw_introspect_cpp"

INSTALL_HINT = (
    "Install ROS 2 Jazzy into this virtual environment with\n"
    "    pip install 'pytest-rmw-introspect[jazzy]'      # or [kilted] for ROS 2 Kilted\n"
    "or, on a machine with a standard ROS 2 install, source it first:\n"
    "    source /opt/ros/jazzy/setup.bash"
)


@dataclass(frozen=True)
class RosEnvironment:
    """The ROS 2 install the plugin runs against."""

    kind: str  # WHEELS or SYSTEM
    prefix: Path  # the venv (wheels) or the underlay prefix that holds rmw_implementation
    distro: str
    ament_prefixes: tuple[Path, ...] = field(default_factory=tuple)
    library_dirs: tuple[Path, ...] = field(default_factory=tuple)
    # a system install whose underlay is the wheels' venv (the overlay): its processes need the
    # venv's library dirs and must not let the wheels' bootstrapper reorder LD_LIBRARY_PATH
    wheels_underlay: bool = False

    def library_path(self, existing: str | None = None) -> str:
        """``LD_LIBRARY_PATH`` for a process of this install, ahead of ``existing``."""
        parts = [str(d) for d in self.library_dirs]
        if existing:
            parts += [p for p in existing.split(os.pathsep) if p and p not in parts]
        return os.pathsep.join(parts)


def ament_prefixes(extra: tuple[Path, ...] = ()) -> list[Path]:
    """The ament prefixes to search, in order: ``AMENT_PREFIX_PATH`` first, then ``extra``, then
    the symlink prefixes of ament_python packages installed editable (``run.editable``)."""
    seen: list[Path] = []
    for prefix in [*ament_index.env_prefixes(), *extra]:
        if prefix not in seen:
            seen.append(prefix)
    return [*seen, *(p for p in editable.prefixes(seen) if p not in seen)]


@functools.lru_cache(maxsize=8)
def _package_shares(prefixes: tuple[Path, ...]) -> dict[str, str]:
    found: dict[str, str] = {}  # package → share directory
    for prefix in prefixes:
        for name in ament_index.names(prefix):
            found.setdefault(name, str(prefix / "share" / name))
    return {share: package for package, share in found.items()}


def package_shares(prefixes: Sequence[Path]) -> dict[str, str]:
    """Share directory → package, for every package of the ament ``prefixes`` (the first prefix
    that has a package wins, as ``$(find-pkg-share)`` finds it)."""
    return _package_shares(tuple(Path(p) for p in prefixes))


def _wheels_distro(site: Path | None = None) -> str | None:
    """The distro of the ``ros-<distro>-rclpy`` meta-package installed here, if any: its
    ``ros_<distro>_rclpy-*.dist-info`` in ``site`` (a directory listing, not the ~10 ms scan of
    every installed distribution, which is the fallback)."""
    if site is not None:
        for info in sorted(site.glob("ros_*_rclpy-*.dist-info")):
            parts = info.name.split("-", 1)[0].split("_")
            if len(parts) == 3 and parts[1]:
                return parts[1]
    from importlib import metadata

    for dist in metadata.distributions():
        name = (dist.metadata["Name"] or "").lower().replace("_", "-")
        if name.startswith("ros-") and name.endswith("-rclpy") and name.count("-") == 2:
            return name.split("-")[1]
    return None


def _detect_wheels(prefix: Path) -> RosEnvironment | None:
    if not (prefix / "lib" / "librmw_fastrtps_cpp.so").exists():
        return None
    if (prefix / "lib" / "librmw_implementation.so").exists():
        return None  # a prefix with runtime selection is handled like a standard install
    site = prefix / "lib" / f"python{sys.version_info.major}.{sys.version_info.minor}" / "site-packages"
    if not (site / "ros_wheels_bootstrapper").exists():
        return None
    lib_dirs = [prefix / "lib", *sorted(p.resolve() for p in site.glob("ros_*.libs") if p.is_dir())]
    return RosEnvironment(
        kind=WHEELS,
        prefix=prefix,
        distro=_wheels_distro(site) or os.environ.get("ROS_DISTRO", "jazzy"),
        ament_prefixes=tuple(ament_prefixes((prefix,))),
        library_dirs=tuple(lib_dirs),
    )


def _selects_at_runtime(prefix: Path) -> bool:
    return (prefix / "lib" / "librmw_implementation.so").exists()


def _detect_overlay(venv: Path) -> RosEnvironment | None:
    """The wheels' venv with, ahead of it in ``AMENT_PREFIX_PATH``, a prefix that has runtime
    selection (``librmw_implementation.so``): a system install over the wheels."""
    wheels = _detect_wheels(venv)
    prefixes = ament_prefixes()
    if wheels is None or venv not in prefixes:
        return None
    ahead = prefixes[: prefixes.index(venv)]
    selecting = [p for p in ahead if _selects_at_runtime(p)]
    if not selecting:
        return None
    library_dirs: list[Path] = []
    for prefix in prefixes:
        library_dirs += wheels.library_dirs if prefix == venv else (prefix / "lib",)
    return RosEnvironment(
        kind=SYSTEM,
        prefix=selecting[0],
        distro=wheels.distro,
        ament_prefixes=tuple(prefixes),
        library_dirs=tuple(library_dirs),
        wheels_underlay=True,
    )


def _detect_system() -> RosEnvironment | None:
    prefixes = ament_prefixes()
    for prefix in prefixes:
        if _selects_at_runtime(prefix):
            distro = os.environ.get("ROS_DISTRO") or (prefix.name if prefix.parent == Path("/opt/ros") else "")
            return RosEnvironment(
                kind=SYSTEM,
                prefix=prefix,
                distro=distro or "unknown",
                ament_prefixes=tuple(prefixes),
                library_dirs=tuple(p / "lib" for p in prefixes),
            )
    return None


@functools.lru_cache(maxsize=None)
def detect() -> RosEnvironment:
    """Find the ROS 2 install for this interpreter, or raise :class:`SetupError` saying how to get one."""
    venv = Path(sys.prefix)
    found = _detect_overlay(venv) or _detect_wheels(venv) or _detect_system()
    if found is None:
        raise SetupError(
            "ROS 2 was not found: this Python environment has no ROS 2 Jazzy wheels "
            f"(no librmw_fastrtps_cpp.so under {sys.prefix}/lib) and no sourced ROS 2 install "
            "(no librmw_implementation.so under AMENT_PREFIX_PATH).\n" + INSTALL_HINT
        )
    return found


_SANITIZER_RUNTIMES = ("libasan", "libtsan", "libubsan", "liblsan", "libhwasan", "libclang_rt.")


def _is_sanitizer_runtime(path: str) -> bool:
    return os.path.basename(path).startswith(_SANITIZER_RUNTIMES)


def _preload_entry(library: Path) -> tuple[str, bool]:
    """What ``LD_PRELOAD`` names ``library`` by, and whether its directory must then come first
    in ``LD_LIBRARY_PATH``. The loader splits ``LD_PRELOAD`` at spaces and colons, with no way to
    quote them: a library whose path holds one (a venv in "~/My Projects") is named by its
    file name alone, which the loader looks up in ``LD_LIBRARY_PATH`` (split at colons only) like
    a needed library (issue 50, N16)."""
    if not any(c.isspace() or c == ":" for c in str(library)):
        return str(library), False
    if ":" in str(library.parent) or any(c.isspace() for c in library.name):
        raise SetupError(
            f"The recording middleware library {library} cannot be preloaded: the dynamic loader splits "
            "LD_PRELOAD at spaces and colons and LD_LIBRARY_PATH at colons, so its directory must not hold a "
            "colon. Point RMW_INTROSPECT_LIBRARY at a copy in a directory without one (or RMW_INTROSPECT_CACHE, "
            "for a library built in the cache).")
    return library.name, True


def activation_env(library: Path, ros: RosEnvironment, base: Mapping[str, str] | None = None) -> dict[str, str]:
    """Environment variables that make a process of ``ros`` run on the middleware ``library``.

    ``base`` is the environment the process would otherwise get (default: ``os.environ``);
    only the returned variables need to be set on top of it.
    """
    if base is None:
        base = os.environ
    library = Path(library).resolve()
    env: dict[str, str] = {}
    library_dirs = ros.library_path(base.get("LD_LIBRARY_PATH"))
    prefixes = [str(p) for p in ros.ament_prefixes]
    # The process's own AMENT_PREFIX_PATH (a target's `env:`, a sourced overlay) comes first.
    for prefix in reversed([str(p) for p in ament_index.env_prefixes(base)]):
        if prefix in prefixes:
            prefixes.remove(prefix)
        prefixes.insert(0, prefix)
    # Preloaded on both kinds of install: with the wheels it is the only way in; on a standard
    # install RMW_IMPLEMENTATION selects it too, but only a preloaded library's definitions of
    # rcutils_steady_time_now/rcutils_system_time_now replace librcutils' (virtual time).
    # Sanitizer runtimes must come first in LD_PRELOAD, so they stay ahead of the library.
    preloaded, library_first = _preload_entry(library)
    others = [p for p in base.get("LD_PRELOAD", "").replace(":", " ").split() if p not in (str(library), preloaded)]
    sanitizers = [p for p in others if _is_sanitizer_runtime(p)]
    rest = [p for p in others if p not in sanitizers]
    env["LD_PRELOAD"] = " ".join([*sanitizers, preloaded, *rest])
    # Set on both kinds: a user's RMW_IMPLEMENTATION=rmw_fastrtps_cpp would make rcl refuse the
    # preloaded middleware (RCL_RET_MISMATCHED_RMW_ID, exit 102) in the wheels setup.
    env["RMW_IMPLEMENTATION"] = MIDDLEWARE_NAME
    if ros.kind == WHEELS:
        env["LD_LIBRARY_PATH"] = os.pathsep.join([str(library.parent), library_dirs]) if library_first else library_dirs
        # The wheels' bootstrapper would re-exec the interpreter just to set LD_LIBRARY_PATH;
        # it is set already, so tell it to skip that (saves a whole interpreter start).
        env["_ROS_WHEELS_BOOTSTRAP_COMPLETE"] = "1"
    else:
        install_prefix = library.parent.parent
        env["LD_LIBRARY_PATH"] = os.pathsep.join([str(library.parent), library_dirs])
        if str(install_prefix) not in prefixes:
            prefixes.insert(0, str(install_prefix))
        if ros.wheels_underlay:
            env["_ROS_WHEELS_BOOTSTRAP_COMPLETE"] = "1"  # the order above must stay
    env["AMENT_PREFIX_PATH"] = os.pathsep.join(prefixes)
    return env
