"""`make dist`: the sdist and the wheels of pytest-rmw-introspect, into dist/.

1. the sdist and the platform-independent wheel (``python -m build``): the Python package with
   the middleware's sources, which it builds on first use (any platform, any install);
2. the Linux x86_64 wheel: the same files plus ``pytest_rmw_introspect/prebuilt/<distro>/
   librmw_introspect_cpp.so`` for every ROS 2 distribution asked for (default jazzy and kilted),
   each built from the bundled sources against the rmw of that distribution's PyPI wheels (the
   venv of ``make bootstrap DISTRO=<distro>``; its build cache is reused). The RPATH the build
   gave it (the build venv's lib/) is replaced by ``$ORIGIN/../../../../..``: the lib/ of the venv
   the wheel is installed into, where that distribution's wheels put librmw. Then
   ``auditwheel repair`` checks it and gives the wheel its manylinux tag: the oldest glibc (and
   libstdc++) the library's own symbol versions allow. Every library the ROS wheels provide is
   excluded from the repair, so the wheel bundles none of them (the check at the end fails the
   build if it did).

Usage: python scripts/dist.py [--out DIR] [--distros jazzy,kilted]
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
LIBRARY = "librmw_introspect_cpp.so"
#: where the wheel's library sits: <venv>/lib/pythonX.Y/site-packages/pytest_rmw_introspect/prebuilt/<distro>/
RPATH_TO_VENV_LIB = "$ORIGIN/../../../../.."
#: the libraries of the system every manylinux policy allows (never bundled, never excluded by name)
SYSTEM_LIBRARIES = re.compile(r"^(libc|libm|libdl|libpthread|librt|libstdc\+\+|libgcc_s|ld-linux-x86-64)\.so")


def say(line: str) -> None:
    print(f"dist: {line}", flush=True)


def run(cmd: list[str], **kwargs) -> subprocess.CompletedProcess[str]:
    say("$ " + " ".join(cmd))
    return subprocess.run(cmd, check=True, text=True, **kwargs)


def venv_dir(distro: str) -> Path:
    """The venv of ``make bootstrap DISTRO=<distro>``: Python 3.11's, else 3.12's (.ci/run makes
    Kilted's on 3.12; the library does not depend on the Python), else where 3.11's would be."""
    base = ".venv" if distro == "jazzy" else f".venv-{distro}"
    found = [ROOT / name for name in (base, f"{base}-py312") if (ROOT / name / "bin" / "python").is_file()]
    return found[0] if found else ROOT / base


def venv_python(distro: str) -> Path:
    return venv_dir(distro) / "bin" / "python"


def needed(library: Path) -> list[str]:
    """The DT_NEEDED entries of ``library`` (pyelftools, which auditwheel brings)."""
    from elftools.elf.dynamic import DynamicSection
    from elftools.elf.elffile import ELFFile

    with library.open("rb") as stream:
        for section in ELFFile(stream).iter_sections():
            if isinstance(section, DynamicSection):
                return [tag.needed for tag in section.iter_tags() if tag.entry.d_tag == "DT_NEEDED"]
    return []


def build_library(distro: str, python: Path, stage: Path) -> list[str]:
    """Build (or take from the cache) the library for ``distro`` with that distribution's venv,
    copy it to ``stage/prebuilt/<distro>/`` with the wheel's RPATH; return the ROS libraries it
    needs (every DT_NEEDED that is not the system's)."""
    if not python.is_file():
        sys.exit(f"dist: no venv for ROS 2 {distro} at {python.parent.parent}: run `make bootstrap DISTRO={distro}` first "
                 f"(or leave {distro} out: --distros)")
    built = subprocess.run(["nice", "-n", "10", str(python), "-m", "pytest_rmw_introspect.run.middleware", "--source-build"],
                           check=True, text=True, stdout=subprocess.PIPE, cwd=ROOT).stdout.strip()
    target = stage / "pytest_rmw_introspect" / "prebuilt" / distro / LIBRARY
    target.parent.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(built, target)
    run(["patchelf", "--force-rpath", "--set-rpath", RPATH_TO_VENV_LIB, str(target)])
    ros = [name for name in needed(target) if not SYSTEM_LIBRARIES.match(name)]
    say(f"{distro}: {built} -> {target.relative_to(stage)}; needs from ROS: {', '.join(ros)}")
    return ros


def platform_wheel(pure: Path, stage: Path, out: Path, excludes: list[str]) -> Path:
    """The pure wheel with the staged libraries added, as a Linux wheel repaired by auditwheel."""
    with tempfile.TemporaryDirectory(dir=ROOT / "build") as scratch:
        work = Path(scratch)
        run([sys.executable, "-m", "wheel", "unpack", "--dest", str(work / "unpacked"), str(pure)])
        (tree,) = (work / "unpacked").iterdir()
        shutil.copytree(stage / "pytest_rmw_introspect", tree / "pytest_rmw_introspect", dirs_exist_ok=True)
        (info,) = tree.glob("*.dist-info")
        wheel_file = info / "WHEEL"
        text = wheel_file.read_text()
        text = text.replace("Root-Is-Purelib: true", "Root-Is-Purelib: false")
        text = re.sub(r"^Tag: .*$", "Tag: py3-none-linux_x86_64", text, flags=re.M)
        wheel_file.write_text(text)
        (work / "linux").mkdir()
        run([sys.executable, "-m", "wheel", "pack", "--dest-dir", str(work / "linux"), str(tree)])
        (linux,) = (work / "linux").glob("*.whl")
        exclude_args = [arg for name in excludes for arg in ("--exclude", name)]
        before = set(out.glob("*manylinux*.whl"))
        run([sys.executable, "-m", "auditwheel", "repair", "--wheel-dir", str(out), *exclude_args, str(linux)])
        (repaired,) = set(out.glob("*manylinux*.whl")) - before
    return repaired


def check_bundles_nothing_of_ros(wheel: Path, distros: list[str]) -> None:
    """The wheel's shared libraries are exactly the prebuilt middleware's (no ``.libs`` directory
    of grafted libraries), and each keeps the RPATH to the venv's lib/."""
    with zipfile.ZipFile(wheel) as archive:
        libraries = sorted(n for n in archive.namelist() if ".so" in Path(n).name)
    expected = sorted(f"pytest_rmw_introspect/prebuilt/{d}/{LIBRARY}" for d in distros)
    if libraries != expected:
        sys.exit(f"dist: {wheel.name} holds the shared libraries {libraries}, expected only {expected}")
    say(f"{wheel.name}: shared libraries {', '.join(libraries)} (nothing of ROS bundled)")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ROOT / "dist")
    parser.add_argument("--distros", default="jazzy,kilted", help="comma-separated ROS 2 distributions to prebuild for")
    args = parser.parse_args()
    distros = [d for d in args.distros.split(",") if d]
    out: Path = args.out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    for old in out.glob("pytest_rmw_introspect-*"):
        old.unlink()
    (ROOT / "build").mkdir(exist_ok=True)
    stage = ROOT / "build" / "dist-stage"
    shutil.rmtree(stage, ignore_errors=True)

    # the sdist and the platform-independent wheel, with the locked build backend (no download)
    run([sys.executable, "-m", "build", "--no-isolation", "--sdist", "--wheel", "--outdir", str(out), str(ROOT)],
        stdout=subprocess.DEVNULL)
    (pure,) = out.glob("pytest_rmw_introspect-*-py3-none-any.whl")

    excludes: set[str] = set()
    for distro in distros:
        excludes.update(build_library(distro, venv_python(distro), stage))
    repaired = platform_wheel(pure, stage, out, sorted(excludes))
    check_bundles_nothing_of_ros(repaired, distros)
    for made in sorted(out.glob("pytest_rmw_introspect-*")):
        say(f"wrote {made.relative_to(ROOT) if made.is_relative_to(ROOT) else made}")
    return 0


if __name__ == "__main__":
    os.environ.setdefault("SOURCE_DATE_EPOCH", "1700000000")  # reproducible archive times
    # the venv's tools (patchelf, which auditwheel calls too) ahead of the system's
    os.environ["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}"
    raise SystemExit(main())
