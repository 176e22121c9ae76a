"""What a session wrote, and whether it may write: the part of the golden writer a pytest
session (an xdist controller) needs without the writer itself (PyYAML, the contract model).

* ``ci_refusal()``: with ``CI`` set (non-empty, not ``0``/``false``) goldens are never written;
  front ends turn the message into their usage error.
* Every written golden is recorded on the test's report (``user_properties``) as
  ``(USER_PROPERTY, "<action>\\t<path>")``; reports travel from xdist workers to the
  controller, where :class:`GoldenSession` collects them for the terminal summary.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

from ..model.paths import shown

USER_PROPERTY = "rmw_introspect_golden_written"
CREATED = "created"
UPDATED = "updated"
#: a golden --update-golden could not rewrite: the file is not a valid contract
INVALID = "invalid"


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


def property_value(action: str, path: str | Path) -> str:
    return f"{action}\t{Path(path).resolve()}"


@dataclass
class GoldenSession:
    """What this session wrote (filled from test reports, so it works under xdist)."""

    enabled: bool = False
    written: dict[Path, str] = field(default_factory=dict)

    def record_report(self, user_properties: Iterable[tuple[str, object]]) -> None:
        for name, value in user_properties:
            if name != USER_PROPERTY or not isinstance(value, str) or "\t" not in value:
                continue
            action, path = value.split("\t", 1)
            p = Path(path)
            # "created" wins over a later "updated" of the same file
            if self.written.get(p) != CREATED:
                self.written[p] = action

    def summary_lines(self, base: Path | None = None) -> list[str]:
        """One line per golden written (``created``/``updated``), then one per golden left as it was
        because it is invalid; then the counts."""
        def line(p: Path) -> str:
            return f"{self.written[p]:8} {shown(p, base) if base is not None else p}"

        written = [line(p) for p in sorted(self.written) if self.written[p] != INVALID]
        invalid = [line(p) + "  (not written: fix or delete it, then run --update-golden again)"
                   for p in sorted(self.written) if self.written[p] == INVALID]
        if not written and not invalid:
            return ["no golden contract needed changes"]
        counts = [f"{len(written)} golden contract(s) written"]
        if invalid:
            counts.append(f"{len(invalid)} invalid golden contract(s) not written")
        return [*written, *invalid, "; ".join(counts)]
