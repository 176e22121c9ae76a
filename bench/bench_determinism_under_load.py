"""Same captures under a CPU hog: the example contracts, captured again and again while two busy
processes at normal priority compete for the CPU, must give the same capture every time
(issue 24 item 2). Too slow for the suite (50 runs of 17 targets); run it by hand:

    python bench/bench_determinism_under_load.py [--runs 50] [--hogs 2]

Each run captures the target of every ``*.interfaces.yaml`` of the example package (its
``target:`` block, as ``rmw-introspect check`` would) and keeps the contract view (nodes,
interfaces, type hashes, QoS, parameters, lifecycle states; ``destroyed_at`` as "destroyed", an
age counted from start-up) and the notes with their numbers left out. The first run is the
reference; every later run must equal it. Prints the count of identical runs per target, the
differences of the first run that differed, and exits 1 when any run differed or failed.
"""

from __future__ import annotations

import argparse
import json
import re
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

from pytest_rmw_introspect.errors import TargetError
from pytest_rmw_introspect.model import contract
from pytest_rmw_introspect.run import middleware, runner
from pytest_rmw_introspect.run.target import TargetSpec

CONTRACTS = Path(__file__).resolve().parents[1] / "examples" / "rmw_introspect_examples" / "contracts"
HOG = "while True:\n    pass\n"


def _marked(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: "destroyed" if k == "destroyed_at" else _marked(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_marked(v) for v in value]
    return value


def outcome(spec: TargetSpec, library: Path) -> str:
    """What one capture of ``spec`` found, as canonical JSON (or the error's kind)."""
    try:
        cap = runner.run(spec, library=library)
    except TargetError as exc:
        return json.dumps({"error": type(exc).__name__})
    return json.dumps({"nodes": _marked(cap.to_contract_nodes()),
                       "notes": [re.sub(r"\d+(\.\d+)?", "#", n) for n in cap.notes()]}, sort_keys=True)


def targets() -> dict[str, TargetSpec]:
    out = {}
    for path in sorted(CONTRACTS.glob("*.interfaces.yaml")):
        loaded = contract.load(path)
        if loaded.target:
            out[path.name] = TargetSpec.from_mapping(loaded.target, base_dir=path.parent)
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", type=int, default=50)
    parser.add_argument("--hogs", type=int, default=2, help="busy processes at normal priority (default 2)")
    args = parser.parse_args()
    specs = targets()
    library = middleware.ensure_library()  # once: a source edit meanwhile must not rebuild it mid-run
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))  # stopped: the hogs go too (finally)
    hogs = [subprocess.Popen([sys.executable, "-c", HOG]) for _ in range(args.hogs)]
    reference: dict[str, str] = {}
    same = {name: 0 for name in specs}
    first_difference: dict[str, tuple[int, str]] = {}
    t0 = time.monotonic()
    try:
        for run in range(args.runs):
            for name, spec in specs.items():
                found = outcome(spec, library)
                if name not in reference:
                    reference[name] = found
                if found == reference[name]:
                    same[name] += 1
                else:
                    first_difference.setdefault(name, (run, found))
            print(f"run {run + 1}/{args.runs} done ({time.monotonic() - t0:.0f} s)", flush=True)
    finally:
        for hog in hogs:
            hog.kill()
            hog.wait()
    print(f"\n{len(specs)} targets, {args.runs} runs each, {args.hogs} CPU hogs, {time.monotonic() - t0:.0f} s")
    for name in specs:
        print(f"  {name:<44} {same[name]}/{args.runs} identical")
    for name, (run, found) in first_difference.items():
        print(f"\n{name}: run {run + 1} differed from run 1:\n  run 1: {reference[name]}\n  run {run + 1}: {found}")
    total = sum(same.values())
    print(f"\nidentical: {total}/{len(specs) * args.runs}")
    return 0 if total == len(specs) * args.runs else 1


if __name__ == "__main__":
    sys.exit(main())
