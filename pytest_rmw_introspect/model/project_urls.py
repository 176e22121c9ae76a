"""Where the project lives on the web: the repository, and links to its documentation pages for
output that leaves the repository (a drawing's HTML page is opened anywhere, so its links are
absolute). pyproject.toml's ``[project.urls]`` names the same repository
(tests/unit/test_project_urls.py checks both, and that every linked page and anchor exists)."""

from __future__ import annotations

REPOSITORY = "https://github.com/pytest-rmw-introspect/pytest-rmw-introspect"


def docs_page(page: str, anchor: str = "") -> str:
    """The page ``docs/<page>`` as the repository shows it (GitHub renders the Markdown and
    makes an anchor of each heading), with ``#anchor`` when given."""
    return f"{REPOSITORY}/blob/main/docs/{page}" + (f"#{anchor}" if anchor else "")


#: the compatibility rules' table of docs/drift-rules.md (the rules a drawing marks)
COMPATIBILITY_RULES = docs_page("drift-rules.md", "compatibility-rules-comparecompatibility")
