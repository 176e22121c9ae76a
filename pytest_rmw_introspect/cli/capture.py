"""``rmw-introspect capture``: run one target (or, with a launch file, a system) on the recording
middleware and print what it created, as a contract, NoDL or JSON (``formats``). Imports only
what running a target needs, so a capture starts without loading the comparison pipeline (and,
without a launch file, the system pipeline)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from ..errors import TargetError, UsageError
from . import launch_options
from .arguments import add_target, target_from_args
from .exit_status import EXIT_OK
from .live_options import add_live

#: the start note of a command's only capture: a warm start server pays off from the second one
ONE_CAPTURE_STARTS_COLD = "a run with one capture starts it cold (a warm start server pays off from the second)"

CAPTURE_EPILOG = """\
formats:
  yaml  (default) a complete contract: contract_version, a `target:` block saying how the
        target was run (paths relative to the -o file, or to the current directory), and the
        `nodes:` block. Save it with -o NAME.interfaces.yaml and check it with
        `rmw-introspect check` or by running pytest next to it.
  json  the contract's `nodes` mapping as JSON.
  nodl  one NoDL v2 document per node (nodl_version: 2; parameters keyed by name with
        type, default_value, description, read_only, additional_constraints; publishers,
        subscriptions, service_servers, service_clients, action_servers, action_clients
        with name, type and qos for topics), as a YAML stream; a `# node: /fqn` comment
        names the node of each document (NoDL documents do not name their node), a
        `# lifecycle: STATE` comment a lifecycle node's state. `check` reads the file
        back as a contract, `check --update` rewrites it as NoDL.

parameters and lifecycle:
  every node's parameters are read through its own parameter services (--no-read-parameters
  to skip), lifecycle nodes are driven to --lifecycle (default active) first; the contract's
  nodes list their `parameters:` and a lifecycle node its `lifecycle:` state.

endpoints:
  default               infrastructure endpoints (/rosout, /parameter_events, parameter,
                        type description, logger and lifecycle services) and parameters
                        (use_sim_time, start_type_description_service) are left out; the
                        services and topics of an action are grouped into one action entry.
  --include-ros-infra   keeps the infrastructure endpoints (the yaml contract then gets
                        `options: {include_infrastructure: true}`); actions stay grouped.
  --raw                 every endpoint exactly as the middleware recorded it, destroyed ones
                        included: with yaml/json the capture document itself (nodes and
                        endpoints with raw rmw QoS), with nodl the endpoints per node,
                        ungrouped and unfiltered.

--partial: when the target fails, hangs or creates no node, still write what was captured so
far (to -o or stdout; a yaml contract gets a `# PARTIAL capture` comment). The exit status stays 2.

Notes about how the capture came about (the program ended by itself, exited after settling,
uses sim time, virtual time stopped early) are printed to stderr as `note: ...` lines.

exit status: 0 captured, 2 error (no target, target failed/hung/created no node, setup).
"""


def add_parser(sub: Any) -> None:
    """Declare ``capture`` (``sub``: the subparsers of ``rmw-introspect``)."""
    cap = sub.add_parser("capture", help="run a target and print its interfaces (a contract, JSON, NoDL or the raw capture)",
                         description="Run a target on the recording middleware and print its interfaces.",
                         epilog=CAPTURE_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter,
                         usage="%(prog)s [options] (--package P --executable E | --script F | --module M "
                               "| --entry-point MOD:FUNC | -- COMMAND ...)")
    add_target(cap)
    out = cap.add_argument_group("output")
    out.add_argument("--format", choices=("yaml", "json", "nodl"), default="yaml",
                     help="yaml: a complete contract (default); json: the nodes as JSON; nodl: NoDL v2 per node")
    out.add_argument("--raw", action="store_true", help="every endpoint as created: no infrastructure filter, no action grouping")
    out.add_argument("--include-ros-infra", dest="include_infrastructure", action="store_true",
                     help="keep infrastructure endpoints (actions stay grouped)")
    out.add_argument("-o", "--output", metavar="FILE", help="write to FILE instead of stdout")
    out.add_argument("--partial", action="store_true",
                     help="when the target fails or hangs, still write what was captured (exit status stays 2)")
    launch_options.add_launch(cap)
    add_live(cap)  # --live: the running graph (issue 52, cli/live.py)
    cap.set_defaults(handler=cmd_capture)


def cmd_capture(args: argparse.Namespace, command: list[str] | None) -> int:
    from .ros_setup import Setup

    if args.live:  # issue 52: a system contract of the running graph
        from . import live

        return live.cmd_capture(args, command)
    if args.parameter_timeout is not None:
        raise UsageError("--parameter-timeout is for a running graph: give --live too")
    setup = Setup()  # the ROS environment and the middleware, found on first use
    if launch_options.wants_launch(args):
        from . import system_contracts  # the system pipeline and launch readers: only for a launch file

        return system_contracts.cmd_capture(args, command, setup.ros, setup.library)
    from ..run import runner
    from ..run.target import TargetSpec
    from . import formats

    launch_options.launch_block(args)  # launch options without a launch file are a usage error
    cwd = Path.cwd()
    target = target_from_args(args, command)
    spec = TargetSpec.from_mapping(target, base_dir=cwd, source="command line")
    if spec.kind is None:
        raise UsageError("no target: give --package P --executable E, --script FILE, --module M, "
                         "--entry-point MOD:FUNC or -- COMMAND ARGS...")
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
