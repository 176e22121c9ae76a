"""``rmw-introspect graph``: the nodes of contracts drawn with their connections, and what the
compatibility rules find marked on them (``compare.graph``); nothing is run."""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from ..model.vocabulary import FAIL_ON, parse_threshold
from .exit_status import EXIT_OK

GRAPH_FORMATS = ("mermaid", "dot", "html")

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


def add_parser(sub: Any) -> None:
    """Declare ``graph`` (``sub``: the subparsers of ``rmw-introspect``)."""
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
    gra.set_defaults(handler=cmd_graph)


def cmd_graph(args: argparse.Namespace) -> int:
    from ..check import system_pipeline
    from ..compare import graph as graph_module
    from . import formats

    loaded = system_pipeline.load_any(args.contracts)
    from ..compare.compatibility import NOTES

    items = [item for item in system_pipeline.compatibility_items(loaded, strict_system_default=args.strict_system_default)
             if item.rule not in NOTES]  # notes (a pair only DDS would refuse) are no problem to draw
    title = args.title or drawing_title(args.contracts, any_system=loaded.any_system)
    drawing = graph_module.build(loaded.processes, items, title=title)
    formats.emit(graph_module.render(drawing, args.format, threshold=parse_threshold(args.fail_on)), args.output)
    return EXIT_OK


def drawing_title(paths: Sequence[str], *, any_system: bool) -> str:
    """A drawing's default title says what is drawn: a system, or one or several node contracts."""
    names = ", ".join(Path(p).name for p in paths)
    if any_system:
        return f"System {names}"
    return f"Node contract {names}" if len(paths) == 1 else f"Node contracts {names}"
