"""``rmw-introspect contracts [DIR]``: the contract files under a directory, found by their
content whatever their names (``check.contract_files``), one path a line: what the GitHub
action's check step hands to ``check``, and an answer to "which of my files does the tool take
for contracts?". Nothing is loaded or run."""

from __future__ import annotations

import argparse
import os
import sys
from typing import Any

from ..errors import UsageError
from .exit_status import EXIT_OK

#: ``--kind`` words and the kinds they name
KIND_WORDS = {"node": "NODE", "golden": "GOLDEN", "system": "SYSTEM", "nodl": "NODL"}

CONTRACTS_EPILOG = """\
A file is a contract by its top-level keys: `contract_version:` a node contract (with a
`target:` block it runs by itself: `node`; without one it is the golden of a marker test:
`golden`), `system_version:` a system contract (`system`), `nodl_version` a NoDL document
(`nodl`); a name ending in .interfaces.yaml, .system.yaml or .nodl.yaml also says so. In a git
repository the files are those git knows of (tracked, and untracked ones it does not ignore);
elsewhere every file below DIR but hidden directories and build, install and log.

  rmw-introspect contracts                          # every contract here
  rmw-introspect contracts src --kind node --kind system
  rmw-introspect check $(rmw-introspect contracts --kind node)

exit status: 0 at least one contract listed; 2 none (the message says where it looked and which
YAML files it passed over).
"""


def add_parser(sub: Any) -> None:
    """Declare ``contracts`` (``sub``: the subparsers of ``rmw-introspect``)."""
    con = sub.add_parser("contracts", help="list the contract files under a directory, found by their content",
                         description="List the contract files under a directory (default: the current one), found "
                         "by their content whatever their names; nothing is loaded or run.",
                         epilog=CONTRACTS_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    con.add_argument("directory", nargs="?", default=".", metavar="DIR", help="where to look (default: .)")
    con.add_argument("--kind", action="append", choices=sorted(KIND_WORDS), dest="kinds",
                     help="only contracts of this kind (repeatable; default: every kind)")
    con.add_argument("-0", "--null", action="store_true",
                     help="end each path with a NUL byte instead of a newline (for `xargs -0`, bash `read -d ''`)")
    con.set_defaults(handler=cmd_contracts)


def cmd_contracts(args: argparse.Namespace) -> int:
    from ..check import contract_files
    from ..model.contract_kind import Kind

    kinds = {Kind[KIND_WORDS[word]] for word in args.kinds} if args.kinds else None
    listing = contract_files.find_contracts(args.directory)
    chosen = listing.of_kind(kinds)
    passed = (f"; not contracts ({contract_files.NOT_A_CONTRACT}): {contract_files.skipped_text(listing.skipped, 'YAML file')}"
              if listing.skipped else "")
    unread = ("; not read: " + "; ".join(f"{contract_files.display(name)} {why}" for name, why in listing.unread.items())
              if listing.unread else "")
    if not chosen:
        others = (f"; it found {contract_files.kinds_text(listing.contracts.values())}, of other kinds"
                  if listing.contracts else "")
        wanted = " or ".join(f"`{word}`" for word in args.kinds) + " " if args.kinds else ""
        raise UsageError(f"no {wanted}contract under {args.directory}: it looked at {listing.how}{others}{passed}"
                         f"{unread}")
    prefix = "" if args.directory in (".", "./") else args.directory.rstrip("/") + "/"
    end = "\0" if args.null else "\n"
    # the names as the file system spells them (a name that is not UTF-8 is still the file's name)
    listed = "".join(f"{prefix}{name}{end}" for name in chosen)
    raw = getattr(sys.stdout, "buffer", None)
    if raw is None:  # a text stream without bytes under it (a test's StringIO): the names as they print
        sys.stdout.write(listed.encode("utf-8", "surrogateescape").decode("utf-8", "replace"))
    else:
        sys.stdout.flush()
        raw.write(os.fsencode(listed))
        raw.flush()
    said = contract_files.kinds_text(listing.contracts[name] for name in chosen)
    print(f"rmw-introspect: {contract_files.counted(len(chosen), 'contract')} under {args.directory} ({said}){passed}"
          f"{unread}", file=sys.stderr)
    return EXIT_OK
