"""Reading files people (or a fuzzer) hand us: bounded, typed and fast.

Contracts and capture files may come from anywhere (``diff`` and ``compat`` are meant for
untrusted pull requests), so reading them is bounded:

* :func:`read_text`: only regular files (a FIFO, which blocks whoever opens it for reading,
  is refused before anything opens it; so is ``/dev/zero``), at most :data:`MAX_FILE_BYTES`,
  UTF-8; :func:`read_bytes` for the first bytes of such a file (sniffing a file's kind);
* :func:`compose_yaml`: libyaml when installed (about ten times faster than the pure-Python
  parser on large files, with the same line numbers), every failure a :class:`InputError`;
* :func:`check_tree`: mapping keys are strings and unique, nesting is at most
  :data:`MAX_DEPTH` deep, and the document expands (through YAML aliases) to at most
  :data:`MAX_VALUES` values, so an alias bomb is refused in linear time instead of being
  expanded for hours.

Each function raises :class:`InputError` (reason, 1-based line, location as a path of keys and
indices); the readers turn it into their own error type with the file's name.
"""

from __future__ import annotations

import contextlib
import gc
import hashlib
import os
import re
import stat
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import InputError

if TYPE_CHECKING:
    import yaml

#: the largest file read (a contract of 100k endpoints is about 7 MB)
MAX_FILE_BYTES = 64 * 1024 * 1024
#: the deepest nesting of mappings and lists (a contract needs 6)
MAX_DEPTH = 64
#: the most values a document may expand to through aliases
MAX_VALUES = 2_000_000

#: the loader class; None: libyaml's when PyYAML was built with it, else the pure-Python one
LOADER: type | None = None


def _loader(loader: type | None) -> type:
    import yaml  # ~20 ms: imported on first use, so `rmw-introspect capture` starts without it

    if loader is not None:
        return loader
    if LOADER is not None:
        return LOADER
    fastest: type = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
    return fastest


def not_a_file(mode: int) -> str | None:
    """What a file of this ``st_mode`` is when it cannot be read as a document, as the end of
    a sentence about it ("is a directory, not a file"); None for a regular file."""
    if stat.S_ISREG(mode):
        return None
    if stat.S_ISDIR(mode):
        return "is a directory, not a file"
    if stat.S_ISFIFO(mode):
        return "is a FIFO (named pipe), not a regular file"
    if stat.S_ISSOCK(mode):
        return "is a socket, not a regular file"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "is a device, not a regular file"
    return "is not a regular file"


def file_problem(path: Path) -> str | None:
    """Why ``path`` cannot be read as a document, as the end of a sentence about it ("does not
    exist", "is a FIFO (named pipe), not a regular file"); None for a regular file. Nothing is
    opened."""
    try:
        return not_a_file(os.stat(path).st_mode)
    except FileNotFoundError:
        return "does not exist"
    except OSError as exc:
        return f"cannot be read ({exc.strerror or exc})"


def _stat_regular(path: Path) -> os.stat_result:
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise
    except OSError as exc:
        raise InputError(f"cannot read it: {exc.strerror or exc}") from None
    _refuse_kind(info)
    return info


def _refuse_kind(info: os.stat_result) -> None:
    reason = not_a_file(info.st_mode)
    if reason is not None:
        raise InputError(f"it {reason}; give the path of a file")


def read_bytes(path: Path, max_bytes: int) -> bytes:
    """At most ``max_bytes + 1`` bytes of the regular file ``path``. A FIFO, socket or device is
    refused from its ``stat`` before anything opens it (opening a FIFO for reading blocks until
    a writer comes), and again from the opened file (it may have been swapped in between).
    Raises FileNotFoundError for a missing file, InputError otherwise."""
    _stat_regular(path)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_NOCTTY | os.O_CLOEXEC)
    except FileNotFoundError:
        raise
    except OSError as exc:
        raise InputError(f"cannot read it: {exc.strerror or exc}") from None
    with os.fdopen(fd, "rb") as f:
        _refuse_kind(os.fstat(fd))
        try:
            return f.read(max_bytes + 1)
        except OSError as exc:
            raise InputError(f"cannot read it: {exc.strerror or exc}") from None


def read_text(path: Path, *, max_bytes: int | None = None) -> str:
    """The UTF-8 text of a regular file of at most ``max_bytes`` (default :data:`MAX_FILE_BYTES`;
    raises FileNotFoundError for a missing file, InputError otherwise)."""
    max_bytes = MAX_FILE_BYTES if max_bytes is None else max_bytes
    size = _stat_regular(path).st_size
    if size > max_bytes:
        raise InputError(f"it is {size / 1e6:.0f} MB, more than the {max_bytes / 1e6:.0f} MB limit")
    data = read_bytes(path, max_bytes)
    if len(data) > max_bytes:
        raise InputError(f"it grew beyond the {max_bytes / 1e6:.0f} MB limit while being read")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(f"it is not UTF-8 text (byte {exc.start}: {exc.reason})") from None


@contextlib.contextmanager
def gc_paused() -> Iterator[None]:
    """No cyclic garbage collection in the block. Parsing and validating a document makes
    millions of objects and no cycles; each collection the allocations trigger walks all of
    them, which made loading a large contract superlinear (30k endpoints: 5.4 s to compose the
    YAML with collections, 1.1 s without)."""
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled:
            gc.enable()


def compose_yaml(text: str, loader: type | None = None) -> yaml.Node | None:
    """The YAML node tree of ``text`` (one document), or None for an empty document."""
    with gc_paused():
        return _compose_yaml(text, loader)


def _compose_yaml(text: str, loader: type | None) -> yaml.Node | None:
    import yaml

    loader_class = _loader(loader)
    too_deep = _bracket_past(text, MAX_DEPTH)
    if too_deep is not None:
        # Deep flow nesting costs both scanners time quadratic in the depth (a possible simple
        # key per level, each looked at for every token): read the events of the text only up to
        # the bracket that goes past the limit, which says where, at once. A bracket inside a
        # quoted string counts here too: then the events find no such depth and the whole text
        # is composed as usual.
        error = _nesting_error(text[: too_deep + 1])
        if error is not None:
            raise error
    try:
        parser = loader_class(text)
    except yaml.YAMLError as exc:  # the pure reader refuses control characters at once
        raise _yaml_error(exc) from None
    try:
        root: yaml.Node | None = parser.get_single_node()
        return root
    except yaml.YAMLError as exc:
        # libyaml refuses flow nesting past its own limit (1000 levels in PyYAML 6.0.4's wheels)
        # before our check sees the tree: say what our limit says, whichever parser refused it
        raise _nesting_error(text) or _yaml_error(exc) from None
    except RecursionError:  # the pure-Python composer recurses once per level
        raise _nesting_error(text) or InputError(
            f"nested more than {MAX_DEPTH} levels deep") from None
    finally:
        parser.dispose()


_BRACKETS = re.compile(r"[\[\]{}]")


def _bracket_past(text: str, limit: int) -> int | None:
    """The offset of the first opening bracket that nests more than ``limit`` deep in ``text``,
    or None (brackets inside quotes count too: a cheap upper bound of the flow nesting)."""
    depth = 0
    for match in _BRACKETS.finditer(text):
        if match.group() in "[{":
            depth += 1
            if depth > limit:
                return match.start()
        elif depth:
            depth -= 1
    return None


def _nesting_error(text: str, max_depth: int = MAX_DEPTH) -> InputError | None:
    """The error :func:`check_tree` would give for a document nested more than ``max_depth``
    levels, found from the events of the pure-Python parser (no tree is built, nothing recurses;
    libyaml's scanner looks ahead to the end of a flow collection before it gives the first
    event, so it would fail before reaching the level), or None when the document is not that
    deep before the parser stops."""
    import yaml

    try:
        parser = yaml.SafeLoader(text)
    except yaml.YAMLError:  # the pure reader refuses control characters at once
        return None
    depth = 0
    try:
        while parser.check_event():
            event = parser.get_event()  # type: ignore[no-untyped-call]  # unannotated in types-PyYAML
            if isinstance(event, yaml.CollectionEndEvent):
                depth -= 1
            elif isinstance(event, (yaml.CollectionStartEvent, yaml.ScalarEvent, yaml.AliasEvent)):
                # as in check_tree: a value's level is the number of collections around it
                if depth > max_depth:
                    mark = event.start_mark
                    return InputError(f"nested more than {max_depth} levels deep",
                                      line=mark.line + 1 if mark is not None else None)
                if isinstance(event, yaml.CollectionStartEvent):
                    depth += 1
    except (yaml.YAMLError, RecursionError):
        return None
    finally:
        parser.dispose()
    return None


def construct(root: yaml.Node, loader: type | None = None) -> Any:
    """Plain Python data for a node tree :func:`check_tree` accepted."""
    with gc_paused():
        return _construct(root, loader)


def _construct(root: yaml.Node, loader: type | None) -> Any:
    import yaml

    loader_class = _loader(loader)
    constructor = loader_class("")
    try:
        return constructor.construct_document(root)
    except yaml.YAMLError as exc:
        raise _yaml_error(exc) from None
    except (RecursionError, ValueError, OverflowError) as exc:
        raise InputError(f"a value cannot be read: {exc}") from None
    finally:
        constructor.dispose()


def _yaml_error(exc: yaml.YAMLError) -> InputError:
    import yaml

    if isinstance(exc, yaml.MarkedYAMLError):
        mark = exc.problem_mark or exc.context_mark
        line = mark.line + 1 if mark is not None else None
        column = f", column {mark.column + 1}" if mark is not None else ""
        reason = " ".join(p for p in (exc.context, exc.problem) if p)
        return InputError(f"YAML syntax error{column}: {reason}", line=line)
    if isinstance(exc, yaml.reader.ReaderError):
        return InputError(f"YAML syntax error: {exc.reason} (character {exc.character!r} at position {exc.position}); "
                          "control characters are not allowed in YAML")
    return InputError(f"YAML error: {exc}")


_STR_TAG = "tag:yaml.org,2002:str"


def check_tree(root: yaml.Node, *, max_depth: int = MAX_DEPTH, max_values: int = MAX_VALUES) -> None:
    """Keys are unique strings, nesting and expanded size are bounded (iterative: no recursion,
    and each node, however many aliases point at it, is looked at once)."""
    import yaml

    expanded: dict[int, int] = {}  # node id → number of values it expands to
    stack: list[tuple[yaml.Node, tuple[Any, ...], bool]] = [(root, (), False)]
    on_path: set[int] = set()
    while stack:
        node, where, children_done = stack.pop()
        key = id(node)
        if children_done:
            on_path.discard(key)
            total = 1 + sum(expanded[id(child)] for child in _children(node))
            if total > max_values:
                raise InputError(f"the document expands to more than {max_values:,} values through YAML aliases "
                                 "(an alias bomb?)", line=node.start_mark.line + 1, location=where)
            expanded[key] = total
            continue
        if key in expanded:
            continue
        if key in on_path:  # a recursive alias
            raise InputError("a YAML alias refers to a value that contains it", line=node.start_mark.line + 1,
                             location=where)
        if len(where) > max_depth:
            raise InputError(f"nested more than {max_depth} levels deep", line=node.start_mark.line + 1, location=where)
        on_path.add(key)
        stack.append((node, where, True))
        if isinstance(node, yaml.MappingNode):
            seen: dict[str, int] = {}
            for k, v in node.value:
                if not isinstance(k, yaml.ScalarNode) or k.tag != _STR_TAG:
                    shown = shorten(k.value) if isinstance(k, yaml.ScalarNode) else "a list or mapping"
                    raise InputError(f"mapping keys must be strings, got {shown}; quote it (\"{shown}\") if it is a name",
                                     line=k.start_mark.line + 1, location=where)
                if k.value in seen:
                    raise InputError(f"duplicate key {shorten(k.value)} (first at line {seen[k.value]}); YAML would "
                                     "silently keep only the last one", line=k.start_mark.line + 1,
                                     location=where + (k.value,))
                seen[k.value] = k.start_mark.line + 1
                stack.append((v, where + (k.value,), False))
        elif isinstance(node, yaml.SequenceNode):
            for index, item in enumerate(node.value):
                stack.append((item, where + (index,), False))


def _children(node: yaml.Node) -> list[yaml.Node]:
    import yaml

    if isinstance(node, yaml.MappingNode):
        return [v for _k, v in node.value]
    if isinstance(node, yaml.SequenceNode):
        return list(node.value)
    return []


def shorten(value: Any, limit: int = 80) -> str:
    """``repr(value)``, cut to ``limit`` characters for messages."""
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def shorten_with_digest(value: Any, limit: int = 80) -> str:
    """``repr(value)``, or when that is longer than ``limit``: its start and end, its length and
    a digest of all of it, so that two long values that differ anywhere read differently
    (``'aaaa...aaaa' (1,000,000 characters, sha256 3f1c...)``) and a report of a megabyte
    parameter stays one short line."""
    text = repr(value)
    if len(text) <= limit:
        return text
    digest = hashlib.sha256(text.encode("utf-8", "surrogatepass")).hexdigest()[:12]
    length = len(value) if isinstance(value, (str, bytes, list, tuple, dict)) else len(text)
    unit = "characters" if isinstance(value, str) else "bytes" if isinstance(value, bytes) else \
        "items" if isinstance(value, (list, tuple, dict)) else "characters shown"
    half = max(8, (limit - 3) // 2)
    return f"{text[:half]}...{text[-half:]} ({length:,} {unit}, sha256 {digest})"


class Short:
    """A value whose ``repr`` is cut for messages (``f"{Short(v)!r}"``); other uses see the value."""

    def __init__(self, value: Any, limit: int = 80) -> None:
        self.value = value
        self.limit = limit

    def __repr__(self) -> str:
        return shorten(self.value, self.limit)

    def __iter__(self) -> Any:
        return iter(self.value)
