"""How long `rmw-introspect diff` takes on a large contract, with libyaml and with the pure-Python
YAML parser, in one run (issue 11 §2 item 11).

A generated contract with N endpoints (default 100,000: 1,000 nodes of 100 publishers) is
diffed against a copy with one change; each variant runs in a fresh process, and the table
shows the median wall time and the peak resident memory.

    python bench/bench_large_contract.py [--endpoints 100000] [--runs 3]
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

HASH = "RIHS01_" + "ab" * 32


def contract(endpoints: int, per_node: int = 100, changed: bool = False) -> str:
    lines = ["contract_version: 1", "nodes:"]
    for n in range(max(1, endpoints // per_node)):
        lines += [f"  /node_{n:05d}:", "    publishers:"]
        for p in range(per_node):
            depth = 5 if changed and n == 0 and p == 0 else 10
            lines += [f"      - name: /topic_{n:05d}_{p:03d}", "        type: std_msgs/msg/String",
                      f"        type_hash: {HASH}",
                      f"        qos: {{history: KEEP_LAST, depth: {depth}, reliability: RELIABLE, durability: VOLATILE}}"]
    return "\n".join(lines) + "\n"


RUNNER = textwrap.dedent("""
    import json, resource, sys, time, yaml
    from pytest_rmw_introspect.model import untrusted
    if sys.argv[1] == "pure":
        untrusted.LOADER = yaml.SafeLoader
    from pytest_rmw_introspect.check.diff import diff_contracts
    started = time.perf_counter()
    result = diff_contracts(sys.argv[2], sys.argv[3])
    wall = time.perf_counter() - started
    print(json.dumps({"wall": wall, "items": len(result.items),
                      "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
""")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--endpoints", type=int, default=100_000)
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        old, new = Path(tmp) / "old.interfaces.yaml", Path(tmp) / "new.interfaces.yaml"
        old.write_text(contract(args.endpoints))
        new.write_text(contract(args.endpoints, changed=True))
        size_mb = old.stat().st_size / 1e6
        rows = {}
        for variant in ("libyaml", "pure"):
            samples = []
            for _ in range(args.runs):
                out = subprocess.run([sys.executable, "-c", RUNNER, variant, str(old), str(new)],
                                     capture_output=True, text=True, check=True)
                samples.append(json.loads(out.stdout))
            rows[variant] = samples
    print(f"diff of two contracts of {args.endpoints:,} endpoints ({size_mb:.1f} MB each), median of {args.runs} runs")
    print(f"{'YAML parser':<28}{'wall s':>10}{'peak RSS MB':>14}{'drift items':>13}")
    for variant, samples in rows.items():
        wall = statistics.median(s["wall"] for s in samples)
        rss = statistics.median(s["rss_mb"] for s in samples)
        name = "libyaml (CSafeLoader)" if variant == "libyaml" else "pure Python (SafeLoader)"
        print(f"{name:<28}{wall:>10.2f}{rss:>14.0f}{samples[0]['items']:>13}")
    ratio = statistics.median(s["wall"] for s in rows["pure"]) / statistics.median(s["wall"] for s in rows["libyaml"])
    print(f"libyaml is {ratio:.1f}x faster")
    return 0


if __name__ == "__main__":
    sys.exit(main())
