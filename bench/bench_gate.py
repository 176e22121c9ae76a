"""How long the pull-request gate takes on 100 contracts, against `git diff` of the same files
in the same run (issue 38: under 2 s on this machine).

A temporary repository gets N node contracts (default 100; 10 publishers and 5 subscriptions
each) and 2 system contracts on `main`; a branch then changes 10 of them (QoS, a retype, a bump),
renames 2 and removes 1. Timed, each the median of --runs in fresh processes:

- `rmw-introspect diff --against main` (the whole command, Python start-up included),
- the same with `--format markdown`,
- `git diff main -- '*.interfaces.yaml' '*.system.yaml'` (what a reviewer reads), the yardstick.

    python bench/bench_gate.py [--contracts 100] [--runs 5]
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "support"))

from git_history import GitRepo, endpoint, node_contract, system_contract  # noqa: E402

LIMIT_S = 2.0


def _contract(i: int, *, changed: bool = False) -> str:
    publishers = "".join(endpoint(f"/robot/n{i:03d}/out{p}", depth=5 if changed and p == 0 else 10) for p in range(10))
    subscriptions = "".join(endpoint(f"/robot/n{(i + 1) % 1000:03d}/out{s}") for s in range(5))
    return node_contract(f"/robot/n{i:03d}", publishers=publishers, subscriptions=subscriptions,
                         version="1.1.0" if changed else "1.0.0")


def build(root: Path, contracts: int) -> GitRepo:
    repo = GitRepo(root)
    for i in range(contracts):
        repo.write(f"contracts/n{i:03d}.interfaces.yaml", _contract(i))
    for s in range(2):
        nodes = {f"/robot/consumer{s}_{k}": ("", endpoint(f"/robot/n{k:03d}/out0")) for k in range(10)}
        repo.write(f"robot{s}.system.yaml", system_contract(nodes))
    repo.commit("contracts")
    repo.git("checkout", "-q", "-b", "feature")
    for i in range(10):
        repo.write(f"contracts/n{i:03d}.interfaces.yaml", _contract(i, changed=True))
    repo.move("contracts/n050.interfaces.yaml", "contracts/renamed/n050.interfaces.yaml")
    repo.move("contracts/n051.interfaces.yaml", "contracts/renamed/n051.interfaces.yaml")
    repo.remove(f"contracts/n{contracts - 1:03d}.interfaces.yaml")
    repo.commit("changes")
    return repo


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def timed(command: list[str], cwd: Path, runs: int) -> tuple[float, float, int]:
    """Median wall time and CPU time (user + system of the process and its git children)."""
    walls, cpus, status = [], [], 0
    for _ in range(runs):
        cpu_before, started = _children_cpu(), time.perf_counter()
        result = subprocess.run(command, cwd=cwd, capture_output=True, check=False)
        walls.append(time.perf_counter() - started)
        cpus.append(_children_cpu() - cpu_before)
        status = result.returncode
    return statistics.median(walls), statistics.median(cpus), status


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--contracts", type=int, default=100)
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()
    tool = str(Path(sys.executable).parent / "rmw-introspect")
    with tempfile.TemporaryDirectory() as tmp:
        repo = build(Path(tmp) / "repo", args.contracts)
        git_diff = timed(["git", "diff", "main", "--", "*.interfaces.yaml", "*.system.yaml"], repo.path, args.runs)
        gate = timed([tool, "diff", "--against", "main"], repo.path, args.runs)
        markdown = timed([tool, "diff", "--against", "main", "--format", "markdown"], repo.path, args.runs)
        merge_base = timed([tool, "diff", "--against", "main...HEAD"], repo.path, args.runs)
    rows = [("git diff main (the same files)", git_diff), ("rmw-introspect diff --against main", gate),
            ("  --format markdown", markdown), ("  --against main...HEAD", merge_base)]
    load = os.getloadavg()[0]
    print(f"the gate over {args.contracts} node contracts + 2 system contracts (10 changed, 2 renamed, 1 removed); "
          f"median of {args.runs} runs; exit status {gate[2]}; load average {load:.1f} on {os.cpu_count()} cores")
    print(f"{'command':<40} {'wall':>9} {'cpu':>9} {'x git diff (wall)':>18}")
    for label, (wall, cpu, _) in rows:
        print(f"{label:<40} {wall * 1000:>7.0f}ms {cpu * 1000:>7.0f}ms {wall / git_diff[0]:>17.1f}x")
    verdict = "under" if gate[0] < LIMIT_S else "OVER"
    print(f"the gate takes {gate[0]:.2f} s wall, {gate[1]:.2f} s CPU: {verdict} the {LIMIT_S:.0f} s of issue 38"
          + (" (a loaded machine: compare the CPU time)" if load > (os.cpu_count() or 1) else ""))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
