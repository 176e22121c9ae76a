"""Shared test configuration.

``pytester`` is enabled here (a top-level conftest) because pytest only honours
``pytest_plugins`` in conftest files it loads at start-up.
"""

pytest_plugins = ["pytester"]
