"""The exit statuses of ``rmw-introspect`` (its ``--help`` says them to the user)."""

from __future__ import annotations

import signal

EXIT_OK = 0  # everything matches, or only drift below the fail threshold
EXIT_DRIFT = 1  # drift or incompatibility at or above the fail threshold
EXIT_ERROR = 2  # a problem the user can fix: a bad option, a missing or malformed contract, a failing target
EXIT_INTERRUPTED = 128 + signal.SIGINT  # Ctrl-C
EXIT_TERMINATED = 128 + signal.SIGTERM
