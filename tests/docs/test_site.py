"""The documentation site (mkdocs.yml, docs/): it builds with warnings as errors, which includes
MkDocs' check of every internal link and anchor and our hook's check of links into the
repository; it fetches nothing from outside (it must work offline); and its getting-started
page renders in a real headless browser: the marker example's code block is laid out, visible
and highlighted, the theme's script ran, and the navigation lists the pages.

The build needs MkDocs and Material (requirements/tools.in); the browser part needs Chromium
from the system packages (`apt-get install chromium`; `.ci/run` installs it) and is skipped,
saying so, only where there is none."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from headless_browser import probe

from pytest_rmw_introspect.model.project_urls import REPOSITORY

ROOT = Path(__file__).resolve().parents[2]
MKDOCS = Path(sys.executable).with_name("mkdocs")

#: runs in the getting-started page once it has loaded and reports what it measured
PROBE = """
window.addEventListener("load", () => setTimeout(() => {
  const blocks = [...document.querySelectorAll("article pre")];
  const block = blocks.find(b => b.textContent.includes("@pytest.mark.interfaces"));
  const out = {found: !!block};
  if (block) {
    const box = block.getBoundingClientRect(), style = getComputedStyle(block);
    const decorator = [...block.querySelectorAll("span")].find(s => s.textContent.includes("pytest"));
    out.block = {width: box.width, height: box.height, left: box.left, top: box.top,
                 display: style.display, visibility: style.visibility, opacity: style.opacity,
                 text: block.textContent};
    out.highlighted_spans = block.querySelectorAll("span[class]").length;
    out.decorator_color = decorator ? getComputedStyle(decorator).color : null;
    out.text_color = getComputedStyle(document.querySelector("article p")).color;
    out.copy_button = !!block.parentElement.querySelector(".md-clipboard, .md-code__button");
  }
  // every code block: is any of its text beyond what it shows?
  out.code = [...document.querySelectorAll("article pre > code")].map(code => ({
    first_line: code.textContent.split("\\n").find(line => line.trim()) || "",
    scroll_width: code.scrollWidth, client_width: code.clientWidth,
    right: code.getBoundingClientRect().right}));
  const header = document.querySelector(".md-header");
  out.header = header ? {position: getComputedStyle(header).position,
                         background: getComputedStyle(header).backgroundColor} : null;
  const source = document.querySelector(".md-header .md-source");
  out.repository = source ? {href: source.href, text: source.textContent.trim(),
                             visible: source.getBoundingClientRect().width > 0} : null;
  out.source_components = document.querySelectorAll("[data-md-component=source]").length;
  out.nav = [...document.querySelectorAll("nav.md-nav--primary a.md-nav__link")]
    .map(a => ({text: a.textContent.trim(), href: a.getAttribute("href")}))
    .filter(link => link.href);
  out.viewport = window.innerWidth;
  rmwiReport(out);
}, 500));
"""

#: types a word into the search box of a page opened from disk and reports what the search shows
SEARCH = """
window.addEventListener("load", () => {
  const input = document.querySelector("input.md-search__input");
  const out = {input: !!input, visible: !!input && input.getBoundingClientRect().width > 0};
  if (!input) { rmwiReport(out); return; }
  try {
    input.focus();
    input.value = WORD;
    input.dispatchEvent(new Event("input", {bubbles: true}));
    input.dispatchEvent(new KeyboardEvent("keyup", {bubbles: true, key: "e"}));
  } catch (error) {
    out.error = String(error);
    rmwiReport(out);
    return;
  }
  let tries = 0;
  const look = () => {
    const items = [...document.querySelectorAll(".md-search-result__item")];
    if (items.length === 0 && ++tries < 50) { setTimeout(look, 200); return; }
    out.meta = (document.querySelector(".md-search-result__meta") || {}).textContent || "";
    out.results = items.map(item => ({text: item.textContent.trim().slice(0, 200),
                                      href: (item.querySelector("a") || {}).href || ""}));
    rmwiReport(out);
  };
  setTimeout(look, 200);
});
"""


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    """The site, built as `make docs` builds it (strict: any warning fails the build)."""
    assert MKDOCS.is_file(), f"no mkdocs next to {sys.executable}: make bootstrap installs it (requirements/tools.in)"
    out = tmp_path_factory.mktemp("site")
    proc = subprocess.run([str(MKDOCS), "build", "--strict", "--config-file", str(ROOT / "mkdocs.yml"),
                           "--site-dir", str(out)], cwd=ROOT, capture_output=True, text=True, timeout=280,
                          env={**os.environ, "NO_MKDOCS_2_WARNING": "1"})
    assert proc.returncode == 0, f"mkdocs build --strict failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-5000:]}"
    return out


def test_the_site_builds_strict_with_every_page_and_the_generated_references(site):
    for page in ("index.html", "getting-started/ament-python.html", "getting-started/ament-cmake.html",
                 "troubleshooting.html", "drift-rules.html", "design.html", "contributing.html",
                 "reference/cli.html", "reference/pytest.html", "reference/contract.html"):
        assert (site / page).is_file(), f"{page} missing from the built site"
    index = (site / "index.html").read_text(encoding="utf-8")
    assert "Interface contract tests for ROS 2 nodes" in index  # README.md is the front page
    cli = (site / "reference" / "cli.html").read_text(encoding="utf-8")
    assert "--write-baseline" in cli and "rmw-introspect capture" in cli


def test_the_site_fetches_nothing_from_outside(site):
    """Scripts, stylesheets, fonts and images all come from the site itself (it is read offline);
    links to other sites (the theme's credit line, NoDL, SARIF) are fine, loads are not."""
    loads = re.compile(r"<(?:script|img|iframe)[^>]*\ssrc=\"([^\"]+)\"|<link[^>]*\shref=\"([^\"]+)\"[^>]*>", re.I)
    external = []
    for page in site.rglob("*.html"):
        for match in loads.finditer(page.read_text(encoding="utf-8")):
            url = match.group(1) or match.group(2)
            if re.match(r"^(https?:)?//", url):
                external.append(f"{page.relative_to(site)}: {url}")
    assert not external, "the site loads resources from outside:\n" + "\n".join(external[:20])
    for css in site.rglob("*.css"):
        assert "fonts.googleapis" not in css.read_text(encoding="utf-8"), css


def test_the_getting_started_page_renders_its_example_in_a_browser(site, tmp_path):
    page = site / "getting-started" / "ament-python.html"
    seen = probe(page, PROBE, tmp_path / "profile", window="1400,1000")

    assert seen["found"], "no code block with the interfaces marker on the getting-started page"
    block = seen["block"]
    assert "def test_talker(interfaces):" in block["text"]
    assert block["display"] != "none" and block["visibility"] == "visible" and float(block["opacity"]) > 0.5
    assert block["height"] > 60 and block["width"] > 300, f"the example's code block is not laid out: {block}"
    assert 0 <= block["left"] < seen["viewport"], f"the example's code block is off screen: {block}"
    # the stylesheet and the highlighter: coloured tokens, a styled header; the theme's script: copy buttons
    assert seen["highlighted_spans"] > 5, "the example is not syntax-highlighted"
    assert seen["decorator_color"] and seen["decorator_color"] != seen["text_color"], seen
    assert seen["header"] and seen["header"]["position"] == "sticky", f"the theme's stylesheet did not apply: {seen['header']}"
    assert seen["copy_button"], "the theme's script did not run (no copy button on the code block)"

    titles = {link["text"] for link in seen["nav"]}
    for title in ("An ament_python package", "An ament_cmake package", "The marker and fixtures", "Contract format",
                  "Drift rules", "System contracts and the graph", "CI recipes", "Troubleshooting",
                  "Known limits", "Performance", "Contributing"):
        assert title in titles, f"the navigation lacks {title!r}: {sorted(titles)}"
    for link in seen["nav"]:
        if link["href"].startswith("#"):  # the page's own table of contents
            continue
        target = (page.parent / link["href"].split("#")[0]).resolve()
        assert target.is_file(), f"the navigation's {link['text']!r} points to {link['href']}, which is not in the site"

    # at 1400 px no line of code is cut off: code blocks wrap (docs/stylesheets/code.css), so what a
    # block holds is as wide as what it shows; the marker line among them
    assert seen["code"], "no code block measured"
    hidden = [code for code in seen["code"] if code["scroll_width"] > code["client_width"]]
    assert hidden == [], f"code blocks hide part of their lines at 1400 px: {hidden}"
    assert any(code["first_line"].startswith("import pytest") for code in seen["code"])
    assert all(code["right"] <= seen["viewport"] for code in seen["code"]), seen["code"]

    # the header links the repository, as a plain link (no script that asks GitHub's API for stars)
    assert seen["repository"] == {"href": REPOSITORY, "text": "pytest-rmw-introspect", "visible": True}, seen["repository"]
    assert seen["source_components"] == 0


def test_search_works_on_the_site_opened_from_disk(site, tmp_path):
    """README.md says to open site/index.html: from file:// the search box is there and finds
    pages (Material's offline plugin: the index as a script; our worker stand-in,
    docs/javascripts/iframe-worker-from-disk.js, since browsers start no worker from a file)."""
    page = site / "getting-started" / "ament-python.html"
    word = "quiescence"  # in the virtual time and performance pages, not on this one
    assert word not in page.read_text(encoding="utf-8").lower()
    seen = probe(page, SEARCH.replace("WORD", json.dumps(word)), tmp_path / "profile", window="1400,1000")

    assert seen["input"] and seen["visible"], f"no search box on the page opened from disk: {seen}"
    assert "error" not in seen, seen
    assert seen["results"], f"searching {word!r} from disk shows nothing: {seen}"
    assert re.match(r"\d+ matching documents?", seen["meta"]), seen["meta"]
    pages = {result["href"].split("#")[0] for result in seen["results"]}
    assert (site / "virtual-time.html").as_uri() in pages, pages
    for href in pages:
        assert href.startswith("file://") and Path(href[len("file://"):]).is_file(), f"a result points nowhere: {href}"
