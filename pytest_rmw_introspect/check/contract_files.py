"""The contract files under a directory, found by their content (``model.contract_kind``),
whatever their names: for ``rmw-introspect contracts`` (the GitHub action's check step), and for
any command that is given a directory instead of files.

In a git repository the files are those git knows of under the directory: tracked, and untracked
but not ignored (a contract written a minute ago and not yet added is found; a build tree that
``.gitignore`` names is not). Elsewhere every file below it, except hidden directories and the
trees colcon and Python leave behind (``build``, ``install``, ``log``, ``__pycache__``, ...).
Only YAML files (and NoDL JSON) are read; the others are not looked at. The gate lists the
tracked files of a revision itself (``check.revision``) and sorts them with :func:`classify`.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from collections.abc import Callable, Collection, Iterable
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import InputError
from ..model import contract_kind, untrusted
from ..model.contract_kind import Kind

#: why a YAML file is not a contract, as reports say it
NOT_A_CONTRACT = "no top-level contract_version:, system_version: or nodl_version: key"
#: how many of the YAML files that are not contracts the text and Markdown reports name (JSON: all)
SKIPPED_SHOWN = 5
#: the first line of a git LFS pointer file (what git stores for a file kept in LFS)
LFS_POINTER_START = "version https://git-lfs.github.com/spec/v1\n"
#: what to do about a contract kept in git LFS, said wherever one is met
LFS_ADVICE = ("the gate reads files as git stores them: run `git lfs pull` before it (GitHub Actions: "
              "actions/checkout with `lfs: true`), and keep contracts out of LFS (at the base revision git "
              "stores only the pointer): `git lfs untrack PATTERN` and commit them again (docs/known-limits.md)")
#: directories never walked outside a git repository (colcon's and Python's leftovers)
_NOT_WALKED = frozenset({"build", "install", "log", "__pycache__", "node_modules", "site-packages"})


@dataclass
class Listing:
    """The contracts under a directory (paths relative to it, posix) by kind, the YAML files that
    are not contracts, and how they were found."""

    directory: Path
    contracts: dict[str, Kind] = field(default_factory=dict)
    skipped: list[str] = field(default_factory=list)
    how: str = "the files git knows of there"
    #: the YAML files it could not read (name: why, the end of a sentence about the file) and whose
    #: names do not say they are contracts (a symbolic link out of the repository, an LFS pointer, a FIFO)
    unread: dict[str, str] = field(default_factory=dict)

    def of_kind(self, kinds: Collection[Kind] | None = None) -> list[str]:
        """The contract files of these kinds (all: None), sorted."""
        return sorted(name for name, kind in self.contracts.items() if kinds is None or kind in kinds)


def counted(n: int, kind: Kind | str) -> str:
    """``1 node contract``, ``2 system contracts``, ``3 contracts``."""
    if isinstance(kind, Kind):
        return f"{n} {kind.value if n == 1 else kind.plural}"
    return f"{n} {kind}{'' if n == 1 else 's'}"


def skipped_text(skipped: list[str], noun: str = "tracked YAML file", shown: int = SKIPPED_SHOWN) -> str:
    """``2 tracked YAML files: a.yaml, b.yaml`` (the first ``shown`` names, then how many more)."""
    names = ", ".join(display(name) for name in skipped[:shown]) + (f" and {len(skipped) - shown} more" if len(skipped) > shown else "")
    return f"{counted(len(skipped), noun)}: {names}"


def kinds_text(kinds: Iterable[Kind]) -> str:
    """``2 node contracts, 1 system contract``: how many of each kind (in ``Kind``'s order)."""
    seen = list(kinds)
    return ", ".join(counted(n, kind) for kind in Kind if (n := seen.count(kind)))


def classify(names: Iterable[str], kind_of: Callable[[str], Kind | None]) -> tuple[dict[str, Kind], list[str]]:
    """The candidates among ``names`` (YAML, NoDL JSON) sorted into contracts by kind and the files
    that are not contracts; ``kind_of`` reads one (``contract_kind.kind_of_file`` of its path)."""
    contracts: dict[str, Kind] = {}
    skipped: list[str] = []
    for name in sorted(name for name in names if name and contract_kind.is_candidate(name)):
        kind = kind_of(name)
        if kind is None:
            skipped.append(name)
        else:
            contracts[name] = kind
    return contracts, skipped


def lfs_pointer(text: str) -> str | None:
    """Why ``text`` cannot be read as a contract when it is a git LFS pointer (the sentence's end),
    else None."""
    if not text.startswith(LFS_POINTER_START) or len(text) > 1024:
        return None
    size = next((line.split()[1] for line in text.splitlines() if line.startswith("size ")), "?")
    return f"is a git LFS pointer (to a file of {size} bytes kept in LFS), not the file: {LFS_ADVICE}"


def display(name: str) -> str:
    """A file name as messages show it: bytes that are not UTF-8 (decoded with surrogateescape)
    as ``\\xff`` and control characters (a newline) escaped, so that every name prints, on one line."""
    if name.isprintable():
        return name
    raw = name.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")
    return "".join(c if c.isprintable() else c.encode("unicode_escape").decode("ascii") for c in raw)


def outside(top: Path, name: str) -> str | None:
    """Why the work tree's ``name`` is not read when it is a symbolic link that leads outside the
    repository at ``top`` (the sentence's end), else None."""
    real = Path(os.path.realpath(top / name))
    try:
        real.relative_to(os.path.realpath(top))
        return None
    except ValueError:
        return (f"is a symbolic link to {display(os.fsdecode(real))}, outside the repository: not followed (the gate "
                "compares what the repository holds); commit the contract itself instead of a link to it")


def read_tracked(top: Path, name: str) -> str:
    """The text of the work tree's file ``name`` (relative to ``top``) as the gate reads it: a
    symbolic link that leads outside the repository is not followed, a FIFO is refused unopened,
    the size is bounded, a git LFS pointer is named. Raises FileNotFoundError, or InputError whose
    text ends a sentence about the file ("is a FIFO ...")."""
    why = outside(top, name)
    if why is not None:
        raise InputError(why)
    try:
        text = untrusted.read_text(top / name)
    except InputError as exc:
        raise InputError(f"cannot be read: {exc}") from None
    why = lfs_pointer(text)
    if why is not None:
        raise InputError(why)
    return text


def find_contracts(directory: str | Path = ".") -> Listing:
    """Every contract under ``directory`` by its content (see the module's text for which files)."""
    root = Path(directory)
    names = _git_files(root)
    how = "the files git knows of there (tracked, and untracked ones it does not ignore)"
    if names is None:
        names, how = _walk(root), "every file below it (not a git repository)"
    present = [name for name in names if os.path.lexists(root / name) and not (root / name).is_dir()]
    unread: dict[str, str] = {}

    def kind_of(name: str) -> Kind | None:
        try:
            return contract_kind.kind_of_text(read_tracked(root, name), name)
        except FileNotFoundError:
            return None  # (a dangling link, or gone since git listed it)
        except (OSError, InputError) as exc:
            kind = contract_kind.kind_of_name(name)
            if kind is None:
                unread[name] = str(exc)
            return kind

    contracts, skipped = classify(present, kind_of)
    return Listing(directory=root, contracts=contracts, skipped=[name for name in skipped if name not in unread],
                   how=how, unread=unread)


def _git_files(root: Path) -> list[str] | None:
    """The files git knows of under ``root`` (relative to it), or None: not in a git work tree."""
    if shutil.which("git") is None or not root.is_dir():
        return None
    result = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard", "--", "."],
                            cwd=root, capture_output=True, check=False, timeout=120)
    if result.returncode != 0:
        return None
    return list(dict.fromkeys(os.fsdecode(name) for name in result.stdout.split(b"\0") if name))


def _walk(root: Path) -> list[str]:
    out: list[str] = []
    for here, dirs, files in os.walk(root):
        dirs[:] = sorted(d for d in dirs if not d.startswith(".") and d not in _NOT_WALKED)
        rel = Path(here).relative_to(root)
        out += [(rel / name).as_posix() for name in files]
    return out
