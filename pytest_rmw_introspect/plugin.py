"""pytest entry point of pytest-rmw-introspect (work in progress)."""
