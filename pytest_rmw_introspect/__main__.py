"""``python -m pytest_rmw_introspect``: the ``rmw-introspect`` command line."""

import sys

from .cli import main

sys.exit(main())
