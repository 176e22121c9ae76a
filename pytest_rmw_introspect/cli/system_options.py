"""The command-line options of system contracts (``parser`` calls these): launch files for
``capture`` and ``check``, and the ``graph`` command (``--system-fail-on`` is a comparison
option, ``model.option_tables.COMPARISON``)."""

from __future__ import annotations

import argparse
from typing import Any

from ..model.option_tables import TARGET, FrontEnd
from ..model.vocabulary import FAIL_ON

GRAPH_FORMATS = ("mermaid", "dot", "html")

LAUNCH_HELP = """\
a system (a launch file: every process it starts is captured, in parallel):
  --launch FILE                        an XML, YAML or Python launch file, or a record.json of dump_launch
  --launch-package P --launch-file F   a launch file of a package, found like `ros2 launch P F`
With a launch file, `capture` writes a system contract (NAME.system.yaml) and the target
options apply to every process ({flags} only).
""".format(flags=", ".join(option.flag if option.default is not True else f"--[no-]{option.flag[2:]}"
                           for option in TARGET.exposed(FrontEnd.SYSTEM)))

GRAPH_EPILOG = """\
Draws the nodes of the contracts (system contracts, node contracts, or both) with their topics,
services and actions, and marks what the compatibility rules find (docs/drift-rules.md, "Compatibility
rules"): the edges of an incompatible connection, a requester without provider, duplicate
node names, several servers, a launched process that created no node, in red (BREAKING) or
orange (RISKY) with the rule id. Nothing is run.

formats:
  mermaid  (default) a Mermaid flowchart: put it in a ```mermaid block of a pull request, an
           issue or a Markdown file and GitHub/GitLab draw it
  dot      Graphviz: `dot -Tsvg system.dot -o system.svg`
  html     one self-contained page (the drawing and the list of problems; no script, nothing
           fetched): open it in a browser, or keep it as a CI artifact

exit status: 0 drawn, 2 errors (missing or malformed contract). The problems do not change it:
use `rmw-introspect compat` or `check` to gate on them.
"""


def add_launch(parser: argparse.ArgumentParser) -> None:
    """``--launch``, ``--launch-package``/``--launch-file``, ``--launch-arg``, ``--allow-unsupported``."""
    g = parser.add_argument_group("system (launch file)", LAUNCH_HELP)
    g.add_argument("--launch", metavar="FILE", help="launch file (XML, YAML, Python) or dump_launch record.json")
    g.add_argument("--launch-package", metavar="P", help="package of the launch file (with --launch-file)")
    g.add_argument("--launch-file", metavar="F", help="launch file name inside the package's share directory")
    g.add_argument("--launch-arg", action="append", metavar="NAME:=VALUE",
                   help="launch argument, as `ros2 launch ... NAME:=VALUE` (repeatable)")
    g.add_argument("--allow-unsupported", action="store_true", default=None,
                   help="capture what the launch reader supports and note the rest, instead of failing")
    g.add_argument("--jobs", type=int, metavar="N", help="processes captured at a time (default: the number of cores)")


def add_graph(sub: Any, parser_class: type[argparse.ArgumentParser]) -> None:
    """The ``graph`` command."""
    gra = sub.add_parser("graph", help="draw a system: nodes, topics, services, actions and what does not fit",
                         description="Draw the nodes of the contracts with their connections; mark the problems.",
                         epilog=GRAPH_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    gra.add_argument("contracts", nargs="+", metavar="CONTRACT", help="system contracts and/or node contracts")
    gra.add_argument("--format", choices=GRAPH_FORMATS, default="mermaid", help="mermaid (default), dot or html")
    gra.add_argument("-o", "--output", metavar="FILE", help="write to FILE instead of stdout")
    gra.add_argument("--title", help="title of the drawing (default: the contracts' names)")
    gra.add_argument("--strict-system-default", action="store_true",
                     help="also mark policies left at SYSTEM_DEFAULT on both ends")
    gra.add_argument("--fail-on", choices=FAIL_ON, default="breaking",
                     help="threshold the html page's verdict line uses (default breaking)")
