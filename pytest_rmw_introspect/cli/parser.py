"""The ``rmw-introspect`` parser: the program's own description and options, and the subparser
of every command, each declared by its command's module (``add_parser``, beside the ``cmd_*``
it runs). A command module imports at module level only what its parser needs, so building the
whole parser (every run, ``--help``, a usage error) loads none of the pipelines."""

from __future__ import annotations

import argparse

from .._version import __version__
from . import capture, check, compat, contracts, diff, graph, init, install_launch, lock, validate
from .arguments import CliParser

#: the command modules, in the order ``rmw-introspect --help`` lists them
COMMANDS = (capture, check, diff, init, validate, contracts, lock, compat, graph, install_launch)

_DESCRIPTION = """\
Interface contracts of ROS 2 nodes: run a node on the recording middleware (rmw_introspect_cpp)
and write down, check or compare the publishers, subscriptions, services and actions it creates.

A launch file is a target too: `capture --launch robot.launch.xml -o robot.system.yaml` captures
every process it starts into a system contract, which check, diff, compat and graph read.

Run `rmw-introspect COMMAND --help` for the options of a command.

examples:
  rmw-introspect capture --package my_pkg --executable talker -o talker.interfaces.yaml
  rmw-introspect capture --format nodl --script my_node.py --param rate:=10.0
  rmw-introspect check contracts/*.interfaces.yaml --fail-on risky
  rmw-introspect check --update contracts/talker.interfaces.yaml
  rmw-introspect diff old/talker.interfaces.yaml talker.interfaces.yaml --format json
  rmw-introspect compat contracts/*.interfaces.yaml
  rmw-introspect capture --launch-package my_robot --launch-file robot.launch.xml -o robot.system.yaml
  rmw-introspect graph robot.system.yaml --format html -o robot.html

exit status: 0 everything matches (or only drift below the fail threshold), 1 drift /
incompatibility at or above the fail threshold, 2 an error (a missing or malformed contract,
no target, a target that fails, hangs or creates no node, ROS 2 or the middleware missing,
a bad option). Errors are one message on stderr, never a traceback. Interrupted (Ctrl-C) 130,
terminated (SIGTERM) 143; a running target is stopped first.
"""


def build_parser() -> argparse.ArgumentParser:
    """The parser of ``rmw-introspect``; ``args.handler`` is the chosen command's ``cmd_*``."""
    parser = CliParser(prog="rmw-introspect", description=_DESCRIPTION,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=CliParser, title="commands")
    sub.required = True
    for command in COMMANDS:
        command.add_parser(sub)
    return parser
