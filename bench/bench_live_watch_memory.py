"""Whether `check --live --watch` keeps its memory flat while the graph keeps changing (issue 52
item 2): the example talker runs on Fast DDS in a domain of its own, the example listener is
started and stopped over and over (every change a new graph for the watch), and the resident set
of the command line and of its reader process is sampled after every cycle.

    python bench/bench_live_watch_memory.py [--seconds 300] [--pause 1] [--log FILE]

``--pause`` is the idle time after each stop: an hours-long run takes ``--seconds 7200 --pause 20``
(a change every ~11 s, little CPU beside other work); ``--log`` appends every sample as it is taken
(``seconds cli_kB reader_kB``), so a run that is cut short still says what it saw.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

from pytest_rmw_introspect.live import bringup
from pytest_rmw_introspect.run.target import TargetSpec

CONTRACT = Path(__file__).resolve().parents[1] / "examples" / "rmw_introspect_examples" / "contracts" / \
    "talker.interfaces.yaml"


def rss_kb(pid: int | None) -> int | None:
    try:
        with open(f"/proc/{pid}/status", encoding="utf-8") as status:
            return int(next(line for line in status if line.startswith("VmRSS")).split()[1])
    except (OSError, StopIteration, TypeError):
        return None


def reader_pid(parent: int) -> int | None:
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat", encoding="utf-8") as stat:
                    if int(stat.read().rsplit(")", 1)[1].split()[1]) == parent:
                        return int(entry)
            except (OSError, ValueError, IndexError):
                continue
    return None


def example(executable: str) -> TargetSpec:
    return TargetSpec(package="rmw_introspect_examples", executable=executable)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=300.0)
    parser.add_argument("--pause", type=float, default=1.0, help="seconds idle after each listener stop")
    parser.add_argument("--log", type=Path, help="append each sample to this file as it is taken")
    args = parser.parse_args()
    domain = bringup.reserve_domain()
    talker = bringup.start([example("talker")], domain=domain)
    watch = subprocess.Popen([sys.executable, "-m", "pytest_rmw_introspect", "check", "--live", "--watch",
                              "--duration", f"{args.seconds:g}", "--settle", "0.5", str(CONTRACT)],
                             env=talker.env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    start, cycles, samples = time.monotonic(), 0, []
    try:
        while watch.poll() is None:
            listener = bringup.start([example("listener")], domain=domain)
            time.sleep(2.0)
            listener.stop()
            cycles += 1
            samples.append((time.monotonic() - start, rss_kb(watch.pid), rss_kb(reader_pid(watch.pid))))
            if args.log:
                with args.log.open("a", encoding="utf-8") as log:
                    log.write("%.0f %s %s\n" % samples[-1])
            time.sleep(args.pause)
    finally:
        watch.wait()
        talker.stop()
        domain.release()
    print(f"{cycles} listener start/stop cycles in {time.monotonic() - start:.0f} s (two graph changes each)")
    print("seconds  command line RSS (kB)  reader RSS (kB)")
    for at, cli, reader in samples[:: max(1, len(samples) // 12)] + samples[-1:]:
        print(f"{at:7.0f}  {cli!s:>21}  {reader!s:>15}")


if __name__ == "__main__":
    main()
