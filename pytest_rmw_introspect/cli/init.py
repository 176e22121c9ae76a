"""``rmw-introspect init --package P``: start contract testing on an existing package.

Captures every executable the package installs, writes one contract per executable into
``contracts/`` (never over an existing one unless ``--force``), reports the executables it
could not capture and why, and says how the contracts become tests in that kind of package.
"""

from __future__ import annotations

import argparse
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

from ..check import golden
from ..errors import RmwIntrospectError
from ..run import runner
from ..run.target import TargetSpec, package_executables
from .parser import EXIT_ERROR, EXIT_OK, UsageError
from .ros_setup import Setup

_CMAKE_WIRING = """\
  if(BUILD_TESTING)
    find_package(pytest_rmw_introspect REQUIRED)
    rmw_introspect_add_contract_tests(DIRECTORY contracts)
  endif()"""


def _build_type(package_dir: Path) -> str | None:
    try:
        root = ET.parse(package_dir / "package.xml").getroot()
    except (OSError, ET.ParseError):
        return None
    build_type = root.find("export/build_type")
    return build_type.text.strip() if build_type is not None and build_type.text else None


def cmd_init(args: argparse.Namespace) -> int:
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
    written, kept, failed = [], [], []
    for executable in executables:
        path = contracts_dir / f"{executable}.interfaces.yaml"
        if path.exists() and not args.force:
            kept.append(path)
            continue
        spec = TargetSpec.from_mapping({"package": args.package, "executable": executable, **timing},
                                       source="rmw-introspect init")
        try:
            capture = runner.run(spec, library=setup.library(), ros=ros)
        except RmwIntrospectError as exc:
            failed.append((executable, str(exc).splitlines()[0]))
            continue
        text = golden.new_contract_text(capture.to_contract_nodes(), spec=spec, base=contracts_dir,
                                        how=f"rmw-introspect init --package {args.package}",
                                        distribution=capture.ros_distribution)
        golden.write_text(path, text)
        written.append(path)
        for note in capture.notes():
            print(f"note: {executable}: {note}", file=sys.stderr)

    for path in written:
        print(f"wrote {path}")
    for path in kept:
        print(f"kept  {path} (exists; --force overwrites it)")
    for executable, reason in failed:
        print(f"could not capture {args.package}/{executable}: {reason}", file=sys.stderr)
    print()
    build_type = _build_type(package_dir)
    if build_type == "ament_cmake":
        print("To run the contracts with `colcon test`, add to CMakeLists.txt:\n" + _CMAKE_WIRING)
    elif build_type == "ament_python":
        print("`colcon test` runs pytest in the package, which collects contracts/*.interfaces.yaml as tests.")
    else:
        print(f"Run the contracts with `pytest {contracts_dir}` (each *.interfaces.yaml is a test), or from CMake with:\n"
              + _CMAKE_WIRING)
    return EXIT_ERROR if failed else EXIT_OK
