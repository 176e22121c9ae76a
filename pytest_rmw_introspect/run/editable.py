"""ament_python packages installed editable (``pip install -e .``) made into ament prefixes as
colcon's ``--symlink-install`` would install them.

An editable install has no ``share/`` and no ament index marker (``model.editable_installs``),
so ``ros2 launch``, ``$(find-pkg-share)`` and ``--launch-package`` cannot find the package. For
every editable install on the Python path whose source tree holds a ``package.xml`` (an ament
package) and that no other prefix provides, :func:`prefixes` makes an ament prefix of symbolic
links into the source tree: each file of the ``data_files`` that setup.py / setup.cfg /
pyproject.toml declare (read through setuptools itself, in a subprocess, without building
anything) is linked at its install path, and the package's index marker is always there. Where
the ``data_files`` cannot be read or install nothing into ``share/<pkg>``, ``share/<pkg>`` links
to the source tree itself (a package's ``launch/``, ``config/`` and ``package.xml`` usually sit
there under the same names). The prefix lives in the cache (``editable/<pkg>-<hash of the source
path>``) and is made again whenever the setup files, the package.xml or a directory the data
files come from changed (a file added to ``launch/`` is seen at the next run, as a symlink
install sees it).

``ros_env.ament_prefixes`` puts these prefixes after every other one, so a package built and
sourced (or installed for real) wins, and the targets get them in their ``AMENT_PREFIX_PATH``
(a node that calls ``get_package_share_directory`` finds its files too).
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import subprocess
import sys
from collections.abc import Iterable, Sequence
from pathlib import Path

from ..model import ament_index
from ..model.editable_installs import installs
from .cache import cache_root

#: the manifest of a prefix made here
MANIFEST = "editable.json"
#: setup files whose change makes the prefix again
_SETUP_FILES = ("setup.py", "setup.cfg", "pyproject.toml", "package.xml")

#: run in the source tree: the data_files setuptools reads from setup.py / setup.cfg / pyproject.toml
_READ_DATA_FILES = r"""
import json, os, runpy, sys
os.chdir(sys.argv[1]); sys.path.insert(0, sys.argv[1]); sys.argv = ['setup.py', '--name']
import setuptools
import distutils.core as core
core._setup_stop_after = 'config'
if os.path.isfile('setup.py'):
    runpy.run_path('setup.py', run_name='__main__')
else:
    setuptools.setup()
dist = core._setup_distribution
found = [[str(d), [str(f) for f in files]] for d, files in (dist.data_files or [])]
sys.__stdout__.write('\n@@data_files@@' + json.dumps(found) + '\n')
"""


def prefixes(known: Sequence[Path], path: Sequence[str] | None = None, cache: Path | None = None) -> list[Path]:
    """The symlink prefixes of the editable ament packages of ``path`` that none of the ``known``
    prefixes provides (made or refreshed in ``cache``, default the plugin's cache)."""
    made: list[Path] = []
    for editable in installs(path):
        package = editable.package
        if package is None or ament_index.providers(package, known):
            continue
        try:
            made.append(_prefix(package, editable.source, cache or cache_root()))
        except OSError:
            continue  # a cache that cannot be written: the package stays unresolved, as before
    return made


def _prefix(package: str, source: Path, cache: Path) -> Path:
    digest = hashlib.sha256(str(source.resolve()).encode()).hexdigest()[:16]
    prefix = cache / "editable" / f"{package}-{digest}"
    try:
        manifest = json.loads((prefix / MANIFEST).read_text())
    except (OSError, ValueError):
        manifest = None
    if isinstance(manifest, dict) and manifest.get("key") == _key(source, manifest.get("directories", [])):
        return prefix
    data_files = _data_files(source)
    tmp = prefix.with_name(f"{prefix.name}.tmp-{os.getpid()}")
    shutil.rmtree(tmp, ignore_errors=True)
    directories = _link(package, source, data_files, tmp)
    (tmp / MANIFEST).write_text(json.dumps({
        "package": package, "source": str(source), "directories": directories,
        "how": "source tree" if (tmp / "share" / package).is_symlink() else "data_files",
        "key": _key(source, directories)}, indent=1) + "\n")
    shutil.rmtree(prefix, ignore_errors=True)
    try:
        os.rename(tmp, prefix)
    except OSError:  # another process made it at the same moment: use theirs
        shutil.rmtree(tmp, ignore_errors=True)
    return prefix


def _key(source: Path, directories: Iterable[str]) -> str:
    stats = []
    for path in [*(source / name for name in _SETUP_FILES), *(source / d for d in directories)]:
        try:
            st = path.stat()
            stats.append(f"{path}:{st.st_mtime_ns}:{st.st_size}")
        except OSError:
            stats.append(f"{path}:-")
    return hashlib.sha256("\n".join(stats).encode()).hexdigest()


def _data_files(source: Path) -> list[tuple[str, list[str]]] | None:
    """The ``data_files`` setuptools reads from the source tree's setup files (None: unreadable)."""
    try:
        done = subprocess.run([sys.executable, "-c", _READ_DATA_FILES, str(source)], capture_output=True,
                              text=True, timeout=60, check=False, stdin=subprocess.DEVNULL)
    except (OSError, subprocess.TimeoutExpired):
        return None
    marker = done.stdout.rfind("@@data_files@@")
    if done.returncode != 0 or marker < 0:
        return None
    try:
        found = json.loads(done.stdout[marker + len("@@data_files@@"):].splitlines()[0])
    except (ValueError, IndexError):
        return None
    return [(str(d), [str(f) for f in files]) for d, files in found]


def _link(package: str, source: Path, data_files: list[tuple[str, list[str]]] | None, prefix: Path) -> list[str]:
    """Make the symlink prefix; returns the source directories its files came from."""
    marker = ament_index.resource(prefix, package)
    marker.parent.mkdir(parents=True)
    marker.touch()
    directories: list[str] = []
    for destination, files in data_files or []:
        if Path(destination).is_absolute():
            continue
        for name in files:
            file = (source / name).resolve()
            if not file.is_file():
                continue
            link = prefix / destination / file.name
            link.parent.mkdir(parents=True, exist_ok=True)
            if link.is_symlink() or link.exists():
                link.unlink()
            link.symlink_to(file)
            directory = os.path.relpath(file.parent, source.resolve())
            if directory not in directories:
                directories.append(directory)
    if not (prefix / "share" / package).exists():  # no data_files (or unreadable): the source tree is the share
        (prefix / "share").mkdir(exist_ok=True)
        (prefix / "share" / package).symlink_to(source.resolve(), target_is_directory=True)
        directories.append(".")
    return directories
