"""Contract files at a git revision, for ``rmw-introspect diff --against REF`` (``check.gate``).

git is the only tool: ``rev-parse`` resolves REF (a branch, tag or commit, or ``A...B``: their
merge base, as ``git diff`` reads it), ``ls-files``/``ls-tree`` list the files of the work tree
and of REF, ``diff --name-status -M`` finds renamed ones, and one ``cat-file --batch`` process
reads every file at REF. A file is a contract by its content (``model.contract_kind``), whatever
its name: every tracked YAML file is read now, and at REF only those that differ from the work
tree (an unchanged file is at REF what it is now). Paths inside this module are relative to the repository's top
(git's "full names"); :meth:`Revision.shown` gives them as people read them, relative to the
directory the command runs in. Every failure a user can cause is a :class:`RevisionError` that
says what to do next.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import RevisionError
from ..model import contract_kind
from ..model.contract_kind import Kind
from .contract_files import classify

#: what a CI job must fetch for REF to be there, said in every message about a missing revision
FETCH_ADVICE = ("fetch it first: `git fetch origin <branch>` (in GitHub Actions `actions/checkout` with "
                "`fetch-depth: 0`; in GitLab CI `GIT_DEPTH: 0`), docs/ci.md")


@dataclass(frozen=True)
class Survey:
    """What the gate looked at: the contracts git tracks under ``cwd`` now and at REF (full name:
    kind), and the tracked YAML files it decided were not contracts (full names, now)."""

    now: dict[str, Kind]
    at_ref: dict[str, Kind]
    skipped: list[str]


@dataclass(frozen=True)
class FileChange:
    """How a file differs between REF and the work tree: ``status`` is git's letter (A, D, M, R)."""

    status: str
    old: str | None  # at REF (None: added)
    new: str | None  # in the work tree (None: removed)


@dataclass
class Revision:
    """REF resolved in the repository that holds ``cwd``."""

    ref: str
    commit: str
    top: Path
    cwd: Path
    shallow: bool = False
    _texts: dict[str, str | None] = field(default_factory=dict, repr=False)
    _survey: Survey | None = field(default=None, repr=False)
    _changes: list[FileChange] | None = field(default=None, repr=False)

    def shown(self, full_name: str) -> str:
        """A repository path as a message shows it: relative to the directory the command runs in."""
        return os.path.relpath(self.top / full_name, self.cwd)

    def full_name(self, path: str | Path) -> str:
        """A path given on the command line (relative to ``cwd``, or absolute) as git names it."""
        absolute = Path(os.path.normpath(self.cwd / path))
        try:
            return absolute.relative_to(self.top).as_posix()
        except ValueError:
            raise RevisionError(f"{path} is outside the git repository at {self.top}: `diff --against` compares the "
                                "repository's own contract files; name files inside it") from None

    def at_ref(self, full_name: str) -> str:
        """``REF:path`` as messages name a file at REF."""
        return f"{self.ref}:{self.shown(full_name)}"

    def survey(self) -> Survey:
        """Every contract git tracks under ``cwd`` now and at REF, found by its content."""
        if self._survey is not None:
            return self._survey
        tracked = _git(["ls-files", "-z", "--full-name", "--", "."], self.cwd).split("\0")
        present = [name for name in tracked if contract_kind.is_candidate(name) and (self.top / name).is_file()]
        now, skipped = classify(present, lambda name: contract_kind.kind_of_file(self.top / name))
        at_ref_names = _git(["ls-tree", "-r", "-z", "--name-only", "--full-name", self.commit, "--", "."],
                            self.cwd).split("\0")
        differ = {change.old for change in self.changes() if change.old is not None}
        # a file that does not differ from the work tree is at REF what it is now: read only the others
        self.read(name for name in at_ref_names if name in differ and contract_kind.is_candidate(name))

        def kind_at_ref(name: str) -> Kind | None:
            if name not in differ:
                return now.get(name)
            text = self._texts.get(name)
            return contract_kind.kind_of_text(text, name) if text is not None else None

        at_ref, _ = classify(at_ref_names, kind_at_ref)
        self._survey = Survey(now=now, at_ref=at_ref, skipped=skipped)
        return self._survey

    def contracts_now(self) -> list[str]:
        """The contract files git tracks under ``cwd`` (as they are in the work tree)."""
        return sorted(self.survey().now)

    def contracts_at_ref(self) -> list[str]:
        """The contract files under ``cwd`` at REF."""
        return sorted(self.survey().at_ref)

    def exists_at_ref(self, full_names: Iterable[str]) -> set[str]:
        """Those of these files that exist at REF (whatever they hold; read with the others)."""
        names = list(full_names)
        self.read(names)
        return {name for name in names if self._texts.get(name) is not None}

    def changes(self) -> list[FileChange]:
        """Every file under ``cwd`` that differs between REF and the work tree, renames found as
        ``git diff -M`` finds them (50 % similar content)."""
        if self._changes is not None:
            return self._changes
        out = _git(["diff", "-z", "--no-color", "--no-ext-diff", "--name-status", "-M", self.commit, "--", "."],
                   self.cwd)
        words = out.split("\0")
        changes: list[FileChange] = []
        i = 0
        while i < len(words) - 1:
            status = words[i][:1]
            if status in ("R", "C"):
                changes.append(FileChange(status, words[i + 1], words[i + 2]))
                i += 3
                continue
            path = words[i + 1]
            changes.append(FileChange(status, None if status == "A" else path, None if status == "D" else path))
            i += 2
        self._changes = changes
        return changes

    def read(self, full_names: Iterable[str]) -> None:
        """Read these files at REF (one ``git cat-file --batch`` for all); :meth:`text` gives them."""
        wanted = [name for name in dict.fromkeys(full_names) if name not in self._texts]
        if not wanted:
            return
        request = "".join(f"{self.commit}:{name}\n" for name in wanted).encode()
        result = subprocess.run(["git", "cat-file", "--batch"], cwd=self.top, input=request,
                                capture_output=True, check=False, timeout=120)
        if result.returncode != 0:
            raise RevisionError(f"git cat-file could not read the contracts at {self.ref}: "
                                f"{result.stderr.decode(errors='replace').strip()}")
        data, offset = result.stdout, 0
        for name in wanted:
            end = data.index(b"\n", offset)
            header = data[offset:end].decode()
            offset = end + 1
            if header.endswith(" missing") or " blob " not in header:
                self._texts[name] = None
                continue
            size = int(header.rsplit(" ", 1)[1])
            self._texts[name] = data[offset:offset + size].decode("utf-8", errors="replace")
            offset += size + 1

    def text(self, full_name: str) -> str | None:
        """The file's text at REF (None: it did not exist there)."""
        self.read([full_name])
        return self._texts[full_name]


def _git(args: Sequence[str], cwd: Path, *, check: bool = True) -> str:
    result = subprocess.run(["git", *args], cwd=cwd, capture_output=True, text=True, check=False, timeout=120)
    if check and result.returncode != 0:
        raise RevisionError(f"`git {' '.join(args)}` failed in {cwd}: {result.stderr.strip()}")
    return result.stdout


def _commit(ref: str, cwd: Path) -> str | None:
    result = subprocess.run(["git", "rev-parse", "--verify", "--quiet", "--end-of-options", f"{ref}^{{commit}}"],
                            cwd=cwd, capture_output=True, text=True, check=False, timeout=60)
    return result.stdout.strip() if result.returncode == 0 else None


def _missing(ref: str, shallow: bool) -> RevisionError:
    if shallow:
        return RevisionError(f"revision {ref!r} is not in this shallow clone (it holds only the latest commits): "
                             + FETCH_ADVICE)
    return RevisionError(f"revision {ref!r} does not exist in this repository: name a branch, tag or commit "
                         f"(`git branch -a` lists the branches); in CI the base branch may not be fetched: "
                         + FETCH_ADVICE)


def open_revision(ref: str, cwd: str | Path | None = None) -> Revision:
    """Resolve ``ref`` in the repository holding ``cwd`` (default: the current directory).
    ``A...B`` is the merge base of A and B (B defaults to HEAD), as in ``git diff A...B``."""
    here = Path(cwd if cwd is not None else os.getcwd()).absolute()
    if not ref or ref.startswith("-"):
        raise RevisionError(f"--against {ref!r}: give a git revision (a branch, tag, commit, or BASE...HEAD)")
    if shutil.which("git") is None:
        raise RevisionError("git is not installed: `diff --against` reads the contracts at a revision with git; "
                            "install git (apt-get install git) or compare two files with `diff OLD NEW`")
    probe = subprocess.run(["git", "rev-parse", "--show-toplevel", "--is-shallow-repository"], cwd=here,
                           capture_output=True, text=True, check=False, timeout=60)
    if probe.returncode != 0:
        raise RevisionError(f"{here} is not inside a git repository: `diff --against {ref}` compares the contracts "
                            "with their versions at a git revision; run it in a clone of the repository (in CI, "
                            "check the repository out with git), or compare two files with `diff OLD NEW`")
    top_line, shallow_line = (probe.stdout.splitlines() + ["", ""])[:2]
    top, shallow = Path(top_line), shallow_line.strip() == "true"
    if ".." in ref and "..." not in ref:
        raise RevisionError(f"--against {ref}: a range of two dots compares two commits, but the gate compares the "
                            f"work tree with one revision: give one (`{ref.split('..')[0] or 'HEAD'}`), or "
                            f"`{ref.replace('..', '...')}` for the merge base of the two")
    if "..." in ref:
        left, _, right = ref.partition("...")
        left, right = left or "HEAD", right or "HEAD"
        ends = []
        for side in (left, right):
            commit = _commit(side, here)
            if commit is None:
                raise _missing(side, shallow)
            ends.append(commit)
        base = subprocess.run(["git", "merge-base", *ends], cwd=here, capture_output=True, text=True, check=False,
                              timeout=60)
        if base.returncode != 0:
            if shallow:
                raise RevisionError(f"{left} and {right} have no merge base in this shallow clone (the history "
                                    "between them was not fetched): " + FETCH_ADVICE)
            raise RevisionError(f"{left} and {right} have no common history: `{ref}` has no merge base; "
                                f"compare with {left} itself (`--against {left}`)")
        return Revision(ref=ref, commit=base.stdout.strip(), top=top, cwd=here, shallow=shallow)
    commit = _commit(ref, here)
    if commit is None:
        raise _missing(ref, shallow)
    return Revision(ref=ref, commit=commit, top=top, cwd=here, shallow=shallow)
