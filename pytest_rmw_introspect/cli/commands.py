"""The commands of ``rmw-introspect`` that check contracts: check, diff, compat, graph (capture
is ``capture``, init is ``init``). Each goes through the same pipeline as the pytest plugin
(``check.pipeline`` and ``check.outcome``), so a contract checks the same way from both and
the reports are the same text; this module only turns outcomes into output and an exit status."""

from __future__ import annotations

import argparse
import json
import os
import shlex
import sys
from pathlib import Path
from typing import Any

from .._version import __version__
from ..check import golden, golden_record, pipeline, sharding
from ..check.outcome import Checked, Verdict, decide
from ..compare import ci_report, sarif
from ..errors import GoldenWriteError, UsageError
from ..model.contract import Contract
from ..model.option_tables import COMPARISON, TARGET, FrontEnd
from . import baselines, option_flags, system_contracts
from .formats import print_json
from .parser import EXIT_DRIFT, EXIT_ERROR, EXIT_OK, compare_from_args, target_from_args
from .ros_setup import Setup


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
    return (f"{shown} has no `target:` block naming what to run; add one (package+executable, "
            "command, script or module) or name the target on the command line "
            "(--package P --executable E, --script FILE, --module M or -- COMMAND)")


def _write_golden(result: Checked, path: Path, shown: str) -> str:
    """Write the golden of ``result``; returns what to say on stderr (raises GoldenWriteError)."""
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


def cmd_check(args: argparse.Namespace, command: list[str] | None) -> int:
    if args.update:
        refusal = golden_record.ci_refusal()
        if refusal:
            raise UsageError(refusal.replace("--update-golden", "--update").replace(
                "run `pytest --update` on", "run `rmw-introspect check --update` on"))
    baseline = baselines.load(args)
    if args.shard:
        shard = sharding.parse(args.shard)
        everything = args.contracts
        args.contracts = shard.select(everything, lambda shown: Path(os.path.normpath(shown)).as_posix())
        print(f"shard {shard}: {len(args.contracts)} of {len(everything)} contract(s)", file=sys.stderr)
    cwd = Path.cwd()
    target = target_from_args(args, command)
    layers = pipeline.Layers(strong_target=[(target, cwd, "command line")] if target else [],
                             strong_options=[(compare_from_args(args), "command line")])
    setup = Setup()
    checked: list[Checked] = []
    status = EXIT_OK
    all_items: list[dict[str, Any]] = []
    for_ci: list[ci_report.ContractOutcome] = []
    for shown in args.contracts:
        path = Path(shown)
        result: Checked
        if system_contracts.is_system(path, args):
            result = system_contracts.check_system_contract(args, path, shown, command, setup.ros, setup.library)
        else:
            result = pipeline.check_contract(path, library=setup.library, ros=setup.ros, layers=layers, shown=shown,
                                             allow_missing=args.update, no_target=_no_target)
        baselines.apply(baseline, result)
        checked.append(result)
        outcome = decide(result, update=args.update, accept_command=accept_command(args, shown, command),
                         verbose=args.verbose)
        all_items += outcome.json
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
            continue
        for_ci.append(result.for_ci())
        if not (args.format == "text" and outcome.report):  # (a drift report lists them itself)
            for note in result.check_notes():
                print(f"note: {shown}: {note}", file=sys.stderr)
        if args.format == "text":
            if outcome.report:
                sys.stdout.write(outcome.report + "\n")
            else:
                print(outcome.message)
        if outcome.failed and status == EXIT_OK:
            status = EXIT_DRIFT
    baselines.finish(args, baseline, checked, [Path(c) for c in args.contracts])
    if args.write_baseline and status == EXIT_DRIFT:
        status = EXIT_OK  # today's findings are what the baseline records
    if args.summary:
        append_summary(args.summary, ci_report.drift_markdown(for_ci))
    if args.format == "json":
        print(json.dumps(all_items, indent=2, default=str))
    elif args.format == "markdown":
        sys.stdout.write(ci_report.drift_markdown(for_ci))
    elif args.format == "github":
        sys.stdout.write(ci_report.drift_github(for_ci))
    elif args.format == "sarif":
        print_json(sarif.drift_log(for_ci, tool_version=__version__))
    return status


def append_summary(path: str, markdown: str) -> None:
    """Append the Markdown report to ``path`` (``$GITHUB_STEP_SUMMARY`` collects what each step
    appends; the run's own result is never replaced)."""
    try:
        with open(path, "a", encoding="utf-8") as summary:
            summary.write(markdown if markdown.endswith("\n") else markdown + "\n")
    except OSError as exc:
        raise UsageError(f"--summary {path}: cannot append the report ({exc.strerror or exc}); "
                         "give a file in a directory that exists and is writable") from None


def cmd_diff(args: argparse.Namespace) -> int:
    given = [flag for flag, value in (("--system", args.against_systems), ("--baseline", args.baseline),
                                      ("--summary", args.summary)) if value]
    if given:
        raise UsageError(f"{' and '.join(given)} go with --against REF (the gate against a git revision), not with "
                         "`diff OLD NEW`")
    if len(args.files) != 2:
        raise UsageError(f"diff compares two files, OLD and NEW ({len(args.files)} given); to compare every contract "
                         "with a git revision: rmw-introspect diff --against REF [CONTRACT...]")
    args.old, args.new = args.files
    if system_contracts.any_system([args.old, args.new]):
        return system_contracts.cmd_diff(args)
    result = pipeline.diff_contracts(args.old, args.new, [(compare_from_args(args), "command line")])
    if args.format == "json":
        print(json.dumps(result.to_json(), indent=2, default=str))
    elif args.format == "markdown":
        sys.stdout.write(ci_report.drift_markdown([result.for_ci()], title=f"Interface drift of {result.new_shown}"))
    elif args.format == "github":
        sys.stdout.write(ci_report.drift_github([result.for_ci()]))
    elif args.format == "sarif":
        print_json(sarif.drift_log([result.for_ci()], tool_version=__version__))
    else:
        sys.stdout.write(result.render_text())
    return EXIT_DRIFT if result.failed else EXIT_OK


def cmd_compat(args: argparse.Namespace) -> int:
    baseline = baselines.load(args)
    result = system_contracts.system_pipeline.check_contracts(args.contracts, fail_on=args.fail_on,
                                                              strict_system_default=args.strict_system_default)
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


def cmd_graph(args: argparse.Namespace) -> int:
    return system_contracts.cmd_graph(args)
