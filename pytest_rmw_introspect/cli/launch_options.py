"""The launch-file options of ``capture`` and ``check`` (``--launch``, ``--launch-package``/``--launch-file``,
``--launch-arg``, ``--allow-unsupported``, ``--jobs``): declared for both, and read before they
decide whether a system is involved, so without importing the system pipeline."""

from __future__ import annotations

import argparse
from typing import Any

from ..errors import UsageError
from ..model.option_tables import TARGET, FrontEnd

LAUNCH_HELP = """\
a system (a launch file: every process it starts is captured, in parallel):
  --launch FILE                        an XML, YAML or Python launch file, or a record.json of dump_launch
  --launch-package P --launch-file F   a launch file of a package, found like `ros2 launch P F`
With a launch file, `capture` writes a system contract (NAME.system.yaml) and the target
options apply to every process ({flags} only).
""".format(flags=", ".join(option.flag if option.default is not True else f"--[no-]{option.flag[2:]}"
                           for option in TARGET.exposed(FrontEnd.SYSTEM)))


def add_launch(parser: argparse.ArgumentParser) -> None:
    """``--launch``, ``--launch-package``/``--launch-file``, ``--launch-arg``, ``--allow-unsupported``, ``--jobs``."""
    g = parser.add_argument_group("system (launch file)", LAUNCH_HELP)
    g.add_argument("--launch", metavar="FILE", help="launch file (XML, YAML, Python) or dump_launch record.json")
    g.add_argument("--launch-package", metavar="P", help="package of the launch file (with --launch-file)")
    g.add_argument("--launch-file", metavar="F", help="launch file name inside the package's share directory")
    g.add_argument("--launch-arg", action="append", metavar="NAME:=VALUE",
                   help="launch argument, as `ros2 launch ... NAME:=VALUE` (repeatable)")
    g.add_argument("--allow-unsupported", action="store_true", default=None,
                   help="capture what the launch reader supports and note the rest, instead of failing")
    g.add_argument("--jobs", type=int, metavar="N", help="processes captured at a time (default: the number of cores)")


def wants_launch(args: argparse.Namespace) -> bool:
    return bool(getattr(args, "launch", None) or getattr(args, "launch_package", None)
                or getattr(args, "launch_file", None))


def launch_arguments(args: argparse.Namespace) -> dict[str, str]:
    """``--launch-arg NAME:=VALUE`` options as a mapping."""
    arguments = {}
    for value in getattr(args, "launch_arg", None) or ():
        name, found, text = value.partition(":=")
        if not found or not name:
            raise UsageError(f"--launch-arg {value!r} is not of the form NAME:=VALUE")
        arguments[name] = text
    return arguments


def launch_block(args: argparse.Namespace) -> dict[str, Any] | None:
    """The ``launch:`` block the command line gives (None: none)."""
    if not wants_launch(args):
        if getattr(args, "launch_arg", None) or getattr(args, "allow_unsupported", None):
            raise UsageError("--launch-arg and --allow-unsupported need a launch file: --launch FILE or "
                             "--launch-package P --launch-file F (or, for `check`, a system contract)")
        return None
    block: dict[str, Any] = {}
    if args.launch:
        if args.launch_package or args.launch_file:
            raise UsageError("give --launch FILE or --launch-package P --launch-file F, not both")
        block["path"] = args.launch
    else:
        if not (args.launch_package and args.launch_file):
            raise UsageError("--launch-package and --launch-file go together")
        block.update(package=args.launch_package, file=args.launch_file)
    arguments = launch_arguments(args)
    if arguments:
        block["arguments"] = arguments
    if args.allow_unsupported:
        block["allow_unsupported"] = True
    return block
