"""``rmw-introspect compat``: do the nodes of several contracts fit together? (the compatibility
rules, ``check.system_pipeline.check_contracts``); nothing is run."""

from __future__ import annotations

import argparse
from typing import Any

from ..model.option_tables import COMPARISON
from ..model.vocabulary import FAIL_ON
from . import option_flags
from .arguments import add_baseline, add_format
from .exit_status import EXIT_DRIFT, EXIT_OK

COMPAT_EPILOG = """\
All nodes of all contracts form one system. Every subscription, service client and action
client is matched with the publishers/servers of the same name: type, type hash and QoS
compatibility (incompatible QoS is BREAKING, possibly incompatible RISKY); a requester without
any provider is RISKY. A policy left at SYSTEM_DEFAULT on both ends is not reported unless
--strict-system-default. QoS is judged for the middleware a system contract says it runs on
(`rmw:`, or RMW_IMPLEMENTATION in its launch environment), else --rmw, else by the DDS rules.
Rules: docs/drift-rules.md ("Compatibility rules", "QoS per middleware"). A problem gets the
level a contract's `options: rules` gives its rule in the file of either end (the more severe
when both set one), under --rule.

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
    option_flags.add(com, [COMPARISON["rules"]])
    add_format(com)
    add_baseline(com)
    com.set_defaults(handler=cmd_compat)


def cmd_compat(args: argparse.Namespace) -> int:
    from ..check import system_pipeline
    from ..compare import rule_levels
    from . import baselines
    from .emit import Report, emit

    baseline = baselines.load(args)
    rules = rule_levels.parse(args.rules, "command line") if args.rules else ()
    result = system_pipeline.check_contracts(args.contracts, fail_on=args.fail_on,
                                             strict_system_default=args.strict_system_default, rmw=args.rmw,
                                             rules=rules)
    baselines.apply(baseline, result)
    baselines.finish(args, baseline, [result])
    emit(Report(text=result.render_text, data=result.to_json(), compat=result), args.format)
    return EXIT_DRIFT if result.failed and not args.write_baseline else EXIT_OK
