"""What a `make coverage` run covered, in one file to compare before and after a change (issue 48,
item 3; docs/development.md, "Line coverage and the exercised set").

    python scripts/coverage_summary.py DIR [--compare OLD_SUMMARY.json]

DIR is the run's directory: ``coverage.json`` (``coverage json``: the package's line coverage,
its subprocesses combined) and ``cost/report.json`` (tests/support/cost_report.py: the rules,
commands, report formats and contract kinds the tests met, end to end and in the unit tier).
Writes ``DIR/summary.json`` and prints it; with ``--compare`` also what is less than in OLD (a line
coverage that went down, a rule, command, format or kind no longer exercised end to end), and
exits 1 when anything is.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any


def summary(coverage: dict[str, Any], cost: dict[str, Any]) -> dict[str, Any]:
    """The figures of one run: line coverage (total and per file) and the exercised sets."""
    totals = coverage["totals"]
    files = {path: round(data["summary"]["percent_covered"], 1) for path, data in sorted(coverage["files"].items())}
    return {"line_coverage": {"percent": round(totals["percent_covered"], 2), "covered": totals["covered_lines"],
                              "statements": totals["num_statements"], "files": files},
            "exercised": cost.get("exercised", {})}


def less(old: dict[str, Any], new: dict[str, Any]) -> list[str]:
    """What ``new`` covers less than ``old``: the total, a file's coverage, an exercised name."""
    out = []
    before, after = old["line_coverage"], new["line_coverage"]
    if after["percent"] < before["percent"]:
        out.append(f"line coverage {before['percent']}% -> {after['percent']}%")
    for path, percent in before["files"].items():
        now = after["files"].get(path)
        if now is not None and now < percent:
            out.append(f"{path}: {percent}% -> {now}%")
    for side in ("e2e",):
        for what, names in old["exercised"].get(side, {}).items():
            gone = sorted(set(names) - set(new["exercised"].get(side, {}).get(what, [])))
            if gone:
                out.append(f"no longer exercised end to end ({what}): {', '.join(gone)}")
    return out


def render(data: dict[str, Any]) -> str:
    cov = data["line_coverage"]
    lines = [f"line coverage of pytest_rmw_introspect: {cov['percent']}% ({cov['covered']} of {cov['statements']} lines)"]
    for side, label in (("e2e", "exercised end to end (e2e, plugin, overlay, slow tiers)"), ("unit", "met in the unit tier")):
        sets = data["exercised"].get(side, {})
        lines.append(f"{label}: " + ("; ".join(f"{len(v)} {k}(s)" for k, v in sets.items()) or "nothing"))
        lines += [f"  {what}: {' '.join(names)}" for what, names in sets.items()]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("directory", type=Path)
    parser.add_argument("--compare", type=Path, help="an earlier summary.json: say what is less now")
    args = parser.parse_args(argv)
    cost_file = args.directory / "cost" / "report.json"
    data = summary(json.loads((args.directory / "coverage.json").read_text(encoding="utf-8")),
                   json.loads(cost_file.read_text(encoding="utf-8")) if cost_file.is_file() else {})
    (args.directory / "summary.json").write_text(json.dumps(data, indent=1) + "\n", encoding="utf-8")
    print(render(data))
    print(f"coverage summary: {args.directory / 'summary.json'}")
    if args.compare is None:
        return 0
    worse = less(json.loads(args.compare.read_text(encoding="utf-8")), data)
    print("\n".join(["less than in " + str(args.compare) + ":", *worse]) if worse else f"nothing less than in {args.compare}")
    return 1 if worse else 0


if __name__ == "__main__":
    sys.exit(main())
