"""The ``rmw-introspect`` command line: capture, check, diff, compat.

One line per module (:func:`main` here is the console script):

- ``parser``: arguments and help texts
- ``option_flags``: the flags of the option tables (``model.option_tables``)
- ``commands``: ``check``, ``diff``, ``compat``, ``graph`` over the check pipeline
- ``gate``: ``diff --against REF``: every contract against its version at a git revision
- ``capture``: ``capture``: one target (or a launch file's processes), printed or written
- ``formats``: what ``capture`` prints or writes (contract, JSON, NoDL, raw)
- ``system_contracts``: system contracts on the command line (``capture --launch``, ``*.system.yaml``)
- ``system_options``: the command-line options of system contracts
- ``launch_options``: what the command line says of a launch file, without the system pipeline
- ``baselines``: ``--baseline`` and ``--write-baseline``
- ``init``: ``init --package P``: contract testing started on a package
- ``validate``: ``validate``: contract files checked without running anything
- ``lock``: ``lock``: the package's type-hash lockfile
- ``ros_setup``: the ROS environment and middleware library, found on first use
"""

from __future__ import annotations

import argparse
import signal
import sys
import threading
from collections.abc import Sequence
from pathlib import Path
from types import FrameType

from ..errors import RmwIntrospectError, Terminated
from .parser import EXIT_ERROR, ONE_CAPTURE_STARTS_COLD, build_parser

EXIT_TERMINATED = 128 + signal.SIGTERM


def _raise_terminated(signum: int, frame: FrameType | None) -> None:
    raise Terminated()


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``rmw-introspect`` console script; returns the exit status."""
    argv = list(sys.argv[1:] if argv is None else argv)
    command: list[str] | None = None
    if "--" in argv:
        i = argv.index("--")
        argv, command = argv[:i], argv[i + 1:]
        if not command:
            print("rmw-introspect: error: `--` must be followed by the command to run", file=sys.stderr)
            return EXIT_ERROR
    parser = build_parser()
    args = parser.parse_args(argv)
    if command is not None and args.command not in ("capture", "check"):
        print(f"rmw-introspect: error: `-- COMMAND` is only for capture and check, not {args.command}",
              file=sys.stderr)
        return EXIT_ERROR
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGTERM, _raise_terminated)
    if args.command == "validate":  # only the contract loader: fast enough for a pre-commit hook
        from .validate import cmd_validate

        try:
            return cmd_validate(args)
        except KeyboardInterrupt:
            return 130
    # Each command imports what it needs once the arguments are valid (`--help` and usage errors
    # answer in a fraction of the time); `capture` never loads the comparison pipeline
    # (deepdiff, jsonschema, ...) nor, without a launch file, the system pipeline, nor the warm
    # start client: its one target starts cold (cli.capture).
    if args.command == "capture":
        return _run_reporting_errors(args, command)
    from ..run.warm import client as warm

    if not _several_captures(args):
        # a warm start server pays for itself from the second capture of a run on
        warm.POOL.disable(ONE_CAPTURE_STARTS_COLD)
    try:
        return _run_reporting_errors(args, command)
    finally:
        warm.shutdown()  # the servers end with the run, whatever way it ends


def _several_captures(args: argparse.Namespace) -> bool:
    """Whether this run may capture more than one target: several contract files, or a system
    contract (one capture per process its launch file starts: counting its files alone, a
    150-process system started every process cold, 5x slower than ``capture --launch``)."""
    contracts = list(getattr(args, "contracts", ()))
    if len(contracts) != 1:
        return len(contracts) > 1
    from .system_contracts import is_system

    return is_system(Path(contracts[0]), args)


def _run_reporting_errors(args: argparse.Namespace, command: list[str] | None) -> int:
    """Run the command; a problem the user can fix (an RmwIntrospectError), an interrupt or SIGTERM
    becomes a message and an exit status. Anything else is a bug of this tool: its traceback shows."""
    try:
        return _run_command(args, command)
    except RmwIntrospectError as exc:
        print(f"rmw-introspect: {exc}", file=sys.stderr)
        return EXIT_ERROR
    except KeyboardInterrupt:
        print("rmw-introspect: interrupted", file=sys.stderr)
        return 130
    except Terminated:
        print("rmw-introspect: terminated", file=sys.stderr)
        return EXIT_TERMINATED


def _run_command(args: argparse.Namespace, command: list[str] | None) -> int:
    if args.command == "capture":
        from .capture import cmd_capture

        return cmd_capture(args, command)
    if args.command == "init":
        from .init import cmd_init

        return cmd_init(args)
    if args.command == "lock":
        from .lock import cmd_lock

        return cmd_lock(args)
    from . import commands, gate

    if args.command == "check":
        return commands.cmd_check(args, command)
    if args.command == "diff":
        return gate.cmd_gate(args) if args.against is not None else commands.cmd_diff(args)
    if args.command == "graph":
        return commands.cmd_graph(args)
    return commands.cmd_compat(args)


__all__ = ["main"]
