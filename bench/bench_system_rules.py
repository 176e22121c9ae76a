"""What the system rules add to a system check (issue 37: at most 5 %), in one process.

A launch file starts the example robot (examples/rmw_introspect_examples/launch/robot.launch.xml,
7 processes) ``--robots`` times, each in its own namespace; its system contract is written from
a first capture. Then each repetition runs the system check as ``rmw-introspect check`` does
(``system_pipeline.prepare``, the capture of every process, ``compare``: drift and system rules)
and, on that repetition's capture, the rule pass alone: the processes as the rules read them
(``launched_processes``: what the launch file gives each), the files and devices their
parameters point at (``launch_settings.missing_path``) and every compatibility rule of a launched
system (``check_launched``). The check without the rule pass is the check less that time.

    python bench/bench_system_rules.py [--robots 3 | --launch FILE] [--reps 5] [--rule-reps 50]

``--launch``: another launch file (the largest system of a suite) instead of the example robots.

Prints the medians in ms and the ratio (rule pass / check without it).
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

from pytest_rmw_introspect.check import launch_settings, system_pipeline
from pytest_rmw_introspect.compare.compatibility import check_launched
from pytest_rmw_introspect.run import middleware, ros_env, system_capture

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "rmw_introspect_examples" / "launch" / "robot.launch.xml"


def launch_file(robots: int) -> str:
    includes = "\n".join(f'  <include file="{EXAMPLE}"><arg name="robot" value="robot{i + 1}"/></include>'
                         for i in range(robots))
    return f"<launch>\n{includes}\n</launch>\n"


def rule_pass(prepared: system_pipeline.SystemPrepared, capture: system_capture.SystemCapture) -> float:
    start = time.perf_counter()
    external = prepared.contract.external if prepared.contract is not None else None
    missing = launch_settings.missing_path(system_capture.ament_prefixes(prepared.ros))
    check_launched(system_pipeline.launched_processes(capture), external=external, missing_path=missing)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--robots", type=int, default=3)
    parser.add_argument("--launch", type=Path, help="a launch file to check instead of the example robots")
    parser.add_argument("--reps", type=int, default=5)
    parser.add_argument("--rule-reps", type=int, default=50)
    args = parser.parse_args()
    ros = ros_env.detect()
    library = middleware.ensure_library(ros)
    with tempfile.TemporaryDirectory(prefix="bench_system_rules_") as d:
        root = Path(d)
        launch = args.launch.absolute() if args.launch else root / "robots.launch.xml"
        if not args.launch:
            launch.write_text(launch_file(args.robots))
        contract = root / "robots.system.yaml"
        first = system_pipeline.check_system_contract(contract, library=library, ros=ros, allow_missing=True,
                                                      launch={"path": str(launch)}, launch_base=root)
        assert first.error is None, first.error
        first.update()
        checks, rules = [], []
        for _ in range(args.reps):
            start = time.perf_counter()
            prepared = system_pipeline.prepare(contract, ros=ros)
            capture = system_pipeline.run_capture(prepared, library=library, ros=ros)
            result = system_pipeline.compare(prepared, capture)
            checks.append(time.perf_counter() - start)
            assert not result.failed, result.render_text()
            rules.append(statistics.median(rule_pass(prepared, capture) for _ in range(args.rule_reps)))
        processes = len(capture.processes)
    check, rule = statistics.median(checks), statistics.median(rules)
    without = check - rule
    what = args.launch or f"{args.robots} example robots"
    print(f"system check of {processes} processes ({what}), median of {args.reps}:")
    print(f"  check with the rule pass:    {check * 1000:9.1f} ms")
    print(f"  the rule pass alone:         {rule * 1000:9.2f} ms (median of {args.rule_reps} per repetition)")
    print(f"  check without the rule pass: {without * 1000:9.1f} ms")
    print(f"  ratio (rule pass / check without it): {rule / without * 100:.2f} %")


if __name__ == "__main__":
    main()
