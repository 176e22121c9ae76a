"""The ``--live`` options of ``check`` and ``capture`` (issue 52): declared here, with nothing of
the live check imported, so that building the parser stays light (``cli.live`` runs them)."""

from __future__ import annotations

import argparse

from ..live import DEFAULT_PARAMETER_TIMEOUT, DEFAULT_SETTLE, DEFAULT_TIMEOUT

LIVE_HELP = ("read the running ROS 2 graph instead of running a target: joins it on the middleware of "
             "RMW_IMPLEMENTATION, ROS_DOMAIN_ID and ROS_AUTOMATIC_DISCOVERY_RANGE, waits until it has been "
             f"stable for --settle seconds (default {DEFAULT_SETTLE:g}; at most --timeout, default "
             f"{DEFAULT_TIMEOUT:g}) and reads every node, endpoint, parameter and lifecycle state (docs/live.md)")
PARAMETER_TIMEOUT_HELP = ("with --live: seconds the nodes' parameter and lifecycle services have to answer, "
                          f"all nodes together (default {DEFAULT_PARAMETER_TIMEOUT:g}); a node that does not "
                          "answer has its parameters noted as not read, never reported as drift")


def add_live(parser: argparse.ArgumentParser) -> None:
    """``--live`` and ``--parameter-timeout``."""
    g = parser.add_argument_group("live graph (a running system)")
    g.add_argument("--live", action="store_true", help=LIVE_HELP)
    g.add_argument("--parameter-timeout", type=float, metavar="SECONDS", help=PARAMETER_TIMEOUT_HELP)


def add_watch(parser: argparse.ArgumentParser) -> None:
    """``--watch`` and ``--duration`` (``check --live``)."""
    g = parser.add_argument_group("watching a live graph")
    g.add_argument("--watch", action="store_true",
                   help="with --live: after the check, keep watching and report each change of the graph as it "
                   "happens (a node gone, an interface added, a QoS changed; text lines, or JSON lines with "
                   "--format json), then on Ctrl-C or at --duration check the contracts again and sum up")
    g.add_argument("--duration", type=float, metavar="SECONDS",
                   help="with --watch: seconds to watch (default: until Ctrl-C)")
