"""A capture's interface types against the package's type lock (``model.type_lock``).

Each interface's types are hashed as the node uses them now (the hashes the middleware
recorded, the nested ones computed from the capture's type table) and compared with the lock.
A change is reported where it happened, with the path from the interface's type to it: when
``std_msgs/msg/Header`` changed, ``sensor_msgs/msg/Image``'s hash changed only because of it,
so the item is ``sensor_msgs/msg/Image -> std_msgs/msg/Header changed``, under every
interface that uses it. A type the lock does not list is ``TYPE_NOT_LOCKED`` (lock again).
"""

from __future__ import annotations

from collections.abc import Mapping

from ..model import type_lock
from ..model.contract_shapes import ContractNode
from ..model.type_lock import TypeLock
from ..model.types import TypeDescription, closure, interface_roots
from ..model.vocabulary import LABELS, LISTS
from .drift import RULES, TYPE_CHANGE_PREFIX, DriftItem


def _short(value: str) -> str:
    return value[:19] + "..." if len(value) > 22 else value


def _path(table: Mapping[str, TypeDescription], root: str, target: str) -> list[str]:
    """The shortest chain of nested types from ``root`` to ``target`` (both included)."""
    paths = {root: [root]}
    queue = [root]
    while queue:
        name = queue.pop(0)
        if name == target:
            return paths[name]
        for reference in table[name].references() if name in table else ():
            if reference not in paths:
                paths[reference] = paths[name] + [reference]
                queue.append(reference)
    return [root, target]


def lock_drift(nodes: Mapping[str, ContractNode], table: Mapping[str, TypeDescription], lock: TypeLock) -> list[DriftItem]:
    """The differences between the types the interfaces of ``nodes`` (a capture's, in contract
    form) use and ``lock``, as drift items under each interface."""
    items: list[DriftItem] = []
    shown = lock.path.name
    for fqn, node in nodes.items():
        current = type_lock.current_hashes({fqn: node}, table)
        for list_name in LISTS:
            for entry in node.get(list_name) or ():
                reported: set[str] = set()  # an action's parts share nested types: each once
                for root in interface_roots(list_name, entry["type"]):
                    reached = closure(table, [root]) or [root]
                    changed = {t for t in reached if t in lock.types and t in current and lock.types[t] != current[t]}
                    # where a change happened: a changed type none of whose nested types changed
                    origins = [t for t in reached if t in changed
                               and not any(r in changed for r in (table[t].references() if t in table else ()))]
                    for origin in (o for o in origins if o not in reported):
                        reported.add(origin)
                        path = " -> ".join(_path(table, root, origin))
                        items.append(DriftItem(
                            fqn, list_name, entry["name"], TYPE_CHANGE_PREFIX + origin, lock.types[origin],
                            current[origin], "TYPE_LOCK_CHANGED", RULES["TYPE_LOCK_CHANGED"].severity,
                            f"{path} changed since {shown} locked it ({_short(lock.types[origin])} -> "
                            f"{_short(current[origin])}): peers built against the locked definition cannot exchange "
                            f"this {LABELS[list_name]}'s messages with it; if the change is wanted, run "
                            "`rmw-introspect lock` again"))
                    for name in reached:
                        if name in current and name not in lock.types and name not in reported:
                            reported.add(name)
                            items.append(DriftItem(
                                fqn, list_name, entry["name"], TYPE_CHANGE_PREFIX + name, None, current[name],
                                "TYPE_NOT_LOCKED", RULES["TYPE_NOT_LOCKED"].severity,
                                f"{name} is not in {shown}: a change of it upstream would go unnoticed; run "
                                "`rmw-introspect lock` again to pin it"))
    return items
