"""The pull-request gate: every contract compared with its version at a git revision
(``rmw-introspect diff --against REF``, ``pytest --against REF``), without running anything.

The contracts (named, or every contract git tracks under the current directory, found by its
content whatever its name: node contracts, marker goldens, system contracts, NoDL documents;
``model.contract_kind``) are paired with their files at REF (``check.revision``): a renamed file
with its old name, a named one with the same file at REF, an added one with nothing (every node
added), a removed one with nothing now (the removal of everything it promised). A gate that
finds no contract at all is an error (:class:`NoContracts`): it never passes having compared
nothing. A contract it cannot read, now or at REF (a FIFO, too large, a git LFS pointer, a symbolic
link out of the repository: ``check.revision``), is an error of its own entry (exit 2), and so is a
tracked YAML file it cannot read that changed since REF; one that did not change is named on a
line of the report. The report's first line counts the contracts of each kind, the next names the tracked
YAML files that are not contracts. Each pair is compared by ``diff``'s core (``check.diff``:
``compare_contracts``, one :class:`~.diff.DiffResult` per pair; the contract's ``options:`` apply,
the command line's on top), then judged in this order:

1. consumers (``compare.consumers``): a node contract's changed interfaces against the system
   contracts at hand;
2. the interface versions (``compare.versioning``): changes covered by the bump are accepted,
   a missing bump is a BREAKING finding that says which version to write;
3. the contract's ``accept:`` entries, then a baseline (``--baseline``), as everywhere else.

What fails: findings at or above the threshold, which is ``breaking`` unless the command line
says otherwise (``--fail-on``): the contract's own ``fail_on`` is about captures that differ
from it, not about changes to the contract.
"""

from __future__ import annotations

import dataclasses
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..compare import acceptance, consumers, drift, rule_levels, versioning
from ..compare.baseline import Baseline
from ..compare.ci_report import ContractOutcome
from ..compare.drift import DriftItem
from ..errors import ContractError, NoContracts, RevisionError
from ..model import contract as contract_module
from ..model import contract_kind, system_contract
from ..model.contract import Contract
from ..model.contract_kind import Kind
from ..model.contract_shapes import ContractNodes
from ..model.interface_version import Bump
from ..model.locate import LineIndex
from ..model.vocabulary import Severity, parse_threshold
from .contract_files import NOT_A_CONTRACT, counted, kinds_text, skipped_text
from .diff import DiffResult, compare_contracts, said_middleware
from .pipeline import Layers, OptionLayer
from .revision import Revision, open_revision

#: the gate's threshold when the command line gives none
DEFAULT_FAIL_ON = "breaking"
_VERSION_LINE = re.compile(rf"^{contract_module.VERSION_KEY}\s*:", re.M)
#: a node of a contract written as updates write it (for the report's list of an unchanged file's nodes)
_NODE_LINE = re.compile(r"^  (/[^:\s]*):", re.M)


@dataclass
class GateResult:
    """Every contract against REF."""

    against: str
    commit: str
    contracts: list[DiffResult]
    systems: list[str]
    #: the tracked YAML files under the directory that are not contracts (shown names; none when
    #: the contracts were named)
    skipped: list[str] = field(default_factory=list)
    #: the tracked YAML files it could not read and that did not change (``shown why``): said, not failed
    unread: list[str] = field(default_factory=list)

    @property
    def failed(self) -> bool:
        return any(c.failed and c.error is None for c in self.contracts)

    @property
    def errors(self) -> list[DiffResult]:
        return [c for c in self.contracts if c.error is not None]

    def ordered(self) -> list[DiffResult]:
        """Errors and failing contracts first, then by their worst finding (breaking changes lead)."""
        def rank(c: DiffResult) -> tuple[int, int, str]:
            worst = max((item.severity for item in c.items), default=-2)
            return (0 if c.error else 1, -int(c.failed) * 10 - int(worst), c.shown)
        return sorted(self.contracts, key=rank)

    def title(self) -> str:
        return f"Interface changes against {self.against} ({self.commit[:12]})"

    def kinds(self) -> dict[Kind, int]:
        """How many contracts of each kind were compared (kinds in ``Kind``'s order, none left out)."""
        return {kind: n for kind in Kind
                if (n := sum(1 for c in self.contracts if c.kind is kind and c.status != "unreadable"))}

    def compared(self) -> str:
        """``3 contracts: 2 node contracts, 1 system contract; 1 changed, 2 unchanged``: the
        report's first words, in every format."""
        kinds = kinds_text(c.kind for c in self.contracts if c.status != "unreadable")
        statuses = {status: sum(1 for c in self.contracts if c.status == status)
                    for status in ("changed", "renamed", "added", "removed", "unchanged", "unreadable")}
        said = ", ".join(f"{n} {status}" for status, n in statuses.items() if n)
        return f"{counted(len(self.contracts), 'contract')}: {kinds}; {said}"

    def not_contracts(self) -> str | None:
        """The line that names the tracked YAML files the gate decided were not contracts."""
        if not self.skipped:
            return None
        return f"not contracts ({NOT_A_CONTRACT}): {skipped_text(self.skipped)}"

    def not_read(self) -> str | None:
        """The line that names the tracked YAML files the gate could not read (and need not have)."""
        if not self.unread:
            return None
        return f"not read ({counted(len(self.unread), 'tracked YAML file')}): " + "; ".join(self.unread)

    def intro(self) -> list[str]:
        """What the gate looked at, for the Markdown and GitHub reports."""
        return [self.compared()] + [said for said in (self.not_contracts(), self.not_read()) if said]

    def render_text(self) -> str:
        lines = [f"{self.title()}: {self.compared()}"]
        lines += [said for said in (self.not_contracts(), self.not_read()) if said]
        if self.systems:
            lines.append(f"consumers judged with {', '.join(self.systems)}")
        out = "\n".join(lines) + "\n"
        for contract in self.ordered():
            if contract.status == "unchanged" and not contract.notes:
                continue
            out += "\n" + contract.render_text()
        return out

    def to_json(self) -> dict[str, Any]:
        """What the gate looked at and found: ``items`` are the drift items (those of ``diff``,
        each naming its contract), ``not_contracts`` every tracked YAML file it passed over."""
        return {"against": self.against, "commit": self.commit, "contracts": len(self.contracts),
                "kinds": {kind.value: n for kind, n in self.kinds().items()}, "not_contracts": self.skipped,
                "not_read": self.unread,
                "items": [item for contract in self.ordered() for item in contract.to_json()]}

    def for_ci(self) -> list[ContractOutcome]:
        return [contract.for_ci() for contract in self.ordered()]


# ---------------------------------------------------------------------------- loading


def load_text(text: str, label: str) -> Contract:
    """A contract's text of any kind as the node contract a comparison reads (``label`` names it in
    messages; ``model.contract_kind``). Raises ContractError."""
    return contract_kind.loads(text, label)[0]


def _version_line(text: str) -> int | None:
    found = _VERSION_LINE.search(text)
    return text.count("\n", 0, found.start()) + 1 if found else None


def _lines(contract: Contract) -> LineIndex:
    lines = contract.lines()
    version_line = _version_line(contract.text)
    if version_line is not None:
        lines[(versioning.VERSION_NODE, "node", versioning.VERSION_NODE)] = version_line
    return lines


# ---------------------------------------------------------------------------- pairing


@dataclass(frozen=True)
class Pair:
    """A contract now and at REF, by full name (``None``: not there)."""

    old: str | None
    new: str | None

    @property
    def status(self) -> str:
        if self.old is None:
            return "added"
        if self.new is None:
            return "removed"
        return "renamed" if self.old != self.new else "changed"


def pairs(revision: Revision, named: Sequence[str | Path] = ()) -> list[Pair]:
    """The contracts to compare: those named (paths relative to the current directory, compared
    with the same file at REF, or the file it was renamed from), or every contract git tracks
    under it now or tracked at REF (by content: ``Revision.survey``). A renamed file is one pair."""
    changes = revision.changes()
    renamed_from = {c.new: c.old for c in changes if c.status == "R" and c.new and c.old}
    renamed_to = {old: new for new, old in renamed_from.items()}
    if named:
        fulls = [revision.full_name(given) for given in named]
        exists = revision.exists_at_ref(renamed_from.get(full, full) for full in fulls)
        out = []
        for given, full in zip(named, fulls, strict=True):
            now = full if os.path.lexists(revision.top / full) else None
            old = renamed_from.get(full, full)
            if now is None and old not in exists:
                raise RevisionError(f"{given} exists neither in the work tree nor at {revision.ref}: name a contract "
                                    "file of the repository (or leave the names out to compare every contract)")
            out.append(Pair(old if old in exists else None, now))
        return out
    exists = set(revision.contracts_at_ref())
    present = [name for name in revision.contracts_now() if os.path.lexists(revision.top / name)]
    found = [Pair(renamed_from.get(name, name) if renamed_from.get(name, name) in exists else None, name)
             for name in present]
    kept = {pair.old for pair in found}
    found += [Pair(name, None) for name in sorted(exists) if name not in kept and name not in renamed_to]
    return sorted(found, key=lambda pair: pair.new or pair.old or "")


def kind_of_pair(revision: Revision, pair: Pair) -> Kind:
    """What the pair's file is now (a removed one: what it was at REF); a named file that is no
    contract by its content is taken for what its name says, else a node contract (its loader says
    what is wrong with it)."""
    survey = revision.survey()
    if pair.new is not None:
        kind = survey.now.get(pair.new) or revision.kind_now(pair.new)
    else:
        assert pair.old is not None
        kind = survey.at_ref.get(pair.old) or contract_kind.kind_of_text(revision.text(pair.old) or "", pair.old)
    return kind or Kind.NODE


def no_contracts(revision: Revision) -> NoContracts:
    """The error of a gate that found nothing to compare: where it looked, what it passed over."""
    inside = Path(os.path.relpath(revision.cwd, revision.top)).as_posix()
    where = str(revision.cwd) + (f" ({inside}/ of the repository at {revision.top})" if inside != "." else "")
    skipped = revision.survey().skipped
    passed = (f"; it passed over {skipped_text([revision.shown(n) for n in skipped])} ({NOT_A_CONTRACT})"
              if skipped else "; git tracks no YAML file there")
    unread = revision.survey().unread
    if unread:
        passed += "; it could not read " + "; ".join(f"{revision.shown(n)} {why}" for n, why in sorted(unread.items()))
    return NoContracts(
        f"no contract to compare: git tracks no contract under {where}, neither in the work tree nor at {revision.ref} "
        f"({revision.commit[:12]}){passed}. A gate that compares nothing does not pass: run it where the "
        "contracts are (or name them), commit them first (`pytest --update-golden` writes marker goldens, "
        "`rmw-introspect capture ... -o FILE` node contracts), docs/ci.md")


# ---------------------------------------------------------------------------- the gate


def system_nodes(revision: Revision, named: Sequence[str | Path] | None) -> dict[str, ContractNodes]:
    """The nodes of the system contracts that judge consumers, by shown path: those named
    (``--against-system``; an invalid one is an error), else every valid one git tracks under the
    current directory."""
    out: dict[str, ContractNodes] = {}
    if named:
        for given in named:
            path = revision.top / revision.full_name(given)
            out[revision.shown(revision.full_name(given))] = system_contract.load(path).nodes
        return out
    for name, kind in revision.survey().now.items():
        text = revision.text_now(name) if kind is Kind.SYSTEM else None
        if text is not None:
            try:
                out[revision.shown(name)] = system_contract.loads(text, path=revision.shown(name)).nodes
            except ContractError:
                continue  # its own comparison reports it
    return out


def run(against: str, contracts: Sequence[str | Path] = (), *, systems: Sequence[str | Path] | None = None,
        options: Sequence[OptionLayer] = (), fail_on: str | None = None, baseline: Baseline | None = None,
        cwd: str | Path | None = None) -> GateResult:
    """Compare every contract with its version at ``against``. Raises RevisionError (no git
    repository, no such revision, a shallow clone without it) and ContractError (a ``--against-system``
    file that does not load); a contract that does not load now or at REF is an error of its own
    entry (``DiffResult.error``); no contract at all is :class:`NoContracts`."""
    revision = open_revision(against, cwd)
    found = pairs(revision, contracts)
    unreadable, unread = ([], []) if contracts else _unreadable(revision, found)
    if not found and not unreadable:
        raise no_contracts(revision)
    revision.read(pair.old for pair in found if pair.old is not None)
    consumers_at_hand = system_nodes(revision, systems)
    threshold = parse_threshold(fail_on or DEFAULT_FAIL_ON)
    compared = [compare_pair(revision, pair, consumers_at_hand, options=options, threshold=threshold,
                             baseline=baseline) for pair in found]
    return GateResult(against=against, commit=revision.commit, contracts=compared + unreadable,
                      systems=list(consumers_at_hand),
                      skipped=[] if contracts else [revision.shown(name) for name in revision.survey().skipped],
                      unread=unread)


def _unreadable(revision: Revision, found: Sequence[Pair]) -> tuple[list[DiffResult], list[str]]:
    """The tracked YAML files the gate could not read (``Survey.unread``) and paired with no
    contract: an error entry each for one that changed since REF and cannot be read now (it may be
    a contract that changed: the gate cannot tell), a line of the report for the others."""
    paired = {name for pair in found for name in (pair.old, pair.new) if name}
    errors: list[DiffResult] = []
    said: list[str] = []
    for name, why in sorted(revision.survey().unread.items()):
        if name in paired:
            continue
        shown = revision.shown(name)
        if revision.changed(name) and revision.text_now(name) is None:
            errors.append(DiffResult(
                shown=shown, against=None, revision=revision.ref, path=revision.top / name, status="unreadable",
                kind=contract_kind.kind_of_name(name) or Kind.NODE,
                error=f"{shown} {why}\n  It changed since {revision.ref} and the gate cannot tell whether it is a "
                      "contract: make it readable (or, if it is no contract, name the contracts to compare)"))
        else:
            said.append(f"{shown} {why}")
    return errors, said


def update_advice(against: str, path: str | Path, *, cwd: str | Path | None = None) -> str | None:
    """What the gate against ``against`` says of the ``interface_version`` of the contract at
    ``path`` once an update wrote it (``pytest --update-golden --against REF``): the version finding
    that fails it (the version to write), or that the version covers the changes, or the note of a
    version on one side only; None: nothing to say (no change against REF, a contract added since).
    Raises what :func:`run` raises, and RevisionError when the gate cannot compare it."""
    (compared,) = run(against, [path], cwd=cwd).contracts
    if compared.error is not None:
        raise RevisionError(compared.error)
    said = [item.message for item in compared.items if item.node == versioning.VERSION_NODE]
    said += compared.notes  # the gate's notes are those of the versions (compare.versioning)
    old, new = compared.versions
    if not said and compared.needs is not Bump.NONE and old is not None and new is not None:
        said.append(f"interface_version {old} → {new} covers the changes since {against}: it stays as it is")
    if not said:
        return None
    return f"{compared.shown}: against {against}: {'; '.join(said)}"


def compare_pair(revision: Revision, pair: Pair, systems: Mapping[str, ContractNodes], *,
                 options: Sequence[OptionLayer] = (), threshold: Severity = Severity.BREAKING,
                 baseline: Baseline | None = None) -> DiffResult:
    """One contract against its file at REF (a file unchanged since REF is not loaded)."""
    name = pair.new or pair.old
    assert name is not None
    shown = revision.shown(name)
    result = DiffResult(shown=shown, against=revision.at_ref(pair.old) if pair.old else None, revision=revision.ref,
                        path=revision.top / name, status=pair.status, fail_at=threshold, kind=kind_of_pair(revision, pair))
    if _unchanged(revision, pair):  # nothing to compare, nothing to load (most contracts of a pull request)
        result.status = "unchanged" if pair.old == pair.new else "renamed"
        result.nodes = sorted(_NODE_LINE.findall(revision.text_now(pair.new or "") or ""))
        return result
    loaded = _load_pair(revision, pair, shown)
    if isinstance(loaded, str):
        result.error = loaded
        return result
    old, new = loaded
    try:
        opts = Layers(strong_options=options).options(new if pair.new is not None else old, shown=shown)
    except ContractError as exc:
        result.error = str(exc)
        return result
    opts = said_middleware(old, new, opts)  # a system contract is judged for the middleware it says it runs on
    items = compare_contracts(old, new, dataclasses.replace(opts, fail_on=threshold.name.lower()))
    if systems and not contract_kind.is_system_text(new.text or old.text, name):
        items = consumers.judge(items, new.nodes, old.nodes, systems, rmw=opts.rmw)
    result.rules, result.options, result.old, result.new = opts.rules, opts, old, new
    _judge(result, drift.sort_items(items), old, new, baseline, revision.ref)
    result.nodes = sorted((new if pair.new is not None else old).nodes)
    result.lines = _lines(new) if pair.new is not None else {}
    return result


def _unchanged(revision: Revision, pair: Pair) -> bool:
    """Git says the file did not change (a contract kept in git LFS is not read at REF then), or
    it reads the same at REF and now."""
    if pair.old is None or pair.new is None:
        return False
    if pair.old == pair.new and not revision.changed(pair.new) and not (revision.top / pair.new).is_symlink():
        return True  # (a link git did not see change may lead to a file that did: read both)
    now = revision.text_now(pair.new)
    return now is not None and revision.text(pair.old) == now  # one that cannot be read: loading it says why


def _load_pair(revision: Revision, pair: Pair, shown: str) -> tuple[Contract, Contract] | str:
    """The contract at REF and now (an empty one where the file is not), or the error to report."""
    old = new = Contract(path=None, nodes={})
    if pair.old is not None and (why := revision.problem_at_ref(pair.old)) is not None:
        return (f"{revision.at_ref(pair.old)} {why}\n  The gate cannot compare {shown} with its version at "
                f"{revision.ref}; fix what is said, or compare two files with `rmw-introspect diff OLD NEW`")
    if pair.new is not None and (why := revision.problem_now(pair.new)) is not None:
        return f"{shown} {why}"
    if pair.old is not None:
        try:
            old = load_text(revision.text(pair.old) or "", revision.at_ref(pair.old))
        except ContractError as exc:
            return (f"{exc}\n  This is the contract as it was at {revision.ref}; the gate cannot compare with a "
                    "contract that was invalid there: compare with a later revision (--against COMMIT), or compare "
                    "two files with `rmw-introspect diff OLD NEW`")
    if pair.new is not None:
        try:
            new = load_text(revision.text_now(pair.new) or "", shown)
        except ContractError as exc:
            return str(exc)
    return old, new


def _judge(result: DiffResult, items: list[DriftItem], old: Contract, new: Contract,
           baseline: Baseline | None, ref: str) -> None:
    """The versions, then the contract's ``accept:`` entries, then the baseline."""
    present = new if result.status != "removed" else old
    leveled = rule_levels.apply(items, result.rules)  # the project's levels of rules, before the versions
    versioned = versioning.judge(leveled.items, old.interface_version, new.interface_version, source=result.shown,
                                 line=_version_line(new.text), ref=ref)
    findings = rule_levels.apply(versioned.findings, result.rules)
    result.turned_off = leveled.off + findings.off
    judged = acceptance.judge([*findings.items, *versioned.kept], present.accept, rules=frozenset())
    kept = [item for item in judged.kept if isinstance(item, DriftItem)]
    result.accepted = [*versioned.accepted, *judged.accepted]
    if baseline is not None:
        fresh, known = baseline.split(result.path, kept)
        kept = [item for item in fresh if isinstance(item, DriftItem)]
        result.accepted += known
    result.items = kept
    result.needs = versioned.needs
    result.versions = (old.interface_version, new.interface_version)
    turned_off = [rule_levels.turned_off_text(result.turned_off)] if result.turned_off else []
    if result.status in ("added", "removed"):  # the file comes or goes with its version: nothing to say of it
        result.notes = turned_off
        return
    result.notes = [*versioned.notes, *turned_off]
