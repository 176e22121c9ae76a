"""MkDocs hook of the documentation site (``mkdocs.yml``, ``hooks:``).

- Adds the generated reference pages (``scripts/docs/reference.py``: the CLI from its argparse
  parser, the pytest options and ini keys from the plugin's ``pytest_addoption``, the contract
  keys from the JSON Schema), so they are built fresh from the code each time.
- Shows Markdown files of the repository that live outside ``docs/`` as pages of the site, from
  the one file each (README.md is the site's front page; CONTRIBUTING.md, CHANGELOG.md, the
  middleware's and the example package's READMEs), instead of copies that would drift apart.
- Rewrites links between those files and ``docs/`` pages: a page links as on GitHub, relative
  to its own place in the repository (``docs/x.md`` from README.md, ``../CONTRIBUTING.md`` from
  ``docs/``), and the site gets the link to the same page in the site. A relative link to a
  repository file that is not part of the site is reported (an error under ``mkdocs build
  --strict``): write such a path as code instead. Everything that resolves to a page is then
  checked by MkDocs itself (``validation:`` in ``mkdocs.yml``: missing pages and anchors).
"""

from __future__ import annotations

import logging
import posixpath
import re
import sys
from pathlib import Path
from typing import Any

from mkdocs.structure.files import File, Files

sys.path.insert(0, str(Path(__file__).resolve().parent))
import reference  # noqa: E402  (beside this file: MkDocs loads a hook by its path, not as a package)

LOG = logging.getLogger("mkdocs.hooks.rmw_introspect")
ROOT = reference.ROOT

#: site page -> the repository file it shows
MIRRORED = {
    "index.md": "README.md",
    "contributing.md": "CONTRIBUTING.md",
    "changelog.md": "CHANGELOG.md",
    "middleware.md": "rmw_introspect_cpp/README.md",
    "example-package.md": "examples/rmw_introspect_examples/README.md",
}
SHOWN_AS = {source: page for page, source in MIRRORED.items()}

#: a Markdown link or image target: ](target) or ](target "title")
LINK = re.compile(r"\]\((?P<target>[^)\s]+)(?P<title>\s+\"[^\"]*\")?\)")
FENCE = re.compile(r"^(```|~~~)")


def on_files(files: Files, config: Any) -> Files:
    for uri, make in reference.PAGES.items():
        files.append(File.generated(config, uri, content=make()))
    for uri, source in MIRRORED.items():
        files.append(File.generated(config, uri, abs_src_path=str(ROOT / source)))
    return files


def repository_path(src_uri: str) -> str:
    """Where a page of the site comes from, relative to the repository root."""
    return MIRRORED.get(src_uri, f"docs/{src_uri}")


def site_target(page_uri: str, target: str) -> str | None:
    """The link ``target`` of page ``page_uri`` rewritten for the site; ``None``: it points to
    a repository file that is not part of the site. Absolute URLs and anchors stay as they are."""
    if re.match(r"^[a-z][a-z0-9+.-]*:", target) or target.startswith(("#", "/")):
        return target
    path, _, anchor = target.partition("#")
    origin = repository_path(page_uri)
    in_repository = posixpath.normpath(posixpath.join(posixpath.dirname(origin), path))
    if in_repository in SHOWN_AS:
        site_uri = SHOWN_AS[in_repository]
    elif in_repository.startswith("docs/"):
        site_uri = in_repository[len("docs/"):]
    else:
        return None
    relative = posixpath.relpath(site_uri, posixpath.dirname(page_uri) or ".")
    return relative + (f"#{anchor}" if anchor else "")


def on_page_markdown(markdown: str, page: Any, config: Any, files: Files) -> str:
    page_uri = page.file.src_uri
    lines = markdown.split("\n")
    in_code = False
    for number, line in enumerate(lines):
        if FENCE.match(line.lstrip()):
            in_code = not in_code
        if in_code:
            continue

        def rewrite(match: re.Match[str], number: int = number) -> str:
            target = match.group("target")
            rewritten = site_target(page_uri, target)
            if rewritten is None:
                LOG.warning("%s:%d links to %s, a repository file that is not a page of the site: "
                            "write the path as code, or show the file in the site (MIRRORED in %s)",
                            repository_path(page_uri), number + 1, target, Path(__file__).relative_to(ROOT))
                return match.group(0)
            return f"]({rewritten}{match.group('title') or ''})"

        lines[number] = LINK.sub(rewrite, line)
    return "\n".join(lines)
