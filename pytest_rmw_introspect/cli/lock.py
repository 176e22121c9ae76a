"""``rmw-introspect lock``: the type-hash lockfile of a package, written from its contracts'
``types:`` sections without running anything (``model.type_lock``; ``check`` compares with it)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from ..errors import TypeLockError
from .exit_status import EXIT_OK

LOCK_EPILOG = """\
Each contract needs a types: section (`rmw-introspect check --update --include-types CONTRACT`
writes it). The lockfile is JSON, sorted: commit it. `check` (and pytest) then compare every
interface type of a capture, nested types included, with it: a type that changed upstream is
TYPE_LOCK_CHANGED with the path to it (sensor_msgs/msg/Image -> std_msgs/msg/Header changed), a
type it does not list TYPE_NOT_LOCKED. check finds the file in a contract's directory or above,
up to the package root (package.xml, setup.py, pyproject.toml or .git).

exit status: 0 written (or unchanged), 2 a contract is missing, invalid or has no types: section.
"""


def add_parser(sub: Any) -> None:
    """Declare ``lock`` (``sub``: the subparsers of ``rmw-introspect``)."""
    lck = sub.add_parser("lock", help="write the type-hash lockfile of a package's contracts (no target is run)",
                         description="Write the RIHS01 hash of every interface type the contracts use, nested types "
                         "included (from their types: sections), into a lockfile that check compares with.",
                         epilog=LOCK_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    lck.add_argument("contracts", nargs="+", metavar="CONTRACT", help="node contract files with a types: section")
    lck.add_argument("-o", "--output", metavar="FILE",
                     help="the lockfile (default: interfaces.lock.json at the package root above the contracts)")
    lck.set_defaults(handler=cmd_lock)


def default_path(contracts: list[Path]) -> Path:
    """``interfaces.lock.json`` at the package root above the contracts (the first directory with a
    package.xml, setup.py, pyproject.toml or .git), else in the contracts' common directory."""
    from ..model import type_lock

    directories = [c.absolute().parent for c in contracts]
    common = Path(*[parts[0] for parts in zip(*(d.parts for d in directories), strict=False)
                    if all(p == parts[0] for p in parts)])
    for directory in (common, *common.parents):
        if any((directory / marker).exists() for marker in ("package.xml", "setup.py", "pyproject.toml", ".git")):
            return directory / type_lock.FILE_NAME
    return common / type_lock.FILE_NAME


def cmd_lock(args: argparse.Namespace) -> int:
    from ..check import golden
    from ..model import contract as contract_module
    from ..model import type_lock
    from ..model.paths import shown as display

    contracts = [Path(c) for c in args.contracts]
    output = Path(args.output) if args.output else default_path(contracts)
    types: dict[str, str] = {}
    source: dict[str, str] = {}
    for path in contracts:
        shown = display(path)
        contract = contract_module.load(path)
        if contract.nodl is not None:
            raise TypeLockError(shown, "a NoDL document cannot hold the type descriptions a lock is made from",
                                advice="Lock a contract of the same node instead (`rmw-introspect check --update "
                                "--include-types --package P --executable E NODE.interfaces.yaml` writes one).",
                                subject="cannot lock")
        for name, value in type_lock.locked_hashes(contract.nodes, contract.types, shown).items():
            if name in types and types[name] != value:
                raise TypeLockError(output, f"{source[name]} and {shown} record different hashes of {name} "
                                    f"({types[name]} and {value}): they were captured against different definitions",
                                    advice=f"Bring both up to date (`rmw-introspect check --update --include-types "
                                    f"{source[name]} {shown}`), then lock again.")
            types[name], source[name] = value, shown
    changed = golden.write_text(output, type_lock.render(types, contracts, output))
    print(f"{'wrote' if changed else 'unchanged'} {display(output)}: {len(types)} type(s) of "
          f"{len(contracts)} contract(s)", file=sys.stderr)
    elsewhere = [display(c) for c in contracts if type_lock.find(c) != output.absolute()]
    if elsewhere:
        print(f"note: check does not find {display(output)} from {', '.join(elsewhere)}: it looks for "
              f"{type_lock.FILE_NAME} in a contract's directory and above, up to the package root", file=sys.stderr)
    return EXIT_OK
