"""``rmw-introspect diff --against REF [CONTRACT...]``: the pull-request gate (``check.gate``),
printed in the formats of ``diff`` with its exit status (``diff`` declares the options and
hands over to ``cmd_gate``)."""

from __future__ import annotations

import argparse
import sys

from ..check import gate
from ..compare import baseline as baseline_module
from ..compare import ci_report
from ..errors import RmwIntrospectError
from .arguments import compare_from_args
from .emit import Report, emit
from .exit_status import EXIT_DRIFT, EXIT_ERROR, EXIT_OK
from .formats import append_summary


def cmd_gate(args: argparse.Namespace) -> int:
    options = compare_from_args(args)
    fail_on = options.pop("fail_on", None)
    baseline = baseline_module.load(args.baseline) if args.baseline else None
    try:
        result = gate.run(args.against, args.files, systems=args.against_system,
                          options=[(options, "command line")], fail_on=fail_on, baseline=baseline)
    except RmwIntrospectError as exc:  # exit 2 (cli.main says it): the job summary and annotations say it too
        if args.summary:
            append_summary(args.summary, f"## Interface changes against {args.against}: error (exit 2)\n\n"
                           f"```\n{exc}\n```\n")
        if args.format == "github":
            print(ci_report.annotation("error", str(exc), title="rmw-introspect gate"))
        raise
    for contract in result.errors:
        print(f"rmw-introspect: {contract.error}", file=sys.stderr)
    report = Report(text=result.render_text, data=result.to_json(), outcomes=result.for_ci(), title=result.title(),
                    intro=result.intro(), notice=f"{result.title()}: {'; '.join(result.intro())}")
    if args.summary:
        append_summary(args.summary, report.markdown())
    emit(report, args.format)
    if result.errors:
        return EXIT_ERROR
    return EXIT_DRIFT if result.failed else EXIT_OK
