"""``rmw-introspect capture``: run one target (or, with a launch file, a system) on the recording
middleware and print what it created, as a contract, NoDL or JSON (``formats``). Imports only
what running a target needs, so a capture starts without loading the comparison pipeline."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..errors import TargetError, UsageError
from ..run import runner
from ..run.target import TargetSpec
from . import formats, launch_options
from .parser import EXIT_OK, ONE_CAPTURE_STARTS_COLD, target_from_args
from .ros_setup import Setup


def cmd_capture(args: argparse.Namespace, command: list[str] | None) -> int:
    if launch_options.wants_launch(args):
        from . import system_contracts  # the system pipeline and launch readers: only for a launch file

        setup_ = Setup()
        return system_contracts.cmd_capture(args, command, setup_.ros, setup_.library)
    launch_options.launch_block(args)  # launch options without a launch file are a usage error
    cwd = Path.cwd()
    target = target_from_args(args, command)
    spec = TargetSpec.from_mapping(target, base_dir=cwd, source="command line")
    if spec.kind is None:
        raise UsageError("no target: give --package P --executable E, --script FILE, --module M, "
                         "--entry-point MOD:FUNC or -- COMMAND ARGS...")
    setup = Setup()
    include = bool(args.include_infrastructure or args.raw)
    try:
        cap = runner.run(spec, library=setup.library(), ros=setup.ros(), include_infrastructure=include,
                         cold_note=ONE_CAPTURE_STARTS_COLD)
    except TargetError as exc:
        partial = getattr(exc, "partial", None)
        if not args.partial or partial is None:
            raise
        reason = str(exc).splitlines()[0]
        formats.emit(formats.capture_text(partial, args, spec, cwd, partial_reason=reason), args.output)
        raise
    for note in cap.notes():
        print(f"note: {note}", file=sys.stderr)
    formats.emit(formats.capture_text(cap, args, spec, cwd), args.output)
    return EXIT_OK
