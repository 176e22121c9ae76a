"""``rmw-introspect lock``: the type-hash lockfile of a package, written from its contracts'
``types:`` sections without running anything (``model.type_lock``; ``check`` compares with it)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..check import golden
from ..errors import TypeLockError
from ..model import contract as contract_module
from ..model import type_lock
from ..model.paths import shown as display
from .parser import EXIT_OK


def default_path(contracts: list[Path]) -> Path:
    """``interfaces.lock.json`` at the package root above the contracts (the first directory with a
    package.xml, setup.py, pyproject.toml or .git), else in the contracts' common directory."""
    directories = [c.absolute().parent for c in contracts]
    common = Path(*[parts[0] for parts in zip(*(d.parts for d in directories), strict=False)
                    if all(p == parts[0] for p in parts)])
    for directory in (common, *common.parents):
        if any((directory / marker).exists() for marker in ("package.xml", "setup.py", "pyproject.toml", ".git")):
            return directory / type_lock.FILE_NAME
    return common / type_lock.FILE_NAME


def cmd_lock(args: argparse.Namespace) -> int:
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
