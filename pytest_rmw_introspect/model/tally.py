"""What a test run of this repository started and exercised, for its own cost and coverage reports.

Development accounting (issue 48; docs/development.md, "What a test costs"): nothing happens
unless ``RMW_INTROSPECT_TALLY`` names a file, and then each call appends one line to it,
``<what>\t<name>\n``:

- ``start\tcold`` / ``start\twarm``: the runner started a target process (``run/runner.py``);
- ``command\t<name>``, ``format\t<name>``: the command line ran a command, printed a format;
- ``rule\t<id>``: a drift or compatibility item of that rule was made;
- ``kind\t<kind>``: a file was read as a contract of that kind (``model/contract_kind.py``).

The test suite's plugin (``tests/support/cost_report.py``) gives each xdist worker a file of its
own and reads the lines a test appended while it ran: the variable is inherited by the pytest
and ``rmw-introspect`` subprocesses a test starts, so their starts count for that test. Lines
other than ``start`` are written once per process. The file is opened in append mode for
each line (small writes in append mode are not interleaved between processes).
"""

from __future__ import annotations

import os

#: the environment variable naming the file the lines go to
ENV = "RMW_INTROSPECT_TALLY"
_seen: set[tuple[str, str]] = set()


def note(what: str, name: str) -> None:
    """Append ``what``/``name`` to the tally file, if there is one (once per process, except starts)."""
    path = os.environ.get(ENV)
    if not path:
        return
    if what != "start":
        if (what, name) in _seen:
            return
        _seen.add((what, name))
    try:
        with open(path, "a", encoding="utf-8") as f:
            f.write(f"{what}\t{name}\n")
    except OSError:
        pass  # accounting never fails a run
