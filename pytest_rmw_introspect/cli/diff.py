"""``rmw-introspect diff``: two contract files compared (OLD plays the contract, NEW the capture),
or, with ``--against REF``, every contract with its version at a git revision (``gate``);
nothing is run."""

from __future__ import annotations

import argparse
from typing import Any

from ..errors import UsageError
from ..model.option_tables import GATE, FrontEnd
from . import option_flags
from .arguments import add_compare, add_format, compare_from_args
from .exit_status import EXIT_DRIFT, EXIT_OK

DIFF_EPILOG = """\
OLD plays the contract and NEW the capture, so the drift rules and severities are exactly those
of `check`: NEW losing a publisher of OLD is BREAKING, NEW adding one is SAFE. OLD's `options:`
block applies, overridden by the comparison options given here.

--against REF (the pull-request gate, docs/ci.md): each contract git tracks here, found by its
content whatever its name (node contracts, marker goldens, system contracts, NoDL documents), is
compared with its file at REF the same way (a named file with the same file at REF; a renamed
file with its old name; a removed one loses everything it promised; an added one adds its
nodes). The first line counts the contracts of each kind and names the tracked YAML files that
are not contracts; finding no contract at all is an error (exit 2). It fails on BREAKING
changes unless --fail-on says otherwise. A contract with `interface_version: MAJOR.MINOR.PATCH`
at REF and now is judged by semantic versioning: a BREAKING change needs a MAJOR bump, a RISKY
one at least a MINOR bump (the message says which version to write); changes the bump covers
are accepted. With system
contracts (--against-system, or those git tracks here) a changed topic, service or action is checked
against the nodes that use it: one that no longer fits them is BREAKING and named. The git
history must hold REF: in CI fetch the base branch (actions/checkout `fetch-depth: 0`).

  rmw-introspect diff --against origin/main --format markdown
  rmw-introspect diff --against origin/main...HEAD contracts/talker.interfaces.yaml

exit status: 0 no drift (or below --fail-on), 1 drift at or above --fail-on, 2 errors (a missing
or invalid contract, also one invalid at REF; no contract to compare; REF not found; not a git
repository; a shallow clone without REF).
"""


def add_parser(sub: Any) -> None:
    """Declare ``diff`` (``sub``: the subparsers of ``rmw-introspect``)."""
    dif = sub.add_parser("diff", help="compare two contract files, or every contract with a git revision (no "
                         "target is run)",
                         description="Compare two contract files, or every contract with its version at a git "
                         "revision (--against REF: the pull-request gate), without running anything.",
                         epilog=DIFF_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter,
                         usage="%(prog)s [options] OLD NEW\n       %(prog)s --against REF [options] [CONTRACT...]")
    dif.add_argument("files", nargs="*", metavar="FILE",
                     help="OLD NEW: the contract as it was and as it is now; with --against: the contracts to compare "
                     "(default: every contract git tracks under the current directory, found by its content)")
    gate = dif.add_argument_group("the pull-request gate (docs/ci.md)")
    option_flags.add(gate, GATE.exposed(FrontEnd.GATE))
    # the gate's consumer systems were given as --system before the option tables named them
    gate.add_argument("--system", action="append", dest="against_system", metavar="FILE", help=argparse.SUPPRESS)
    gate.add_argument("--baseline", metavar="FILE",
                      help="fail only on findings that FILE (written by `check --write-baseline`) does not hold")
    gate.add_argument("--summary", metavar="FILE",
                      help="also append the Markdown report to FILE (\"$GITHUB_STEP_SUMMARY\"), whatever --format prints")
    add_compare(dif, FrontEnd.DIFF)
    add_format(dif)
    dif.set_defaults(handler=cmd_diff)


def cmd_diff(args: argparse.Namespace) -> int:
    if args.against is not None:
        from .gate import cmd_gate

        return cmd_gate(args)
    from ..check import diff
    from .emit import Report, emit

    given = [flag for flag, value in (("--against-system", args.against_system), ("--baseline", args.baseline),
                                      ("--summary", args.summary)) if value]
    if given:
        raise UsageError(f"{' and '.join(given)} go with --against REF (the gate against a git revision), not with "
                         "`diff OLD NEW`")
    if len(args.files) != 2:
        raise UsageError(f"diff compares two files, OLD and NEW ({len(args.files)} given); to compare every contract "
                         "with a git revision: rmw-introspect diff --against REF [CONTRACT...]")
    old, new = args.files
    result = diff.diff_contracts(old, new, [(compare_from_args(args), "command line")])
    emit(Report(text=result.render_text, data=result.to_json(), outcomes=[result.for_ci()],
                title=f"Interface drift of {result.shown}"), args.format)
    return EXIT_DRIFT if result.failed else EXIT_OK
