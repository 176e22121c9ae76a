"""The HTML drawing of a system in a real headless browser: `rmw-introspect graph --format html`
renders, and the broken connections are highlighted (red on the screenshot) while a system that
fits has no red at all.

Needs Chromium from the system packages (`apt-get install chromium`; `.ci/run` installs it). The
test is skipped, saying so, only where no Chromium is installed."""

from __future__ import annotations

import os
import struct
import subprocess
import zlib
from pathlib import Path

from headless_browser import headless_command

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "rmw_introspect_examples"


def screenshot(page: Path, png: Path, profile: Path) -> None:
    command = headless_command(profile, "--hide-scrollbars", "--force-device-scale-factor=1", "--window-size=1400,1000",
                               f"--screenshot={png}", page.as_uri())
    proc = subprocess.run(command, capture_output=True, text=True, timeout=120, check=False,
                          env={**os.environ, "HOME": str(profile)})
    assert proc.returncode == 0 and png.is_file(), f"chromium failed ({proc.returncode}):\n{proc.stderr[-3000:]}"


def read_png(path: Path) -> tuple[int, int, list[bytes]]:
    """Width, height and rows of RGB(A) pixels of an 8-bit, non-interlaced PNG."""
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat, header = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        chunk = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", chunk)
        elif kind == b"IDAT":
            idat += chunk
        pos += 12 + length
    assert header is not None
    width, height, depth, color, _c, _f, interlace = header
    assert depth == 8 and interlace == 0 and color in (2, 6), header
    channels = 3 if color == 2 else 4
    raw = zlib.decompress(idat)
    stride = width * channels
    rows: list[bytes] = []
    previous = bytearray(stride)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            left = line[i - channels] if i >= channels else 0
            up = previous[i]
            upper_left = previous[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + left) & 0xFF
            elif kind == 2:
                line[i] = (line[i] + up) & 0xFF
            elif kind == 3:
                line[i] = (line[i] + (left + up) // 2) & 0xFF
            elif kind == 4:
                p = left + up - upper_left
                pa, pb, pc = abs(p - left), abs(p - up), abs(p - upper_left)
                line[i] = (line[i] + (left if pa <= pb and pa <= pc else up if pb <= pc else upper_left)) & 0xFF
        rows.append(bytes(line) if channels == 3 else bytes(b for j, b in enumerate(line) if j % 4 != 3))
        previous = line
    return width, height, rows


def count(rows: list[bytes], wanted) -> tuple[int, list[tuple[int, int]]]:
    found = 0
    where = []
    for y, row in enumerate(rows):
        for x in range(0, len(row), 3):
            if wanted(row[x], row[x + 1], row[x + 2]):
                found += 1
                if len(where) < 2000:
                    where.append((x // 3, y))
    return found, where


def red(r: int, g: int, b: int) -> bool:  # the BREAKING colour, #d62728, and its antialiased edges
    return r > 170 and g < 90 and b < 90


def ink(r: int, g: int, b: int) -> bool:
    return r < 200 or g < 200 or b < 200


def draw(cli, contract: Path, out: str) -> Path:
    result = cli("graph", str(contract), "--format", "html", "-o", out)
    assert result.returncode == 0, result
    return cli.path / out


def test_the_page_renders_and_highlights_the_broken_connections(cli_nodes_only, tmp_path):
    cli = cli_nodes_only
    broken = draw(cli, EXAMPLES / "system_demo" / "broken_robot.system-demo.yaml", "broken.html")
    fine = draw(cli, EXAMPLES / "contracts" / "robot.system.yaml", "fine.html")
    broken_png, fine_png = tmp_path / "broken.png", tmp_path / "fine.png"
    screenshot(broken, broken_png, tmp_path / "profile-broken")
    screenshot(fine, fine_png, tmp_path / "profile-fine")

    width, height, rows = read_png(broken_png)
    assert (width, height) == (1400, 1000)
    drawn, _ = count(rows, ink)
    assert drawn > 20_000, "the page looks blank"
    highlighted, where = count(rows, red)
    assert highlighted > 1_500, f"only {highlighted} red pixels: the broken connections are not highlighted"
    # red in the drawing's middle band, between the node column and the topic column: the edges of the
    # TYPE_MISMATCH connection (not only the red verdict line and the badges of the table)
    drawing_edges = [(x, y) for x, y in where if 300 < x < 500 and 140 < y < 600]
    assert len(drawing_edges) > 50, "the broken connection's edge is not red"

    _w, _h, fine_rows = read_png(fine_png)
    fine_drawn, _ = count(fine_rows, ink)
    assert fine_drawn > 20_000, "the page of the example robot looks blank"
    fine_red, _ = count(fine_rows, red)
    assert fine_red == 0, f"{fine_red} red pixels on the drawing of a system that fits"
