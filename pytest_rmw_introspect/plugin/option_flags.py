"""The pytest front ends of the option tables (``model.option_tables``): a command-line option
``--rmw-introspect-<name>`` and an ini key ``rmw_introspect_<name>`` for every option that
exposes them, generated from the table, and their values read back as option layers."""

from __future__ import annotations

from typing import Any, Literal

import pytest

from ..model.option_tables import Family, FrontEnd, Option, Shape


def add(group: pytest.OptionGroup, parser: pytest.Parser, family: Family) -> None:
    """Add the family's pytest options to ``group`` and its ini keys to ``parser``."""
    for option in family.exposed(FrontEnd.PYTEST):
        group.addoption(option.pytest_flag, default=None, help=option.flag_help(), **_flag_kind(option))
    for option in family.exposed(FrontEnd.INI):
        kind, default = _ini_kind(option)
        parser.addini(option.ini_key, _ini_help(option), type=kind, default=default)


def add_gate(group: pytest.OptionGroup, family: Family) -> None:
    """The gate's pytest options (``--against``, ...: named as ``rmw-introspect diff`` names
    them), their values kept as ``rmw_introspect_<name>``."""
    for option in family.exposed(FrontEnd.PYTEST):
        group.addoption(option.pytest_flag, dest=option.pytest_dest, default=None, help=option.flag_help(),
                        **_flag_kind(option))


def _flag_kind(option: Option) -> dict[str, Any]:
    if option.shape is Shape.SWITCH:
        # a switch that is off by default is switched on; one that is on says true or false
        return {"action": "store_true"} if option.default is False else {"choices": ("true", "false")}
    if option.shape is Shape.CHOICE:
        return {"choices": option.choices}
    if option.shape is Shape.SECONDS:
        return {"type": float, "metavar": "SECONDS"}
    if option.shape is Shape.REPEATED:
        return {"action": "append", "metavar": option.metavar}
    assert option.shape in (Shape.WORDS, Shape.TEXT), option.name  # a new shape needs its flag here
    return {"metavar": option.metavar or option.name.upper()}


def _ini_kind(option: Option) -> tuple[Literal["bool", "args", "string"], Any]:
    if option.shape is Shape.SWITCH and option.default is False:
        return "bool", False
    if option.shape in (Shape.WORDS, Shape.REPEATED):
        return "args", []
    return "string", ""


def _ini_help(option: Option) -> str:
    kind = {Shape.WORDS: "names separated by spaces, or 'all'",
            Shape.REPEATED: f"{option.metavar or 'items'} separated by spaces"}.get(option.shape, option.type_text)
    shown = f"; default: {option.shown_default}" if option.shown_default else ""
    return f"{option.help} ({kind}{shown})"


def flag_values(config: pytest.Config, family: Family) -> dict[str, Any]:
    """The family's values given on pytest's command line (those not given are left out)."""
    values = {}
    for option in family.exposed(FrontEnd.PYTEST):
        value = config.getoption(option.pytest_flag.lstrip("-").replace("-", "_"), None)
        if value is not None:
            values[option.name] = value
    return values


def ini_values(config: pytest.Config, family: Family) -> dict[str, Any]:
    """The family's values set in the ini file (those not set are left out; a value that is not a
    number of seconds is a ``pytest.UsageError``)."""
    values = {}
    for option in family.exposed(FrontEnd.INI):
        value = _ini_value(config, option)
        if value is not None:
            values[option.name] = value
    return values


def _ini_value(config: pytest.Config, option: Option) -> Any:
    raw = config.getini(option.ini_key)
    kind, _default = _ini_kind(option)
    if kind == "bool":  # only ever switches on: false is the default anyway
        return True if raw else None
    if kind == "args":  # one word as it is (`all`), several as a list
        return (raw[0] if len(raw) == 1 else list(raw)) if raw else None
    text = str(raw or "").strip()
    if not text:
        return None
    if option.shape is Shape.SECONDS:
        try:
            return float(text)
        except ValueError:
            raise pytest.UsageError(f"ini option {option.ini_key} = {text!r} is not a number of seconds") from None
    return text
