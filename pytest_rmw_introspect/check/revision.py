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

What git stores is read as git stores it (issue 50): names as bytes (``-z``, decoded with
surrogateescape as the file system decodes them, shown escaped), files at REF by object id (a
name with a newline shifts nothing), their sizes asked (``cat-file --batch-check``) before
anything is read. The checks the work tree's files get apply at REF too: the size limit of
``model.untrusted``, symbolic links (mode 120000) followed inside the repository only, git LFS
pointers named, UTF-8; a file that fails one is not read, and :meth:`Revision.problem_at_ref`
(:meth:`Revision.problem_now` in the work tree) says why.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import InputError, RevisionError
from ..model import contract_kind, untrusted
from ..model.contract_kind import Kind
from .contract_files import classify, display, lfs_pointer, read_tracked

#: what a CI job must fetch for REF to be there, said in every message about a missing revision
FETCH_ADVICE = ("fetch it first: `git fetch origin <branch>` (in GitHub Actions `actions/checkout` with "
                "`fetch-depth: 0`; in GitLab CI `GIT_DEPTH: 0`), docs/ci.md")


@dataclass(frozen=True)
class Survey:
    """What the gate looked at: the contracts git tracks under ``cwd`` now and at REF (full name:
    kind), the tracked YAML files it decided were not contracts (full names, now), and the ones it
    could not read (full name: why, as the end of a sentence about the file)."""

    now: dict[str, Kind]
    at_ref: dict[str, Kind]
    skipped: list[str]
    unread: dict[str, str] = field(default_factory=dict)


@dataclass(frozen=True)
class FileChange:
    """How a file differs between REF and the work tree: ``status`` is git's letter (A, D, M, R)."""

    status: str
    old: str | None  # at REF (None: added)
    new: str | None  # in the work tree (None: removed)


@dataclass(frozen=True)
class TreeEntry:
    """A file of REF's tree as ``git ls-tree`` lists it."""

    mode: str  # 100644, 100755, 120000 (a symbolic link), 160000 (a submodule)
    kind: str  # blob (a file or a link), commit (a submodule)
    oid: str


#: how many symbolic links at REF are followed, one to the next, before giving up
_MAX_LINKS = 8


@dataclass
class Revision:
    """REF resolved in the repository that holds ``cwd``. Names are read from git as bytes (``-z``)
    and decoded with surrogateescape (``os.fsdecode``), the same way now and at REF, so that a name
    that is not UTF-8 or holds a newline is one name everywhere; files at REF are read by object id."""

    ref: str
    commit: str
    top: Path
    cwd: Path
    shallow: bool = False
    _texts: dict[str, str | None] = field(default_factory=dict, repr=False)
    _problems: dict[str, str] = field(default_factory=dict, repr=False)
    _tree: dict[str, TreeEntry] | None = field(default=None, repr=False)
    _now: dict[str, str] = field(default_factory=dict, repr=False)
    _now_problems: dict[str, str] = field(default_factory=dict, repr=False)
    _survey: Survey | None = field(default=None, repr=False)
    _changes: list[FileChange] | None = field(default=None, repr=False)
    _changed: set[str] | None = field(default=None, repr=False)

    def shown(self, full_name: str) -> str:
        """A repository path as a message shows it: relative to the directory the command runs in
        (bytes that are not UTF-8 and control characters escaped: ``contract_files.display``)."""
        return display(os.path.relpath(self.top / full_name, self.cwd))

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
        """Every contract git tracks under ``cwd`` now and at REF, found by its content. A file that
        cannot be read (a FIFO, too large, a git LFS pointer, a symbolic link out of the repository)
        is a contract when its name says so or the file on the other side is one; the others are in
        ``unread``."""
        if self._survey is not None:
            return self._survey
        tracked = _names(_git_bytes(["ls-files", "-z", "--full-name", "--", "."], self.cwd))
        present = [name for name in tracked if contract_kind.is_candidate(name) and os.path.lexists(self.top / name)]
        now, skipped = classify(present, self.kind_now)
        tree = self._ref_tree()
        differ = {change.old for change in self.changes() if change.old is not None}
        renamed = {change.old: change.new for change in self.changes() if change.old and change.new}
        # a file that does not differ from the work tree is at REF what it is now: read only the others
        self.read(name for name in tree if name in differ and contract_kind.is_candidate(name))

        def kind_at_ref(name: str) -> Kind | None:
            if name not in differ:
                return now.get(name)
            text = self._texts.get(name)
            if text is not None:
                return contract_kind.kind_of_text(text, name)
            if name in self._problems:
                return contract_kind.kind_of_name(name) or now.get(renamed.get(name) or name)
            return None

        at_ref, _ = classify(tree, kind_at_ref)
        for name in [name for name in present if name in self._now_problems and name in at_ref]:
            now[name] = at_ref[name]  # a contract at REF that cannot be read now: compared, and said why
        unread = {name: why for name, why in self._now_problems.items() if name in present and name not in now}
        for name, why in self._problems.items():  # (each says "at REF")
            if name in differ and name not in at_ref and contract_kind.is_candidate(name):
                unread.setdefault(name, why)
        self._survey = Survey(now=now, at_ref=at_ref, skipped=[name for name in skipped if name not in unread],
                              unread=unread)
        return self._survey

    def kind_now(self, name: str) -> Kind | None:
        """The kind of contract the work tree's file is (one that cannot be read: by its name)."""
        text = self.text_now(name)
        return contract_kind.kind_of_text(text, name) if text is not None else contract_kind.kind_of_name(name)

    def text_now(self, full_name: str) -> str | None:
        """The work tree's file as the gate reads it (``contract_files.read_tracked``), or None: it
        is not there, or cannot be read (:meth:`problem_now` says why)."""
        if full_name not in self._now and full_name not in self._now_problems:
            try:
                self._now[full_name] = read_tracked(self.top, full_name)
            except FileNotFoundError:
                self._now_problems[full_name] = "does not exist"
            except (OSError, InputError) as exc:
                self._now_problems[full_name] = str(exc)
        return self._now.get(full_name)

    def problem_now(self, full_name: str) -> str | None:
        """Why the work tree's file cannot be read (the end of a sentence about it), or None."""
        self.text_now(full_name)
        return self._now_problems.get(full_name)

    def contracts_now(self) -> list[str]:
        """The contract files git tracks under ``cwd`` (as they are in the work tree)."""
        return sorted(self.survey().now)

    def contracts_at_ref(self) -> list[str]:
        """The contract files under ``cwd`` at REF."""
        return sorted(self.survey().at_ref)

    def exists_at_ref(self, full_names: Iterable[str]) -> set[str]:
        """Those of these files that exist at REF (whatever they hold, readable or not)."""
        names = list(full_names)
        self.read(names)
        return {name for name in names if self._texts.get(name) is not None or name in self._problems}

    def changed(self, full_name: str) -> bool:
        """Whether the file differs between REF and the work tree (by git: a file kept in LFS is
        compared by its content, as ``git diff`` compares it); a file outside ``cwd`` counts as changed."""
        if not self._under_cwd(full_name):
            return True
        if self._changed is None:
            self._changed = {name for change in self.changes() for name in (change.old, change.new) if name}
        return full_name in self._changed

    def _under_cwd(self, full_name: str) -> bool:
        inside = Path(os.path.relpath(self.cwd, self.top)).as_posix()
        return inside == "." or full_name.startswith(inside + "/")

    def changes(self) -> list[FileChange]:
        """Every file under ``cwd`` that differs between REF and the work tree, renames found as
        ``git diff -M`` finds them (50 % similar content)."""
        if self._changes is not None:
            return self._changes
        words = _names(_git_bytes(["diff", "-z", "--no-color", "--no-ext-diff", "--name-status", "-M", self.commit,
                                   "--", "."], self.cwd), keep_empty=True)
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

    def _ref_tree(self) -> dict[str, TreeEntry]:
        """Every file under ``cwd`` at REF (``git ls-tree -r -z``: names as bytes, with their modes;
        the sizes of those read are asked for then, not of every file of a large tree)."""
        if self._tree is None:
            self._tree = _tree_entries(_git_bytes(["ls-tree", "-r", "-z", "--full-name", self.commit, "--", "."],
                                                  self.cwd))
        return self._tree

    def _entries(self, full_names: Sequence[str]) -> dict[str, TreeEntry]:
        """The tree entries of these files at REF (those that exist there), wherever they are."""
        tree = self._ref_tree()
        found = {name: tree[name] for name in full_names if name in tree}
        others = [name for name in full_names if name not in tree and not self._under_cwd(name)]
        if others:
            listed = _tree_entries(_git_bytes(["--literal-pathspecs", "ls-tree", "-z", "--full-name", self.commit,
                                               "--", *others], self.top))
            found.update((name, entry) for name, entry in listed.items() if name in others)
        return found

    def read(self, full_names: Iterable[str]) -> None:
        """Read these files at REF (one ``git cat-file --batch`` for all, by object id: a name that
        holds a newline cannot shift the others); :meth:`text` gives them, :meth:`problem_at_ref`
        says why one cannot be read (too large, a symbolic link out of the repository, a git LFS
        pointer, not UTF-8: the checks the work tree's files get)."""
        wanted = [name for name in dict.fromkeys(full_names) if name not in self._texts and name not in self._problems]
        if not wanted:
            return
        entries = self._entries(wanted)
        targets: dict[str, str] = {}  # name -> the file it is at REF (itself, or where its links lead)
        for name in wanted:
            entry = entries.get(name)
            if entry is None or entry.kind != "blob":
                self._texts[name] = None  # not there (or a submodule: no file of this repository)
                continue
            target, why = self._follow(name, entry)
            if why is not None:
                self._problems[name] = why
                continue
            target_entry = self._entries([target]).get(target) if target != name else entry
            assert target_entry is not None
            targets[name] = target_entry.oid
        sizes = self._sizes(set(targets.values()))
        for name, oid in list(targets.items()):
            if sizes[oid] > untrusted.MAX_FILE_BYTES:
                self._problems[name] = (f"is {sizes[oid]:,} bytes at {self.ref}, more than the "
                                        f"{untrusted.MAX_FILE_BYTES:,} bytes a contract may be (as in the work tree): "
                                        "not read; compare with a later revision (--against COMMIT)")
                del targets[name]
        blobs = self._blobs(set(targets.values()))
        for name, oid in targets.items():
            try:
                text = blobs[oid].decode("utf-8")
            except UnicodeDecodeError as exc:
                self._problems[name] = f"is not UTF-8 text at {self.ref} (byte {exc.start}: {exc.reason})"
                continue
            why = lfs_pointer(text)
            if why is not None:
                self._problems[name] = why.replace("not the file:", f"not the file, at {self.ref}:", 1)
                continue
            self._texts[name] = text

    def _follow(self, name: str, entry: TreeEntry) -> tuple[str, str | None]:
        """Where the file ``name`` leads at REF: itself, or the file its symbolic links lead to
        inside the repository (as the work tree follows them); or why it is not read."""
        seen = [name]
        while entry.mode == "120000":
            link = os.fsdecode(self._blobs({entry.oid})[entry.oid])
            target = os.path.normpath(os.path.join(os.path.dirname(seen[-1]), link))
            if os.path.isabs(link) or target == ".." or target.startswith("../"):
                return name, (f"is a symbolic link at {self.ref} to {display(link)}, outside the repository: not "
                              "followed (the gate compares what the repository holds); commit the contract itself")
            found = self._entries([target]).get(target)
            if found is None or found.kind != "blob" or target in seen or len(seen) > _MAX_LINKS:
                return name, (f"is a symbolic link at {self.ref} to {display(link)}, which is no file of the "
                              "repository there: commit the contract itself")
            seen.append(target)
            entry = found
        return seen[-1], None

    def _blobs(self, oids: set[str]) -> dict[str, bytes]:
        """The content of these blobs (one ``git cat-file --batch``)."""
        return {oid: content for oid, _, content in self._cat_file(oids, "--batch")}

    def _sizes(self, oids: set[str]) -> dict[str, int]:
        """The size of these blobs (one ``git cat-file --batch-check``: nothing is read)."""
        return {oid: size for oid, size, _ in self._cat_file(oids, "--batch-check")}

    def _cat_file(self, oids: set[str], mode: str) -> list[tuple[str, int, bytes]]:
        """(object id, size, content: none for ``--batch-check``) of each object, by ``git cat-file MODE``."""
        if not oids:
            return []
        ordered = sorted(oids)
        result = subprocess.run(["git", "cat-file", mode], cwd=self.top,
                                input="".join(f"{oid}\n" for oid in ordered).encode(), capture_output=True,
                                check=False, timeout=120)
        if result.returncode != 0:
            raise RevisionError(f"git cat-file could not read the contracts at {self.ref}: "
                                f"{result.stderr.decode(errors='replace').strip()}")
        data, offset, out = result.stdout, 0, []
        for oid in ordered:
            end = data.index(b"\n", offset)
            header = data[offset:end].decode("ascii", "replace").split()
            offset = end + 1
            if len(header) != 3:  # "<oid> missing": the object is not in this clone
                raise RevisionError(f"git cat-file found no object {oid} at {self.ref}: " + FETCH_ADVICE)
            size = int(header[2])
            if mode == "--batch":
                out.append((oid, size, data[offset:offset + size]))
                offset += size + 1
            else:
                out.append((oid, size, b""))
        return out

    def text(self, full_name: str) -> str | None:
        """The file's text at REF (None: it did not exist there, or cannot be read: :meth:`problem_at_ref`)."""
        self.read([full_name])
        return self._texts.get(full_name)

    def problem_at_ref(self, full_name: str) -> str | None:
        """Why the file cannot be read at REF (the end of a sentence about it), or None."""
        self.read([full_name])
        return self._problems.get(full_name)


def _names(out: bytes, *, keep_empty: bool = False) -> list[str]:
    """The NUL-separated names of git's ``-z`` output, decoded as the file system decodes names
    (surrogateescape: a name that is not UTF-8 is still one name, and opens the same file)."""
    words = [os.fsdecode(word) for word in out.split(b"\0")]
    return words if keep_empty else [word for word in words if word]


def _tree_entries(out: bytes) -> dict[str, TreeEntry]:
    """``git ls-tree -z`` records (``MODE TYPE OID\tNAME``) by name."""
    entries: dict[str, TreeEntry] = {}
    for record in out.split(b"\0"):
        if not record:
            continue
        meta, _, raw_name = record.partition(b"\t")
        mode, kind, oid = meta.decode("ascii").split()
        entries[os.fsdecode(raw_name)] = TreeEntry(mode, kind, oid)
    return entries


def _git_bytes(args: Sequence[str], cwd: Path) -> bytes:
    result = subprocess.run(["git", *args], cwd=cwd, capture_output=True, check=False, timeout=120)
    if result.returncode != 0:
        raise RevisionError(f"`git {' '.join(args)}` failed in {cwd}: {result.stderr.decode(errors='replace').strip()}")
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
                           capture_output=True, check=False, timeout=60)
    if probe.returncode != 0:
        raise RevisionError(f"{here} is not inside a git repository: `diff --against {ref}` compares the contracts "
                            "with their versions at a git revision; run it in a clone of the repository (in CI, "
                            "check the repository out with git), or compare two files with `diff OLD NEW`")
    # (bytes: the repository's own path may be a name that is not UTF-8)
    top_line, shallow_line = ([os.fsdecode(line) for line in probe.stdout.splitlines()] + ["", ""])[:2]
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
