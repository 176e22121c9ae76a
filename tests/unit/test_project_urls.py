"""Where the project says it lives: pyproject.toml's ``[project.urls]`` (the wheel's Project-URL
lines), the documentation site's ``repo_url`` (mkdocs.yml) and the links the package writes into
its output (``model.project_urls``) name one repository, and every page and anchor they link to
exists in docs/."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import yaml

from pytest_rmw_introspect.compare import graph
from pytest_rmw_introspect.model import project_urls

ROOT = Path(__file__).resolve().parents[2]


def github_anchors(markdown: str) -> set[str]:
    """The anchors GitHub (and MkDocs' toc) makes of a page's headings: lower case, punctuation
    other than hyphens dropped, spaces as hyphens."""
    anchors = set()
    for heading in re.findall(r"^#{1,6} +(.+?) *$", markdown, re.M):
        anchors.add(re.sub(r"[^\w\- ]", "", heading.lower()).replace(" ", "-"))
    return anchors


def test_pyproject_names_the_repository_and_its_pages():
    urls = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]["urls"]
    assert set(urls) == {"Homepage", "Documentation", "Repository", "Issues", "Changelog"}
    assert urls["Repository"] == urls["Homepage"] == project_urls.REPOSITORY
    assert all(url.startswith(project_urls.REPOSITORY) for url in urls.values()), urls
    assert urls["Changelog"].endswith("/blob/main/CHANGELOG.md") and (ROOT / "CHANGELOG.md").is_file()
    assert urls["Documentation"].endswith("/tree/main/docs") and (ROOT / "docs").is_dir()


def test_the_documentation_site_links_the_same_repository():
    # mkdocs.yml has Python tags of its own (none here); plain YAML reads the keys wanted
    config = yaml.safe_load((ROOT / "mkdocs.yml").read_text(encoding="utf-8"))
    assert config["repo_url"] == project_urls.REPOSITORY


def test_the_links_into_the_documentation_reach_a_heading():
    for url in (project_urls.COMPATIBILITY_RULES, graph.COMPATIBILITY_RULES):
        prefix = project_urls.REPOSITORY + "/blob/main/"
        assert url.startswith(prefix), url
        path, _, anchor = url[len(prefix):].partition("#")
        page = ROOT / path
        assert page.is_file(), f"{url}: no {path} in the repository"
        assert anchor in github_anchors(page.read_text(encoding="utf-8")), f"{url}: no heading makes #{anchor}"
    assert project_urls.docs_page("cli.md") == project_urls.REPOSITORY + "/blob/main/docs/cli.md"


def test_a_wrong_anchor_is_found():
    assert "compatibility-rules-comparecompatibility" in github_anchors("## Compatibility rules (`compare.compatibility`)\n")
    assert "compatibility-rules" not in github_anchors("## Compatibility rules (`compare.compatibility`)\n")
