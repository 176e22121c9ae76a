"""``rmw-introspect init --package P``: start contract testing on an existing package.

Captures every executable the package installs, writes one contract per executable into
``contracts/`` (never over an existing one unless ``--force``), reports the executables it
could not capture and why, and says how the contracts become tests in that kind of package.
"""

from __future__ import annotations

import argparse
import os
import sys
import threading
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import RmwIntrospectError, UsageError
from ..model.option_tables import TARGET
from . import option_flags
from .exit_status import EXIT_ERROR, EXIT_OK

if TYPE_CHECKING:
    from ..model.capture import Capture
    from ..run.ros_env import RosEnvironment
    from .ros_setup import Setup

INIT_EPILOG = """\
Each executable is captured with default options (no parameters, remappings or namespace);
edit a contract's `target:` block and run `rmw-introspect check --update` on it for another
configuration. Executables that cannot be captured (they need arguments, hardware, a peer)
are listed with the reason and get no contract. Existing contracts are kept unless --force.

exit status: 0 every executable captured, 2 at least one could not be (or no executables).
"""


def add_parser(sub: Any) -> None:
    """Declare ``init`` (``sub``: the subparsers of ``rmw-introspect``)."""
    ini = sub.add_parser("init", help="write a contract for every executable of a package",
                         description="Capture every executable an installed package provides and write one "
                         "contract per executable into DIR/contracts/.", epilog=INIT_EPILOG,
                         formatter_class=argparse.RawDescriptionHelpFormatter)
    ini.add_argument("--package", required=True, metavar="P", help="the installed package (ament index, or a "
                     "Python distribution with console scripts)")
    ini.add_argument("--output-dir", default=".", metavar="DIR",
                     help="the package's source directory: contracts go to DIR/contracts (default: .)")
    ini.add_argument("--force", action="store_true", help="overwrite existing contracts")
    option_flags.add(ini, (TARGET[name] for name in ("settle", "timeout", "horizon")))
    ini.set_defaults(handler=cmd_init)


_CMAKE_WIRING = """\
  if(BUILD_TESTING)
    find_package(pytest_rmw_introspect REQUIRED)
    rmw_introspect_add_contract_tests(DIRECTORY contracts)
  endif()"""


#: the one story of contract files (docs/contract-files.md#one-file-every-check)
_SAME_FILES = ("The same files are checked by `rmw-introspect check`, the pull-request gate "
               "(`rmw-introspect diff --against REF`) and the GitHub action; a marker test may name one as its golden "
               "(@pytest.mark.interfaces(\"../contracts/<executable>.interfaces.yaml\")).")


def _build_type(package_dir: Path) -> str | None:
    import xml.etree.ElementTree as ET

    try:
        root = ET.parse(package_dir / "package.xml").getroot()
    except (OSError, ET.ParseError):
        return None
    build_type = root.find("export/build_type")
    return build_type.text.strip() if build_type is not None and build_type.text else None


def package_build_type(package: str, output_dir: Path, prefixes: Sequence[Path]) -> str | None:
    """The package's build type: from ``output_dir/package.xml`` (init run in the package's
    source), else the installed ``share/<package>/package.xml``, else ``ament_python`` for a
    Python distribution found only by its console scripts (``pip install -e .``)."""
    from ..model import ament_index

    installed = ament_index.providers(package, prefixes)
    for directory in (output_dir, *(prefix / "share" / package for prefix in installed[:1])):
        build_type = _build_type(directory)
        if build_type is not None:
            return build_type
    return None if installed else "ament_python"


def _capture_all(package: str, executables: list[str], timing: dict[str, float], setup: Setup,
                 ros: RosEnvironment) -> dict[str, Capture | RmwIntrospectError]:
    """Every executable captured, several at a time (one that hangs costs its timeout once, not
    once per executable after it): the capture or the error of each."""
    from concurrent.futures import ThreadPoolExecutor

    from ..run import runner
    from ..run.target import TargetSpec

    library = setup.library()
    cancel = threading.Event()

    def capture(executable: str) -> Capture | RmwIntrospectError:
        spec = TargetSpec.from_mapping({"package": package, "executable": executable, **timing},
                                       source="rmw-introspect init")
        try:
            return runner.run(spec, library=library, ros=ros, cancel=cancel)
        except RmwIntrospectError as exc:
            return exc

    pool = ThreadPoolExecutor(max_workers=max(1, min(len(executables), os.cpu_count() or 2)),
                              thread_name_prefix="rmw-introspect-init")
    try:
        futures = {executable: pool.submit(capture, executable) for executable in executables}
        return {executable: future.result() for executable, future in futures.items()}
    except BaseException:
        cancel.set()  # Ctrl-C: the running targets are stopped, the others never start
        raise
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def cmd_init(args: argparse.Namespace) -> int:
    from ..check import golden
    from ..run.executables import package_executables
    from ..run.target import TargetSpec
    from .ros_setup import Setup

    setup = Setup()
    ros = setup.ros()
    package_dir = Path(args.output_dir)
    contracts_dir = package_dir / "contracts"
    executables = package_executables(args.package, ros.ament_prefixes, sys.path)
    if not executables:
        raise UsageError(
            f"package {args.package!r} installs no executables that can be found: no lib/{args.package}/ in the "
            f"ament prefixes ({', '.join(map(str, ros.ament_prefixes)) or 'none'}) and no console scripts of a "
            "Python distribution of that name. Build and install (or `pip install -e`) the package first."
        )
    timing = {k: getattr(args, k) for k in ("settle", "timeout", "horizon") if getattr(args, k) is not None}
    kept = [contracts_dir / f"{e}.interfaces.yaml" for e in executables
            if (contracts_dir / f"{e}.interfaces.yaml").exists() and not args.force]
    to_capture = [e for e in executables if contracts_dir / f"{e}.interfaces.yaml" not in kept]
    written, failed = [], []
    for executable, result in _capture_all(args.package, to_capture, timing, setup, ros).items():
        if isinstance(result, RmwIntrospectError):
            failed.append((executable, str(result)))
            continue
        path = contracts_dir / f"{executable}.interfaces.yaml"
        spec = TargetSpec.from_mapping({"package": args.package, "executable": executable, **timing},
                                       source="rmw-introspect init")
        text = golden.new_contract_text(result.to_contract_nodes(), spec=spec, base=contracts_dir,
                                        how=f"rmw-introspect init --package {args.package}",
                                        distribution=result.ros_distribution)
        golden.write_text(path, text)
        written.append(path)
        for note in result.notes():
            print(f"note: {executable}: {note}", file=sys.stderr)

    for path in written:
        print(f"wrote {path}")
    for path in kept:
        print(f"kept  {path} (exists; --force overwrites it)")
    for executable, reason in failed:
        # the whole message: a crash's stderr tail says why
        first, _, rest = reason.partition("\n")
        print(f"could not capture {args.package}/{executable}: {first}", file=sys.stderr)
        if rest:
            print("\n".join("    " + line for line in rest.splitlines()), file=sys.stderr)
    print()
    build_type = package_build_type(args.package, package_dir, ros.ament_prefixes)
    if build_type == "ament_cmake":
        print("To run the contracts with `colcon test`, add to CMakeLists.txt:\n" + _CMAKE_WIRING)
    elif build_type == "ament_python":
        print(f"Run the contracts with `pytest {contracts_dir}` (each contract file is a test); in the package's "
              f"test/ directory `colcon test` runs them too. {_SAME_FILES}")
    else:
        print(f"Run the contracts with `pytest {contracts_dir}` (each contract file is a test); in an ament_cmake "
              "package, from CMake with:\n" + _CMAKE_WIRING)
    if build_type != "ament_python":
        print(_SAME_FILES)
    return EXIT_ERROR if failed else EXIT_OK
