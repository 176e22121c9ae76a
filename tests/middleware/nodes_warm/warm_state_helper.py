"""Module-level state of a node's own module: a record of every import in this process."""

import os

LOADS = []
LOADS.append(os.getpid())
