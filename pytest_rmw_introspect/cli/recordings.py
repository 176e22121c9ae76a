"""``check --bag PATH``: the command line's side of checking contracts against a recording
(``check.recording_check``): which other options go with it, and the recording read once."""

from __future__ import annotations

import argparse

from ..check.recording_check import BagCheck
from ..errors import UsageError
from .arguments import compare_from_args, target_from_args
from .launch_options import launch_arguments, wants_launch


def start(args: argparse.Namespace, command: list[str] | None) -> BagCheck:
    """The recording of ``--bag``, read (raises RecordingError), with the comparison options given
    here; a usage error for what cannot go with it (nothing runs, nothing is written)."""
    if args.update:
        raise UsageError("--bag checks a recording and writes nothing: leave out --update (accept drift on "
                         "purpose with `accept:` entries in the contract, or --write-baseline FILE)")
    if args.shard:
        raise UsageError("--bag with --shard: a recording is checked against every contract at once (a topic is "
                         "undeclared only if no contract declares it); leave out --shard")
    if target_from_args(args, command) or wants_launch(args) or launch_arguments(args):
        raise UsageError("--bag checks a recording: nothing runs, so target and launch options (and -- COMMAND) "
                         "cannot be given with it")
    return BagCheck.read(args.bag, [(compare_from_args(args), "command line")])
