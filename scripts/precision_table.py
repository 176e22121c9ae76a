#!/usr/bin/env python3
"""The precision and recall of the system rules on the modelled bring-ups (tests/precision).

Usage, with the venv's Python (``make precision-table`` runs the first):

    python scripts/precision_table.py --run [--jobs N] [--system NAME ...]
        captures and checks every modelled system and each of its seeded bugs with `rmw-introspect`
        (a few minutes), records what came out in tests/precision/results.json (with --system,
        only those systems' records are replaced) and writes the table into docs/drift-rules.md
    python scripts/precision_table.py
        writes the table from the recorded results (after editing how it is drawn)
    python scripts/precision_table.py --check
        exits 1 when the table in docs/drift-rules.md is not the one the recorded results give

The table goes between the markers `<!-- precision-table:start -->` and `<!-- precision-table:end -->`.
The suite's tests (tests/precision/test_precision.py) fail when a run differs from the record,
and tests/unit/test_precision_table.py when the page differs from the record.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "drift-rules.md"
sys.path[:0] = [str(ROOT / "tests" / "precision"), str(ROOT / "tests" / "support")]

import precision_suite as suite  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--run", action="store_true", help="run every system and seeded bug, record the results")
    parser.add_argument("--check", action="store_true", help="exit 1 when the page's table is stale")
    parser.add_argument("--jobs", type=int, default=1, help="systems run at once with --run (default 1)")
    parser.add_argument("--system", action="append", default=[], help="with --run: only this system (repeatable)")
    parser.add_argument("--doc", type=Path, default=DOC, help="the page with the table's markers (default: %(default)s)")
    parser.add_argument("--results", type=Path, default=suite.RESULTS, help="the recorded results (default: %(default)s)")
    args = parser.parse_args(argv)
    if args.run:
        from pytest_rmw_introspect.run import middleware

        env = dict(os.environ, RMW_INTROSPECT_LIBRARY=str(middleware.ensure_library()))
        unknown = set(args.system) - {s.name for s in suite.systems()}
        if unknown:
            print(f"precision_table: no modelled system named {', '.join(sorted(unknown))} in {suite.SYSTEMS_DIR}",
                  file=sys.stderr)
            return 2
        with tempfile.TemporaryDirectory(prefix="precision-") as work:
            fresh = suite.run_all(env, Path(work), jobs=args.jobs, only=args.system or None)
        results = suite.load_results(args.results) if args.system else {"systems": {}}
        results.setdefault("systems", {}).update(fresh["systems"])
        suite.write_results(results, args.results)
    try:
        document = args.doc.read_text(encoding="utf-8")
        wanted = suite.with_table(document, suite.render_table(suite.load_results(args.results)))
    except (OSError, ValueError, KeyError, suite.SuiteError) as exc:
        print(f"precision_table: {args.doc}: {exc}", file=sys.stderr)
        return 2
    if args.check:
        if wanted != document:
            print(f"{args.doc}: the precision table is not the one {args.results} gives: "
                  "run `make precision-table`", file=sys.stderr)
            return 1
        return 0
    if wanted != document:
        args.doc.write_text(wanted, encoding="utf-8")
        print(f"precision_table: wrote the table into {args.doc}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
