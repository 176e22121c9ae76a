"""Launch-file substitutions (``$(var name)``, ``$(env NAME default)``, ...): parsing and evaluation.

The grammar is the one of the ROS 2 launch front ends (XML and YAML): ``$(`` a name, then
arguments separated by white space, then ``)``. Arguments may be quoted (``'...'`` or
``"..."``) and may themselves contain substitutions (``$(find-pkg-share $(var pkg))``). Text
outside substitutions is taken as it is.

Supported: ``var``, ``env``, ``optenv``, ``find-pkg-share``, ``find-pkg-prefix``, ``dirname``,
``filename`` and ``anon``. Anything else (``eval``, ``command``, ``exec-in-pkg``,
``find-exec``, ``parameter``, ...) is :class:`UnsupportedSubstitution`, which the launch reader
reports with the file and line of the entity that uses it.

Launch files may come from anywhere, so both steps are bounded: substitutions nest at most
:data:`MAX_NESTING` deep (parsing recurses once per level), a value is at most
:data:`MAX_VALUE_CHARS` characters, and one launch produces at most :data:`MAX_TOTAL_CHARS`
characters of substituted text (:class:`Budget`): a chain of ``<let>`` values that each double
the last one is refused at its twentieth step instead of filling the memory.
"""

from __future__ import annotations

import hashlib
import os
import re
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import SubstitutionError, UnsupportedSubstitution
from ..model import untrusted

#: the substitutions this reader evaluates
SUPPORTED = ("var", "env", "optenv", "find-pkg-share", "find-pkg-prefix", "dirname", "filename", "anon")
#: the deepest nesting of substitutions (``$(find-pkg-share $(var pkg))`` is 2)
MAX_NESTING = 32
#: the longest value a substitution may give (a launch configuration, an attribute)
MAX_VALUE_CHARS = 1_000_000
#: the most characters the substitutions of one launch may give in all
MAX_TOTAL_CHARS = 64_000_000


@dataclass(frozen=True)
class Substitution:
    """``$(name arg arg ...)``; every argument is itself a list of parts."""

    name: str
    arguments: tuple[tuple[Part, ...], ...] = ()


Part = str | Substitution


def parse(text: str) -> tuple[Part, ...]:
    """``text`` as a sequence of plain strings and :class:`Substitution` parts (raises SubstitutionError)."""
    parts, end = _parse_parts(text, 0, top=True, depth=0)
    assert end == len(text)
    return tuple(parts)


def has_substitution(text: str) -> bool:
    return "$(" in text


def _parse_parts(text: str, pos: int, *, top: bool, depth: int) -> tuple[list[Part], int]:
    """Parts from ``pos`` up to the end (``top``) or up to an unquoted white space or ``)``."""
    parts: list[Part] = []

    def add(part: Part) -> None:
        if isinstance(part, str) and parts and isinstance(parts[-1], str):
            parts[-1] += part
        elif part != "":
            parts.append(part)

    while pos < len(text):
        if text.startswith("$(", pos):
            sub, pos = _parse_substitution(text, pos, depth + 1)
            add(sub)
            continue
        char = text[pos]
        if not top and (char.isspace() or char == ")"):
            break
        if not top and char in "'\"":
            end = text.find(char, pos + 1)
            if end < 0:
                raise SubstitutionError(f"unterminated quote in {_short(text)}")
            for part in _parse_parts(text[pos + 1:end], 0, top=True, depth=depth)[0]:
                add(part)
            pos = end + 1
            continue
        add(char)
        pos += 1
    return parts, pos


def _parse_substitution(text: str, pos: int, depth: int) -> tuple[Substitution, int]:
    if depth > MAX_NESTING:
        raise SubstitutionError(f"substitutions are nested more than {MAX_NESTING} levels deep")
    start = pos
    pos += 2
    match = re.compile(r"[A-Za-z_][A-Za-z0-9_-]*").match(text, pos)
    if match is None:
        raise SubstitutionError(f"a substitution name must follow '$(' in {text!r}")
    name = match.group(0)
    pos = match.end()
    arguments: list[tuple[Part, ...]] = []
    while True:
        while pos < len(text) and text[pos].isspace():
            pos += 1
        if pos >= len(text):
            raise SubstitutionError(f"unterminated substitution {_short(text[start:])} (missing ')')")
        if text[pos] == ")":
            return Substitution(name, tuple(arguments)), pos + 1
        argument, pos = _parse_parts(text, pos, top=False, depth=depth)
        arguments.append(tuple(argument))


def _short(text: str) -> str:
    return untrusted.shorten(text)


class Budget:
    """The characters the substitutions of one launch may still give (:data:`MAX_TOTAL_CHARS`)."""

    def __init__(self, total: int = MAX_TOTAL_CHARS) -> None:
        self.left = total

    @staticmethod
    def check_length(length: int) -> None:
        if length > MAX_VALUE_CHARS:
            raise SubstitutionError(f"a substituted value has more than {MAX_VALUE_CHARS:,} characters "
                                    "(a value that doubles at each <let>?)")

    def spend(self, text: str) -> str:
        """``text``, counted; raises SubstitutionError when it is too long or the budget is spent."""
        self.check_length(len(text))
        self.left -= len(text)
        if self.left < 0:
            raise SubstitutionError(f"the substitutions of this launch give more than {MAX_TOTAL_CHARS:,} "
                                    "characters in all (values that grow at each <let> or include?)")
        return text


@dataclass
class Context:
    """What substitutions read: launch configurations, the environment, the current file and
    the ament prefixes (for ``find-pkg-*``)."""

    configurations: Mapping[str, str]
    environment: Mapping[str, str]
    current_file: Path
    find_package: Callable[[str], Path]
    anon_names: dict[str, str] = field(default_factory=dict)
    budget: Budget = field(default_factory=Budget)


def evaluate(parts: Sequence[Part], context: Context) -> str:
    """The text of ``parts`` with every substitution evaluated (raises SubstitutionError)."""
    pieces: list[str] = []
    length = 0
    for part in parts:
        piece = part if isinstance(part, str) else _evaluate_one(part, context)
        length += len(piece)
        context.budget.check_length(length)  # before the join, which would be the allocation
        pieces.append(piece)
    return context.budget.spend("".join(pieces))


def substitute(text: str, context: Context) -> str:
    """Parse and evaluate ``text``."""
    return evaluate(parse(text), context) if has_substitution(text) else text


def _evaluate_one(sub: Substitution, context: Context) -> str:
    args = [evaluate(argument, context) for argument in sub.arguments]

    def arity(low: int, high: int) -> None:
        if not low <= len(args) <= high:
            want = str(low) if low == high else f"{low} to {high}"
            raise SubstitutionError(f"$({sub.name}) takes {want} argument(s), got {len(args)}: {args}")

    if sub.name == "var":
        arity(1, 1)
        if args[0] not in context.configurations:
            known = ", ".join(sorted(context.configurations)) or "none"
            raise SubstitutionError(
                f"launch configuration '{args[0]}' is not set (set here: {known}); declare it with "
                f"<arg name=\"{args[0]}\" default=\"...\"/> or <let>, or pass it as a launch argument"
            )
        return context.configurations[args[0]]
    if sub.name in ("env", "optenv"):
        arity(1, 2)
        if args[0] in context.environment:
            return context.environment[args[0]]
        if len(args) == 2:
            return args[1]
        if sub.name == "optenv":
            return ""
        raise SubstitutionError(
            f"environment variable '{args[0]}' is not set; set it, or give a default: $(env {args[0]} DEFAULT)"
        )
    if sub.name == "find-pkg-share":
        arity(1, 1)
        return str(context.find_package(args[0]) / "share" / args[0])
    if sub.name == "find-pkg-prefix":
        arity(1, 1)
        return str(context.find_package(args[0]))
    if sub.name == "dirname":
        arity(0, 0)
        return str(context.current_file.parent)
    if sub.name == "filename":
        arity(0, 0)
        return str(context.current_file)
    if sub.name == "anon":
        arity(1, 1)
        return anon_name(args[0], context.anon_names)
    raise UnsupportedSubstitution(sub.name, SUPPORTED)


def anon_name(name: str, cache: dict[str, str]) -> str:
    """``$(anon NAME)``: the same name for the same NAME within one launch, as in ROS 2.

    ROS 2 adds the host name, the process id and a random number, so the name differs between
    runs. A contract has to name the node the same way every run, so here the suffix is a
    hash of NAME: unique per NAME, stable across runs.
    """
    if name not in cache:
        digest = hashlib.sha256(name.encode()).hexdigest()[:8]
        cache[name] = re.sub(r"[^A-Za-z0-9_]", "_", f"{name}_anon_{digest}")
    return cache[name]


class _EnvironmentView(Mapping[str, str]):
    """``os.environ`` seen through overrides, read when looked up: a launch evaluates
    substitutions for every attribute, and copying the environment each time was most of the
    time a launch with many includes took."""

    def __init__(self, overrides: Mapping[str, str | None]) -> None:
        self._overrides = overrides

    def __getitem__(self, key: str) -> str:
        if key in self._overrides:
            value = self._overrides[key]
            if value is None:
                raise KeyError(key)
            return value
        return os.environ[key]

    def __iter__(self) -> Iterator[str]:
        unset = {k for k, v in self._overrides.items() if v is None}
        return iter([k for k in {**os.environ, **self._overrides} if k not in unset])

    def __len__(self) -> int:
        return sum(1 for _ in self)


def environment_view(overrides: Mapping[str, str | None]) -> Mapping[str, str]:
    """``os.environ`` with the launch file's ``set_env`` overrides (None: unset)."""
    return _EnvironmentView(overrides)
