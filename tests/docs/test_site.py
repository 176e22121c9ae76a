"""The documentation site (mkdocs.yml, docs/): it builds with warnings as errors, which includes
MkDocs' check of every internal link and anchor and our hook's check of links into the
repository; it fetches nothing from outside (it must work offline); and its getting-started
page renders in a real headless browser: the marker example's code block is laid out, visible
and highlighted, the theme's script ran, and the navigation lists the pages.

The build needs MkDocs and Material (requirements/tools.in); the browser part needs Chromium
from the system packages (`apt-get install chromium`; `.ci/run` installs it) and is skipped,
saying so, only where there is none."""

from __future__ import annotations

import html
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from headless_browser import headless_command

ROOT = Path(__file__).resolve().parents[2]
MKDOCS = Path(sys.executable).with_name("mkdocs")

#: runs in the page once it has loaded and writes what it measured into <pre id="rmwi-check">
PROBE = """
<script>
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
  const header = document.querySelector(".md-header");
  out.header = header ? {position: getComputedStyle(header).position,
                         background: getComputedStyle(header).backgroundColor} : null;
  out.nav = [...document.querySelectorAll("nav.md-nav--primary a.md-nav__link")]
    .map(a => ({text: a.textContent.trim(), href: a.getAttribute("href")}))
    .filter(link => link.href);
  out.viewport = window.innerWidth;
  const pre = document.createElement("pre");
  pre.id = "rmwi-check";
  pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
}, 500));
</script>
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
    probe = page.with_name("ament-python.probe.html")
    probe.write_text(page.read_text(encoding="utf-8").replace("</body>", PROBE + "</body>"), encoding="utf-8")
    command = headless_command(tmp_path / "profile", "--allow-file-access-from-files", "--window-size=1400,1000",
                               "--virtual-time-budget=10000", "--dump-dom", probe.as_uri())
    proc = subprocess.run(command, capture_output=True, text=True, timeout=120, check=False,
                          env={**os.environ, "HOME": str(tmp_path)})
    assert proc.returncode == 0, f"chromium failed ({proc.returncode}):\n{proc.stderr[-3000:]}"
    found = re.search(r'<pre id="rmwi-check">(.*?)</pre>', proc.stdout, re.S)
    assert found, "the page's probe never ran (did the page load?):\n" + proc.stdout[-2000:]
    seen = json.loads(html.unescape(found.group(1)))

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
