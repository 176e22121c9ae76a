"""The ``--update-golden`` side: CI refusal, locked writes, and the list of files written.

* ``ci_refusal()``: with ``CI`` set (non-empty, not ``0``/``false``) goldens are never
  written; the plugin turns the message into a ``pytest.UsageError`` at configure time.
* ``update(path, nodes)``: writes one golden under a file lock keyed by its absolute path,
  so that tests sharing a golden under pytest-xdist write it once (the second writer finds
  the bytes it would write already there). Existing files keep their header (contract.py).
* Every written file is recorded on the test's report (``user_properties``) as
  ``(USER_PROPERTY, "<action>\\t<path>")``; reports travel from xdist workers to the
  controller, where :class:`GoldenSession` collects them for the terminal summary.
"""

from __future__ import annotations

import hashlib
import os
import tempfile
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from filelock import FileLock

from . import contract as contract_module

USER_PROPERTY = "rmw_introspect_golden_written"
CREATED = "created"
UPDATED = "updated"


def ci_refusal(environ: Mapping[str, str] | None = None) -> str | None:
    """The reason why goldens must not be written here, or None."""
    environ = os.environ if environ is None else environ
    value = environ.get("CI", "")
    if value.strip() and value.strip().lower() not in ("0", "false", "no", "off"):
        return (
            f"--update-golden refuses to write golden contracts in CI (the CI environment variable "
            f"is set to {value!r}). Goldens are reviewed changes: run `pytest --update-golden` on "
            "your machine and commit the updated files, or unset CI if this is not a CI run."
        )
    return None


def _lock_path(path: Path) -> Path:
    key = hashlib.sha256(str(path.resolve()).encode()).hexdigest()[:24]
    directory = Path(tempfile.gettempdir()) / "pytest-rmw-introspect-locks"
    directory.mkdir(parents=True, exist_ok=True)
    return directory / f"{key}.lock"


def update(path: str | Path, nodes: Mapping[str, Any], *, timeout: float = 120.0) -> str | None:
    """Write the golden at ``path`` with ``nodes``; return ``CREATED``, ``UPDATED`` or None
    (nothing to change). Entries the golden spells differently but equivalently keep their
    spelling (``contract.preserve_spelling``)."""
    path = Path(path)
    with FileLock(str(_lock_path(path)), timeout=timeout):
        existed = path.exists()
        if existed:
            try:
                current = contract_module.load(path)
                nodes = contract_module.preserve_spelling(current.nodes, nodes)
            except contract_module.ContractError:
                pass  # a broken golden is replaced (its header is kept when it can be found)
        changed = contract_module.write(path, nodes)
    if not changed:
        return None
    return UPDATED if existed else CREATED


def property_value(action: str, path: str | Path) -> str:
    return f"{action}\t{Path(path).resolve()}"


@dataclass
class GoldenSession:
    """What this session wrote (filled from test reports, so it works under xdist)."""

    enabled: bool = False
    written: dict[Path, str] = field(default_factory=dict)

    def record_report(self, user_properties: Iterable[tuple[str, Any]]) -> None:
        for name, value in user_properties:
            if name != USER_PROPERTY or not isinstance(value, str) or "\t" not in value:
                continue
            action, path = value.split("\t", 1)
            p = Path(path)
            # "created" wins over a later "updated" of the same file
            if self.written.get(p) != CREATED:
                self.written[p] = action

    def summary_lines(self, base: Path | None = None) -> list[str]:
        lines = []
        for p in sorted(self.written):
            shown: Path | str = p
            if base is not None:
                try:
                    shown = os.path.relpath(p, base)
                except ValueError:
                    shown = p
            lines.append(f"{self.written[p]:8} {shown}")
        return lines
