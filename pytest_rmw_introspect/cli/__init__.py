"""The ``rmw-introspect`` command line: capture, check, diff, compat, graph, init, validate, lock,
install-launch.

A module per command declares its subparser (``add_parser``) beside the ``cmd_*`` it runs, and
imports what that command runs inside it (building the parser loads every command module).
One line per module (:func:`main` here is the console script):

- ``parser``: the program's parser, built from the command modules (``COMMANDS``)
- ``capture``: ``capture``: one target (or a launch file's processes), printed or written
- ``check``: ``check``: each contract's target run and compared with it (``--update`` writes it)
- ``diff``: ``diff``: two contract files compared, or every contract with a git revision
- ``gate``: ``diff --against REF``: every contract against its version at a git revision
- ``compat``: ``compat``: do the nodes of several contracts fit together
- ``graph``: ``graph``: the nodes of contracts drawn, and what does not fit
- ``init``: ``init --package P``: contract testing started on a package
- ``validate``: ``validate``: contract files checked without running anything
- ``lock``: ``lock``: the package's type-hash lockfile
- ``contracts``: ``contracts``: the contract files under a directory, found by content
- ``install_launch``: ``install-launch``: ROS 2's launch packages into the venv, for Python launch files
- ``arguments``: the option groups several commands share, and the readers of their values
- ``option_flags``: the flags of the option tables (``model.option_tables``)
- ``exit_status``: the exit statuses
- ``formats``: what the commands print or write (contract, JSON, NoDL, raw; ``--summary``)
- ``emit``: the one writer of a report command's outcome in each ``--format`` (text, json, markdown, github, sarif)
- ``recordings``: ``check --bag``: the options that go with a recording, and the recording read once
- ``system_contracts``: system contracts on the command line (``capture --launch``, ``*.system.yaml``)
- ``launch_options``: the launch-file options, declared and read without the system pipeline
- ``live_options``: ``--live`` and ``--parameter-timeout``, declared without the live check
- ``live``: ``check --live`` and ``capture --live``: the running graph read once and compared
- ``baselines``: ``--baseline`` and ``--write-baseline``
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
from ..model import tally
from .capture import ONE_CAPTURE_STARTS_COLD
from .exit_status import EXIT_ERROR, EXIT_INTERRUPTED, EXIT_TERMINATED
from .parser import build_parser

#: the commands that run a target given as ``-- COMMAND ARGS...``
TAKE_A_COMMAND = ("capture", "check")


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
    if command is not None and args.command not in TAKE_A_COMMAND:
        print(f"rmw-introspect: error: `-- COMMAND` is only for capture and check, not {args.command}",
              file=sys.stderr)
        return EXIT_ERROR
    tally.note("command", args.command)  # the test suite's exercised set (model.tally; issue 48)
    if getattr(args, "format", None):
        tally.note("format", f"{args.command} {args.format}")
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGTERM, _raise_terminated)
    if args.command == "validate":  # only the contract loader: fast enough for a pre-commit hook
        try:
            return int(args.handler(args))
        except KeyboardInterrupt:
            return EXIT_INTERRUPTED
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
    from .system_contracts import checks_as_system

    return checks_as_system(Path(contracts[0]), args)


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
        return EXIT_INTERRUPTED
    except Terminated:
        print("rmw-introspect: terminated", file=sys.stderr)
        return EXIT_TERMINATED


def _run_command(args: argparse.Namespace, command: list[str] | None) -> int:
    """The chosen command's ``cmd_*`` (``args.handler``, set by its ``add_parser``)."""
    if args.command in TAKE_A_COMMAND:
        return int(args.handler(args, command))
    return int(args.handler(args))


__all__ = ["main"]
