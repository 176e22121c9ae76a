"""``rmw-introspect check``: run the target of each contract and compare it with the contract.
Each contract goes through the same pipeline as the pytest plugin (``check.pipeline``,
``check.system_pipeline`` for a system contract, ``check.outcome``), so a contract checks the same
way from both and the reports are the same text; this module only turns outcomes into output, a
golden written with ``--update`` and an exit status."""

from __future__ import annotations

import argparse
import os
import shlex
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import GoldenWriteError, UsageError
from ..model.option_tables import COMPARISON, TARGET, FrontEnd
from . import option_flags
from .arguments import add_baseline, add_compare, add_format, add_target, compare_from_args, target_from_args
from .exit_status import EXIT_DRIFT, EXIT_ERROR, EXIT_OK
from .launch_options import add_launch
from .live_options import add_live, add_watch

if TYPE_CHECKING:
    from ..check.outcome import Checked
    from ..compare.ci_report import ContractOutcome
    from ..model.contract import Contract

CHECK_EPILOG = """\
Each contract's target comes from its `target:` block (paths relative to the contract); target
options given here override it (paths relative to the current directory), and a target named
here (--package/--executable, --script, --module, -- COMMAND) replaces the contract's.

Comparison options given here override the contract's `options:` block, which overrides the
defaults (fail_on: any, nothing ignored). Drift rules and severities: docs/drift-rules.md.

--update rewrites the `nodes:` block of every drifted contract from the capture (keeping the
comments, target and options above it) and creates missing ones (with a `target:` block from
the target options given here); it is refused when the CI environment variable is set.

--baseline FILE fails only on findings that FILE (written by --write-baseline FILE) does not
hold; the known ones are reported as accepted by the baseline.

A NoDL v2 document (*.nodl.yaml, or a file with `nodl_version:`) is a contract too: name the
target here; what NoDL cannot express (type hashes, lifecycle states, parameter ranges, service
QoS) and what the document leaves out are not compared. NoDL's schema is used when found (the
nodl_schema package, or RMW_INTROSPECT_NODL_SCHEMA).

--format json prints one JSON array with an object per drift item: contract, node, kind
(publishers, subscriptions, service_servers, service_clients, action_servers, action_clients,
parameters or node), name, change, rule, severity (SAFE, RISKY, BREAKING), old, new, message.

Parameters and lifecycle: a capture reads every node's parameters and drives lifecycle nodes
to --lifecycle (default active). A contract node without `parameters:` does not compare them;
--update adds them to contracts that match but do not state them yet. A lifecycle transition
that fails is an error (exit 2) naming the node, the transition and what to set instead.

exit status: 0 all contracts match (or drift below --fail-on), 1 drift at or above --fail-on, or
(--update) a contract written over a system problem at or above system_fail_on, 2 errors
(missing/malformed contract, no target, target failure, ROS 2/middleware missing).
"""


def add_parser(sub: Any) -> None:
    """Declare ``check`` (``sub``: the subparsers of ``rmw-introspect``)."""
    chk = sub.add_parser("check", help="run the target of each contract and compare it with the contract (drift report)",
                         description="Capture the target of each contract and compare it with the contract.",
                         epilog=CHECK_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter,
                         usage="%(prog)s [options] CONTRACT... [-- COMMAND ...]")
    chk.add_argument("contracts", nargs="+", metavar="CONTRACT",
                     help="contract files (YAML), or directories: every node contract, marker golden and system "
                     "contract under one, found by its content")
    add_target(chk)
    add_compare(chk)
    add_format(chk)
    chk.add_argument("--update", action="store_true",
                     help="rewrite drifted contracts and create missing ones (refused when CI is set)")
    add_baseline(chk)
    chk.add_argument("--summary", metavar="FILE",
                     help="also append the Markdown report (a table of the contracts, the drift by severity) to FILE, "
                     "whatever --format prints: --format github --summary \"$GITHUB_STEP_SUMMARY\" gives the "
                     "annotations and the job summary from one run")
    chk.add_argument("--shard", metavar="I/N",
                     help="check only this CI job's share of the contracts: job I of N (e.g. 2/4); the contracts are "
                     "sorted by path and dealt round-robin, so the N jobs together check each exactly once")
    add_launch(chk)
    chk.add_argument("--bag", metavar="PATH",  # check --bag (cli.recordings)
                     help="check a recording instead of running each contract's target: a rosbag2 bag directory "
                     "(metadata.yaml; sqlite3 or mcap storage), an .mcap or a .db3 file. Each recorded topic's type, "
                     "type hash and offered QoS against the contracts' publishers and subscriptions; contract topics "
                     "the recording lacks, recorded topics no contract declares, and each topic's message count "
                     "(docs/recordings.md)")
    chk.add_argument("-v", "--verbose", action="store_true",
                     help="a passing system contract names every node it matched (else it says how many nodes in "
                     "how many processes)")
    add_live(chk)  # --live: the running graph (issue 52, cli/live.py)
    add_watch(chk)
    chk.set_defaults(handler=cmd_check)


def accept_command(args: argparse.Namespace, contract: str, command: list[str] | None) -> str:
    """`rmw-introspect check --update [the target and comparison flags given] CONTRACT`."""
    words = ["rmw-introspect", "check", "--update"]
    for option in (*TARGET.exposed(FrontEnd.CLI), *COMPARISON.exposed(FrontEnd.CLI)):
        words += option_flags.as_flags(option, getattr(args, option.name, None))
    words.append(contract)
    if command:
        words += ["--", *command]
    return shlex.join(words)


def _no_target(contract: Contract | None, shown: str) -> str:
    if contract is None:
        return (f"{shown} does not exist; to create it, name the target, e.g. "
                f"rmw-introspect check --update --script node.py {shlex.quote(shown)}")
    from ..check import golden_tests

    marker_test = golden_tests.how_to_check(contract.path or shown, shown)
    if marker_test is not None:  # a marker test's golden: its test writes the target
        return marker_test
    return (f"{shown} has no `target:` block naming what to run; add one (package+executable, "
            "command, script or module) or name the target on the command line "
            "(--package P --executable E, --script FILE, --module M or -- COMMAND)")


def _write_golden(result: Checked, path: Path, shown: str) -> str:
    """Write the golden of ``result``; returns what to say on stderr (raises GoldenWriteError)."""
    from ..check import golden, pipeline

    if not isinstance(result, pipeline.CheckResult):  # a system contract writes its own header
        return f"{result.update() or 'unchanged'} {shown}"
    if result.missing:
        assert result.spec is not None
        header = golden.new_contract_header(spec=result.spec, base=path.absolute().parent,
                                            include_infrastructure=result.options.include_infrastructure,
                                            how="rmw-introspect check --update", run_dir=result.spec.cwd or Path.cwd())
        result.update(new_header=header)
        return f"created {shown}"
    return f"{result.update() or 'unchanged'} {shown}"


def contract_files_given(given: list[str]) -> list[str]:
    """The contract files to check: each file given, and for a directory every node contract,
    marker golden and system contract under it, found by its content (``check.contract_files``),
    said on stderr; a directory with none is an error that names where it looked."""
    from ..check import contract_files
    from ..model.contract_kind import Kind

    files: list[str] = []
    for shown in given:
        if not os.path.isdir(shown):
            files.append(shown)
            continue
        listing = contract_files.find_contracts(shown)
        chosen = listing.of_kind({Kind.NODE, Kind.GOLDEN, Kind.SYSTEM})
        passed = (f"; not contracts ({contract_files.NOT_A_CONTRACT}): "
                  f"{contract_files.skipped_text(listing.skipped, 'YAML file')}" if listing.skipped else "")
        if not chosen:
            raise UsageError(f"check {shown}: no contract to check under it: it looked at {listing.how}{passed} "
                             "(`rmw-introspect contracts DIR` lists what it finds; docs/contract-files.md)")
        said = contract_files.kinds_text(listing.contracts[name] for name in chosen)
        print(f"rmw-introspect: {shown}: {contract_files.counted(len(chosen), 'contract')} ({said}){passed}",
              file=sys.stderr)
        files += [os.path.join(shown, name) for name in chosen]
    return files


def cmd_check(args: argparse.Namespace, command: list[str] | None) -> int:
    from ..check import golden_record, pipeline, sharding
    from ..check.outcome import Verdict, decide
    from ..compare import ci_report
    from . import baselines, recordings, system_contracts
    from .emit import Report, emit
    from .formats import append_summary, say_notes
    from .ros_setup import Setup

    if args.update:
        refusal = golden_record.ci_refusal()
        if refusal:
            raise UsageError(refusal.replace("--update-golden", "--update").replace(
                "run `pytest --update` on", "run `rmw-introspect check --update` on"))
    args.contracts = contract_files_given(args.contracts)
    baseline = baselines.load(args)
    if args.shard:
        shard = sharding.parse(args.shard)
        everything = args.contracts
        args.contracts = shard.select(everything, lambda shown: Path(os.path.normpath(shown)).as_posix())
        print(f"shard {shard}: {len(args.contracts)} of {len(everything)} contract(s)", file=sys.stderr)
    # --live (issue 52): the running graph, read once, stands in for every contract's target
    live_graph = None
    if (args.watch or args.duration is not None or args.parameter_timeout is not None) and not args.live:
        raise UsageError("--watch, --duration and --parameter-timeout are for a running graph: give --live too")
    if args.live:
        from . import live as live_check

        live_check.refuse_with_live(args, command)
        if args.bag:
            raise UsageError("--live checks the running graph and --bag a recording: give one of them")
        if args.watch:
            return live_check.cmd_watch(args)
        live_graph = live_check.read(args)
    cwd = Path.cwd()
    target = target_from_args(args, command) if live_graph is None else {}
    layers = pipeline.Layers(strong_target=[(target, cwd, "command line")] if target else [],
                             strong_options=[(compare_from_args(args), "command line")])
    setup = Setup()
    bag = recordings.start(args, command) if args.bag else None  # check --bag: a recording, nothing runs
    checked: list[Checked] = []
    status = EXIT_OK
    all_items: list[dict[str, Any]] = []
    for_ci: list[ContractOutcome] = []
    noted: dict[str, list[str]] = {}
    for shown in bag.order(args.contracts) if bag else args.contracts:
        path = Path(shown)
        result: Checked
        if live_graph is not None:  # --live (issue 52)
            result = live_check.check_one(path, shown, live_graph, layers)
        elif bag is not None:
            result = bag.result(path, shown)
        elif system_contracts.checks_as_system(path, args):
            result = system_contracts.check_system_contract(args, path, shown, command, setup.ros, setup.library)
        else:
            result = pipeline.check_contract(path, library=setup.library, ros=setup.ros, layers=layers, shown=shown,
                                             allow_missing=args.update, no_target=_no_target)
        baselines.apply(baseline, result)
        checked.append(result)
        how = bag.how_to_accept if bag else accept_command(args, shown, command)
        outcome = decide(result, update=args.update, accept_command=how, verbose=args.verbose)
        all_items += outcome.json
        for note in result.check_notes():  # said once per run, after the reports
            noted.setdefault(note, []).append(shown)
        if outcome.verdict is Verdict.ERROR:
            print(f"rmw-introspect: {outcome.message}", file=sys.stderr)
            for_ci.append(result.for_ci())
            status = EXIT_ERROR
            continue
        if outcome.verdict is Verdict.WRITE:
            try:
                said = _write_golden(result, path, shown)
            except GoldenWriteError as exc:
                print(f"rmw-introspect: {exc}", file=sys.stderr)
                for_ci.append(ci_report.ContractOutcome(contract=shown, error=str(exc)))
                status = EXIT_ERROR
                continue
            if args.format == "text" and outcome.report:
                sys.stdout.write(outcome.report)
            print(said, file=sys.stderr)
            if outcome.version_advice:  # an update never changes interface_version itself
                print(f"note: {outcome.version_advice}", file=sys.stderr)
            for_ci.append(result.for_ci(written=said.split(" ", 1)[0]))
            if outcome.unfixed:  # written, and the system still broken: not a green update
                print(f"rmw-introspect: {said}, but {outcome.unfixed}", file=sys.stderr)
                if status == EXIT_OK:
                    status = EXIT_DRIFT
            continue
        for_ci.append(result.for_ci())
        if args.format == "text":
            if outcome.report:
                sys.stdout.write(outcome.report + "\n")
            else:
                print(outcome.message)
        if outcome.failed and status == EXIT_OK:
            status = EXIT_DRIFT
    if args.format != "github":  # (github: notices on the contracts, ci_report.drift_github)
        say_notes(noted)
    baselines.finish(args, baseline, checked, [Path(c) for c in args.contracts])
    if args.write_baseline and status == EXIT_DRIFT:
        status = EXIT_OK  # today's findings are what the baseline records
    # the text report was written contract by contract, as each was checked
    report = Report(text="", data=all_items, outcomes=for_ci)
    if args.summary:
        append_summary(args.summary, report.markdown())
    emit(report, args.format)
    return status
