"""``rmw-introspect install-launch``: ROS 2's Python launch packages into this Python environment.

The ROS 2 PyPI wheels have no ``launch``, ``launch_xml``, ``launch_yaml`` or ``launch_ros`` (and
the PyPI project named ``launch`` is an unrelated one), so a Python launch file (``.launch.py``),
which only ``launch`` can read, cannot be read with the wheels alone. Those four packages are
pure Python: this command runs one ``pip install`` of them from the branch of the ROS 2
distribution of the wheels (``git+https://github.com/ros2/launch.git@jazzy``, ...), or from local
checkouts (``--from DIR``), with ``--no-deps``, plus ``osrf-pycommon`` and ``lark`` from PyPI
when they are missing. Their data files (the ament index markers, launch's ``grammar.lark``)
land in the venv's ``share/``, which is an ament prefix already. ``composition_interfaces``,
which launch_ros imports and which is a CMake-built message package with no wheel, is not
installed: reading a launch file only builds LoadNode requests, and
``launch.composition_stand_in`` supplies them where the package is missing.
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path
from typing import Any

from ..errors import SetupError
from .exit_status import EXIT_OK

#: (package, repository, directory inside it): the packages this command installs
PACKAGES = (
    ("launch", "https://github.com/ros2/launch.git", "launch"),
    ("launch_xml", "https://github.com/ros2/launch.git", "launch_xml"),
    ("launch_yaml", "https://github.com/ros2/launch.git", "launch_yaml"),
    ("launch_ros", "https://github.com/ros2/launch_ros.git", "launch_ros"),
)
#: (module, PyPI requirement): what they import that the ROS 2 wheels may not bring (the versions
#: of requirements/overlay.txt, the lock the overlay tier installs and tests them with)
HELPERS = (("osrf_pycommon", "osrf-pycommon==2.0.2"), ("lark", "lark==1.3.1"))

#: the one command, as the error of a Python launch file without launch names it
COMMAND = "rmw-introspect install-launch"

EPILOG = """\
Runs one `pip install --no-deps` of ROS 2's launch, launch_xml, launch_yaml and launch_ros from
the branch of the distribution of this venv's ROS 2 wheels (jazzy, kilted: needs git and access
to github.com), or from local checkouts with --from DIR (DIR holds a clone of ros2/launch as
DIR/launch and one of ros2/launch_ros as DIR/launch_ros, the layout docs/overlay.md uses), plus
osrf-pycommon and lark from PyPI when they are missing. Then Python launch files (.launch.py)
work like XML and YAML ones: `rmw-introspect capture --launch robot.launch.py -o robot.system.yaml`.
Not needed with a sourced ROS 2 install (it has launch). docs/install.md says more.
"""


def add_parser(sub: Any) -> None:
    """Declare ``install-launch`` (``sub``: the subparsers of ``rmw-introspect``)."""
    cmd = sub.add_parser("install-launch", help="install ROS 2's launch packages, for Python launch files",
                         description="Install ROS 2's launch, launch_xml, launch_yaml and launch_ros into this "
                                     "Python environment (the PyPI wheels lack them), for .launch.py files.",
                         epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    cmd.add_argument("--distro", metavar="NAME",
                     help="the branch to install (default: the distribution of this venv's ROS 2 wheels)")
    cmd.add_argument("--from", dest="source", metavar="DIR", type=Path,
                     help="install from local checkouts: DIR/launch (ros2/launch) and DIR/launch_ros (ros2/launch_ros)")
    cmd.add_argument("--target", metavar="DIR", type=Path,
                     help="install into DIR instead of this environment (then put DIR on PYTHONPATH and "
                          "AMENT_PREFIX_PATH)")
    cmd.add_argument("--dry-run", action="store_true", help="print the pip command, run nothing")
    cmd.set_defaults(handler=cmd_install_launch)


def sources(distro: str | None, checkouts: Path | None) -> list[str]:
    """What pip installs for the four packages: directories of ``checkouts``, else git URLs of
    the ``distro`` branch (raises SetupError)."""
    if checkouts is None:
        if not distro or not re.fullmatch(r"[a-z]+", distro):
            raise SetupError("install-launch: cannot tell which ROS 2 distribution to install launch for "
                             f"({distro or 'no ROS 2 wheels found here'}): give --distro jazzy (or kilted), "
                             "or --from DIR with local checkouts")
        return [f"{name} @ git+{url}@{distro}#subdirectory={directory}" for name, url, directory in PACKAGES]
    found, missing = [], []
    for name, url, directory in PACKAGES:
        repository = url.rsplit("/", 1)[1].removesuffix(".git")
        candidates = [checkouts / repository / directory, checkouts / directory]
        here = next((c for c in candidates if (c / "setup.py").is_file()), None)
        if here is None:
            missing.append(f"{name} (looked for {' and '.join(str(c / 'setup.py') for c in candidates)}; "
                           f"`git clone -b {distro or 'jazzy'} {url} {checkouts / repository}`)")
        else:
            found.append(str(here.resolve()))
    if missing:
        raise SetupError(f"install-launch --from {checkouts}: missing " + "; ".join(missing))
    return found


def pip_command(distro: str | None, checkouts: Path | None, target: Path | None,
                python: str = sys.executable) -> list[str]:
    """The one ``pip install`` this command runs."""
    helpers = [requirement for module, requirement in HELPERS if importlib.util.find_spec(module) is None]
    options = ["--no-deps"]  # their install_requires name `launch` and `ament_index_python`: other PyPI projects
    if importlib.util.find_spec("setuptools") is not None:
        options.append("--no-build-isolation")  # plain setup.py packages: no setuptools download
    if target is not None:
        options += ["--target", str(target)]
    return [python, "-m", "pip", "install", *options, *helpers, *sources(distro, checkouts)]


def _distro() -> str | None:
    from ..run import ros_env  # noqa: PLC0415 - only this command asks

    try:
        return ros_env.detect().distro
    except SetupError:
        return os.environ.get("ROS_DISTRO") or None


def cmd_install_launch(args: argparse.Namespace) -> int:
    distro = args.distro or (None if args.source is not None else _distro())
    command = pip_command(distro, args.source, args.target)
    print(shlex.join(command), flush=True)
    if args.dry_run:
        return EXIT_OK
    done = subprocess.run(command, check=False)
    if done.returncode != 0:
        raise SetupError(f"install-launch: pip failed (exit status {done.returncode}); its output is above")
    env = dict(os.environ)
    if args.target is not None:
        for variable in ("PYTHONPATH", "AMENT_PREFIX_PATH"):
            env[variable] = os.pathsep.join(filter(None, [str(args.target.resolve()), env.get(variable)]))
    check = subprocess.run([sys.executable, "-c", "from pytest_rmw_introspect.launch import python_file; "
                            "python_file.modules()"], env=env, capture_output=True, text=True, check=False)
    if check.returncode != 0:
        raise SetupError("install-launch: installed, but launch_ros still cannot be imported: "
                         f"{(check.stderr.strip().splitlines() or ['?'])[-1]}")
    print("rmw-introspect: launch, launch_xml, launch_yaml and launch_ros are installed: Python launch files "
          "can be read (rmw-introspect capture --launch robot.launch.py -o robot.system.yaml)")
    return EXIT_OK
