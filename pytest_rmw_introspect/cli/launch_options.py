"""What the command line says about a launch file (``--launch``, ``--launch-package``/``--launch-file``,
``--launch-arg``, ``--allow-unsupported``): read by ``capture`` and ``check`` before they decide
whether a system is involved, so without importing the system pipeline."""

from __future__ import annotations

import argparse
from typing import Any

from ..errors import UsageError


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
