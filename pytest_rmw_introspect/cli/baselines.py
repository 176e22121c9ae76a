"""``--baseline FILE`` and ``--write-baseline FILE`` of ``check`` and ``compat``: reading the
baseline once, applying it to each result (``check.baselines``), writing it through the one
writer, and the note that findings of the baseline are gone."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterable
from pathlib import Path

from ..check import baselines, golden
from ..compare import baseline as baseline_module
from ..compare.baseline import Baseline
from ..errors import UsageError


def load(args: argparse.Namespace) -> Baseline | None:
    """The baseline the command line names (None without ``--baseline``); usage errors first."""
    if args.baseline and args.write_baseline:
        raise UsageError("give --baseline FILE (fail only on new findings) or --write-baseline FILE (record "
                         "today's findings), not both")
    if args.write_baseline and getattr(args, "shard", None):
        raise UsageError("--write-baseline with --shard would record one job's findings only: write the baseline "
                         "from a run over every contract (without --shard)")
    if args.write_baseline and getattr(args, "update", False):
        raise UsageError("--write-baseline records findings and --update rewrites contracts: run them one at a time")
    return baseline_module.load(args.baseline) if args.baseline else None


def apply(baseline: Baseline | None, result: baselines.Result) -> None:
    """Apply ``baseline`` to a result that was checked (nothing to do without one or on an error)."""
    if baseline is not None and getattr(result, "error", None) is None:
        baselines.apply(result, baseline)


def finish(args: argparse.Namespace, baseline: Baseline | None, results: Iterable[baselines.Result],
           contracts: Iterable[Path] | None = None) -> None:
    """Write the baseline (``--write-baseline``), or say which findings of the baseline are gone."""
    if args.write_baseline:
        found = baselines.findings(results)
        golden.write_text(args.write_baseline, baseline_module.render(found, args.write_baseline))
        print(f"wrote the baseline {args.write_baseline} ({len(found)} finding(s))", file=sys.stderr)
    elif baseline is not None:
        note = baseline.fixed_note(contracts)
        if note:
            print(f"note: {note}", file=sys.stderr)
