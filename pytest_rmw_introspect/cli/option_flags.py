"""The ``rmw-introspect`` front end of the option tables (``model.option_tables``): the argparse
flags of every option a command exposes, generated from the table (``dest`` is the option's
name), their values read back, and the flags that say them again (``check --update`` hints)."""

from __future__ import annotations

import argparse
from collections.abc import Iterable
from typing import Any

from ..model.option_tables import Family, FrontEnd, Option, Shape


def add(container: Any, options: Iterable[Option]) -> None:
    """Add a flag for each option to ``container`` (a parser or an argument group)."""
    for option in options:
        container.add_argument(option.flag, dest=option.name, default=None, help=option.flag_help(), **_kind(option))


def add_group(parser: argparse.ArgumentParser, family: Family, front_end: FrontEnd, title: str,
              description: str | None = None) -> None:
    """An argument group with the flags of the family's options that ``front_end`` exposes."""
    add(parser.add_argument_group(title, description), family.exposed(front_end))


def _kind(option: Option) -> dict[str, Any]:
    if option.shape is Shape.SWITCH:
        # a switch that is off by default is switched on; one that is on has its --no- form
        return {"action": "store_true"} if option.default is False else {"action": argparse.BooleanOptionalAction}
    if option.shape is Shape.CHOICE:
        return {"choices": option.choices}
    if option.shape is Shape.SECONDS:
        return {"type": float, "metavar": "SECONDS"}
    if option.shape is Shape.REPEATED:
        return {"action": "append", "metavar": option.metavar}
    assert option.shape in (Shape.WORDS, Shape.TEXT), option.name  # a new shape needs its flag here
    return {"metavar": option.metavar or option.name.upper()}


def values(args: argparse.Namespace, options: Iterable[Option]) -> dict[str, Any]:
    """The values of ``options`` as the command line gave them (None: not given)."""
    return {option.name: getattr(args, option.name, None) for option in options}


def as_flags(option: Option, value: Any) -> list[str]:
    """The words that give ``option`` the value ``value`` (as parsed) on the command line."""
    if value is None:
        return []
    if option.shape is Shape.SWITCH:
        if option.default is False:
            return [option.flag] if value else []
        return [option.flag if value else "--no-" + option.flag[2:]]
    if option.shape is Shape.REPEATED:
        return [word for item in value for word in (option.flag, str(item))]
    return [option.flag, str(value)]
