"""``rmw-introspect compat``: do the nodes of several contracts fit together? (the compatibility
rules, ``check.system_pipeline.check_contracts``); nothing is run."""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

from .._version import __version__
from ..model.option_tables import COMPARISON
from ..model.vocabulary import FAIL_ON
from .arguments import add_baseline, add_format
from .exit_status import EXIT_DRIFT, EXIT_OK

COMPAT_EPILOG = """\
All nodes of all contracts form one system. Every subscription, service client and action
client is matched with the publishers/servers of the same name: type, type hash and QoS
compatibility (incompatible QoS is BREAKING, possibly incompatible RISKY); a requester without
any provider is RISKY. A policy left at SYSTEM_DEFAULT on both ends is not reported unless
--strict-system-default. QoS is judged for the middleware a system contract says it runs on
(`rmw:`, or RMW_IMPLEMENTATION in its launch environment), else --rmw, else by the DDS rules.
Rules: docs/drift-rules.md ("Compatibility rules", "QoS per middleware").

--fail-on defaults to `breaking` here (a partial system lacking some publisher is common).
exit status: 0 compatible (or problems below --fail-on), 1 problems at or above --fail-on,
2 errors (missing or malformed contract).
"""


def add_parser(sub: Any) -> None:
    """Declare ``compat`` (``sub``: the subparsers of ``rmw-introspect``)."""
    com = sub.add_parser("compat", help="check that the nodes of several contracts fit together",
                         description="Compatibility check: do the nodes of these contracts fit together?",
                         epilog=COMPAT_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    com.add_argument("contracts", nargs="+", metavar="CONTRACT", help="contract files (YAML)")
    com.add_argument("--fail-on", choices=FAIL_ON, default="breaking",
                     help="least severe problem that fails (exit 1); default breaking")
    com.add_argument("--strict-system-default", action="store_true",
                     help="also report policies left at SYSTEM_DEFAULT on both ends (what rmw would warn about)")
    rmw = COMPARISON["rmw"]
    com.add_argument(rmw.flag, dest="rmw", default=None, choices=rmw.choices, metavar=rmw.metavar,
                     help=rmw.flag_help() + f": one of {', '.join(rmw.choices)}")
    add_format(com)
    add_baseline(com)
    com.set_defaults(handler=cmd_compat)


def cmd_compat(args: argparse.Namespace) -> int:
    from ..check import system_pipeline
    from ..compare import ci_report, sarif
    from . import baselines
    from .formats import print_json

    baseline = baselines.load(args)
    result = system_pipeline.check_contracts(args.contracts, fail_on=args.fail_on,
                                             strict_system_default=args.strict_system_default, rmw=args.rmw)
    baselines.apply(baseline, result)
    baselines.finish(args, baseline, [result])
    if args.format == "json":
        print(json.dumps(result.to_json(), indent=2, default=str))
    elif args.format == "markdown":
        sys.stdout.write(ci_report.compat_markdown(result.items, threshold=result.threshold, labels=result.labels))
    elif args.format == "github":
        sys.stdout.write(ci_report.compat_github(result.items, threshold=result.threshold, lines=result.lines,
                                                 file_of=result.file_of, accepted=result.accepted, stale=result.stale))
    elif args.format == "sarif":
        print_json(sarif.compat_log(result.items, threshold=result.threshold, lines=result.lines, file_of=result.file_of,
                                    tool_version=__version__, accepted=result.accepted, stale=result.stale))
    else:
        sys.stdout.write(result.render_text())
    return EXIT_DRIFT if result.failed and not args.write_baseline else EXIT_OK
