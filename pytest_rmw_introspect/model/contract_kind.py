"""Whether a file is a contract, and of which kind, decided by its content.

The one place that answers "is this a contract?" for the gate (``diff --against``), ``check``,
``validate``, ``diff``, the GitHub action and pytest's collection of contract files. A file is a
contract when its text says so, whatever its name:

- a **system contract**: a top-level ``system_version:`` key (or the name ``*.system.yaml``);
- a **node contract**: a top-level ``contract_version:`` key (or the name ``*.interfaces.yaml``).
  One with a top-level ``target:`` block runs by itself (``check``, ``pytest contracts/``); one
  without is a **golden** of a marker test (``@pytest.mark.interfaces("contracts/x.yaml", ...)``,
  the target is the marker's): it is compared by the gate like any other, and ``check`` says how to
  give it a target;
- a **NoDL document**: a top-level ``nodl_version`` key (or the name ``*.nodl.yaml``).

A name with a contract suffix makes a file a contract even when its text is broken, so that the
loader reports what is wrong with it instead of the file being passed over. Any other YAML file
(a parameters file, a launch file, a CI configuration) is not a contract; the gate lists the ones
it passed over, so that nothing is left out silently.

The test is a look at the top-level keys (a line that starts with the key), not a YAML parse:
it must be cheap for every YAML file of a large repository, and it must also classify a contract
whose YAML is invalid (its loader then says where).
"""

from __future__ import annotations

import enum
import re
from pathlib import Path

from ..errors import InputError
from . import contract, system_contract, tally, untrusted
from .contract import Contract
from .system_contract import SystemContract

#: names that make a file a contract of a kind whatever it holds (its loader reports a broken one)
SYSTEM_SUFFIX = system_contract.SUFFIX
NODE_SUFFIX = ".interfaces.yaml"
_NODL_NAME = re.compile(r"\.nodl\.(ya?ml|json)$")
#: the files whose content is looked at (anything else is never a contract)
CANDIDATE_SUFFIXES = (".yaml", ".yml", ".nodl.json")

_SYSTEM_KEY = re.compile(r"^system_version\s*:", re.M)
_NODE_KEY = re.compile(r"^contract_version\s*:", re.M)
_TARGET_KEY = re.compile(r"^target\s*:", re.M)
_NODL_KEY = re.compile(r'^(\{\s*)?"?nodl_version"?\s*:', re.M)


class Kind(enum.Enum):
    """The kinds of contract file, as reports name them."""

    NODE = "node contract"  # a node contract with its own ``target:``
    GOLDEN = "marker golden"  # a node contract whose target a marker test gives
    SYSTEM = "system contract"
    NODL = "NoDL document"

    @property
    def is_system(self) -> bool:
        return self is Kind.SYSTEM

    @property
    def plural(self) -> str:
        return self.value + "s"


def is_candidate(name: str | Path) -> bool:
    """A file whose content may make it a contract (YAML, or a NoDL JSON document)."""
    return str(name).lower().endswith(CANDIDATE_SUFFIXES)


def kind_of_text(text: str, name: str | Path = "") -> Kind | None:
    """The kind of contract ``text`` is (``name``, the file's name, decides for a text that does not
    say), or None: not a contract."""
    kind = _kind_of_text(text, name)
    if kind is not None:
        tally.note("kind", kind.name)  # the test suite's exercised set (model.tally; issue 48)
    return kind


def _kind_of_text(text: str, name: str | Path) -> Kind | None:
    base = Path(str(name)).name
    if _SYSTEM_KEY.search(text) or base.endswith(SYSTEM_SUFFIX):
        return Kind.SYSTEM
    if _NODE_KEY.search(text) or base.endswith(NODE_SUFFIX):
        return Kind.NODE if _TARGET_KEY.search(text) else Kind.GOLDEN
    if _NODL_KEY.search(text) or _NODL_NAME.search(base):
        return Kind.NODL
    return None


def kind_of_name(name: str | Path) -> Kind | None:
    """The kind a file's name alone says (for a file that cannot be read: its loader says why)."""
    return kind_of_text("", name)


def kind_of_file(path: str | Path) -> Kind | None:
    """The kind of contract the file at ``path`` is, or None. A file that cannot be read (missing,
    a FIFO, too large, not UTF-8) is judged by its name alone; its loader then says what is wrong."""
    path = Path(path)
    try:
        text = untrusted.read_text(path)
    except (OSError, InputError):
        return kind_of_name(path)
    return kind_of_text(text, path)


def is_system_file(path: str | Path) -> bool:
    """A system contract (by :func:`kind_of_file`)."""
    return kind_of_file(path) is Kind.SYSTEM


def is_system_text(text: str, name: str | Path = "") -> bool:
    """A system contract's text (by :func:`kind_of_text`)."""
    return kind_of_text(text, name) is Kind.SYSTEM


# ---------------------------------------------------------------------------- loading either kind
def as_node_contract(system: SystemContract) -> Contract:
    """What a comparison of nodes reads of a system contract (its nodes, ``target:``, ``options:``,
    ``accept:``, ``interface_version``, text and the middleware it says it runs on), as a node
    contract."""
    return Contract(path=system.path, nodes=system.nodes, target=system.target,
                    options=system.options, text=system.text, accept=system.accept,
                    interface_version=system.interface_version, middleware=system.middleware())


def loads(text: str, label: str | Path) -> tuple[Contract, Kind]:
    """A contract's text of any kind as the node contract a comparison reads, and its kind (a text
    that says no kind is read as a node contract: its loader says what is missing); ``label``
    names it in messages. Raises ContractError."""
    kind = kind_of_text(text, label)
    if kind is Kind.SYSTEM:
        return as_node_contract(system_contract.loads(text, path=str(label))), kind
    return contract.loads(text, path=str(label)), kind or Kind.NODE


def load(path: str | Path) -> tuple[Contract, Kind]:
    """The contract file at ``path``, of any kind, as :func:`loads` (raises ContractError)."""
    if is_system_file(path):
        return as_node_contract(system_contract.load(path)), Kind.SYSTEM
    loaded = contract.load(path)
    return loaded, kind_of_file(path) or Kind.NODE
