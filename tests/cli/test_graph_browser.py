"""The HTML drawing of a system in a real headless browser: `rmw-introspect graph --format html`
renders, and the broken connections are highlighted (red on the screenshot) while a system that
fits has no red at all; on a crowded drawing (ten nodes, many findings) no edge's label covers a
box, measured on the rendered page, and each box says what it is.

Needs Chromium from the system packages (`apt-get install chromium`; `.ci/run` installs it). The
test is skipped, saying so, only where no Chromium is installed."""

from __future__ import annotations

import os
import struct
import subprocess
import zlib
from pathlib import Path

import yaml
from headless_browser import headless_command, probe

from pytest_rmw_introspect.model.project_urls import COMPATIBILITY_RULES

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


# ---------------------------------------------------------------- a crowded drawing, measured

QOS = {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE"}
BEST_EFFORT = {**QOS, "reliability": "BEST_EFFORT"}
LATCHED = {**QOS, "durability": "TRANSIENT_LOCAL"}
RELIABILITY_UNSET = {**QOS, "reliability": "SYSTEM_DEFAULT"}
HASH_A, HASH_B = "RIHS01_" + "a" * 64, "RIHS01_" + "b" * 64
LISTS = ("publishers", "subscriptions", "service_servers", "service_clients", "action_servers", "action_clients")


def topic(name: str, type_name: str, qos: dict | None = None, type_hash: str | None = None) -> dict:
    return {"name": name, "type": type_name, **({"type_hash": type_hash} if type_hash else {}), "qos": qos or QOS}


#: ten nodes whose connections break in the ways the compatibility rules of node contracts know:
#: the labels of many edges crowd the gaps between the columns (the drawing that covered "topic /raw")
TEN_NODES = {
    "camera": {"publishers": [topic("/camera/image_raw", "sensor_msgs/msg/Image", BEST_EFFORT),
                              topic("/raw", "std_msgs/msg/String")]},
    "detector": {"subscriptions": [topic("/camera/image_raw", "sensor_msgs/msg/Image")],
                 "publishers": [topic("/detections", "std_msgs/msg/String")]},
    "tracker": {"subscriptions": [topic("/detections", "std_msgs/msg/Int32"), topic("/raw", "std_msgs/msg/Int64")]},
    "lidar": {"publishers": [topic("/scan", "sensor_msgs/msg/LaserScan", type_hash=HASH_A),
                             topic("/raw", "std_msgs/msg/String", BEST_EFFORT)]},
    "mapper": {"subscriptions": [topic("/scan", "sensor_msgs/msg/LaserScan", type_hash=HASH_B)],
               "publishers": [topic("/map", "nav_msgs/msg/OccupancyGrid")]},
    "planner": {"subscriptions": [topic("/map", "nav_msgs/msg/OccupancyGrid", LATCHED),
                                  topic("/odom", "nav_msgs/msg/Odometry")],
                "service_clients": [{"name": "/plan_path", "type": "std_srvs/srv/Trigger"}],
                "publishers": [topic("/cmd_vel", "geometry_msgs/msg/Twist", RELIABILITY_UNSET)]},
    "controller": {"subscriptions": [topic("/cmd_vel", "geometry_msgs/msg/Twist"), topic("/raw", "std_msgs/msg/String")],
                   "action_clients": [{"name": "/navigate", "type": "test_msgs/action/Fibonacci"}]},
    "monitor": {"subscriptions": [topic("/raw", "std_msgs/msg/String"),
                                  topic("/scan", "sensor_msgs/msg/LaserScan", type_hash=HASH_A),
                                  topic("/detections", "std_msgs/msg/String")]},
    "logger": {"subscriptions": [topic("/cmd_vel", "geometry_msgs/msg/Twist", BEST_EFFORT),
                                 topic("/map", "nav_msgs/msg/OccupancyGrid")]},
    "driver": {"subscriptions": [topic("/cmd_vel", "geometry_msgs/msg/Twist", LATCHED)],
               "publishers": [topic("/odom_raw", "nav_msgs/msg/Odometry")]},
}


def write_ten_nodes(directory: Path) -> list[str]:
    paths = []
    for name, lists in TEN_NODES.items():
        path = directory / f"{name}.interfaces.yaml"
        nodes = {f"/{name}": {key: lists.get(key, []) for key in LISTS}}
        path.write_text(yaml.safe_dump({"contract_version": 1, "nodes": nodes}, sort_keys=False), encoding="utf-8")
        paths.append(str(path))
    return paths


#: every box and every edge label of the drawing, as laid out in the browser
MEASURE = """
window.addEventListener("load", () => {
  const rect = element => { const r = element.getBoundingClientRect();
                            return {left: r.left, top: r.top, right: r.right, bottom: r.bottom}; };
  rmwiReport({
    title: document.title,
    heading: document.querySelector("h1").textContent,
    boxes: [...document.querySelectorAll("svg g.vertex")].map(g => ({
      lines: [...g.querySelectorAll("text")].map(t => t.textContent),
      box: rect(g.querySelector("rect")),
      texts: [...g.querySelectorAll("text")].map(rect)})),
    labels: [...document.querySelectorAll("svg g.edge-label")].map(g => ({
      text: [...g.querySelectorAll("text")].map(t => t.textContent).join(" "), box: rect(g)})),
    legend_links: [...document.querySelectorAll(".legend a")].map(a => a.href),
    rule_links: [...document.querySelectorAll("table a")].map(a => [a.textContent, a.href]),
  });
});
"""


def overlaps(a: dict, b: dict) -> bool:
    return a["left"] < b["right"] and b["left"] < a["right"] and a["top"] < b["bottom"] and b["top"] < a["bottom"]


def inside(inner: dict, outer: dict) -> bool:
    return (outer["left"] <= inner["left"] and inner["right"] <= outer["right"]
            and outer["top"] <= inner["top"] and inner["bottom"] <= outer["bottom"])


def test_no_edge_label_covers_a_box_and_every_box_says_what_it_is(cli_nodes_only, tmp_path):
    cli = cli_nodes_only
    result = cli("graph", *write_ten_nodes(cli.path), "--format", "html", "-o", "ten.html")
    assert result.returncode == 0, result
    seen = probe(cli.path / "ten.html", MEASURE, tmp_path / "profile", window="1600,1400")

    boxes, labels = seen["boxes"], seen["labels"]
    assert len(boxes) == 20 and len(labels) >= 15, f"not the crowded drawing meant: {len(boxes)} boxes, {len(labels)} labels"
    covered = [(label["text"], box["lines"][0]) for label in labels for box in boxes if overlaps(label["box"], box["box"])]
    assert covered == [], f"edge labels cover boxes: {covered}"
    for box in boxes:  # a box's text stays in its box (cut with an ellipsis when too long)
        assert all(inside(text, box["box"]) for text in box["texts"]), f"the text of {box['lines']} leaves its box"

    by_name = {box["lines"][0]: box["lines"][1:] for box in boxes}
    # a topic with a finding keeps its type, and its rule id comes on a line of its own
    assert by_name["topic /odom"] == ["nav_msgs/msg/Odometry", "SUBSCRIPTION_WITHOUT_PUBLISHER"], by_name
    # a topic whose ends disagree on the type (TYPE_MISMATCH) shows both types
    assert by_name["topic /detections"] == ["std_msgs/msg/String", "std_msgs/msg/Int32"], by_name
    assert by_name["topic /raw"] == ["std_msgs/msg/String", "std_msgs/msg/Int64"], by_name
    assert by_name["/camera"] == ["camera.interfaces.yaml"], by_name  # a node: its process
    # the legend's reference and the table's rule ids are links to the compatibility rules' table
    assert seen["legend_links"] == [COMPATIBILITY_RULES]
    assert ["TYPE_MISMATCH", COMPATIBILITY_RULES] in seen["rule_links"]
    # several node contracts drawn together are titled as what they are
    assert seen["heading"].startswith("Node contracts camera.interfaces.yaml, detector.interfaces.yaml"), seen["heading"]


def test_a_drawing_is_titled_by_what_it_draws(cli_nodes_only, tmp_path):
    cli = cli_nodes_only
    single = cli("graph", write_ten_nodes(cli.path)[0], "--format", "html", "-o", "one.html")
    assert single.returncode == 0, single
    seen = probe(cli.path / "one.html", MEASURE, tmp_path / "profile-one")
    assert seen["title"] == seen["heading"] == "Node contract camera.interfaces.yaml"
    system = draw(cli, EXAMPLES / "contracts" / "robot.system.yaml", "robot.html")
    seen = probe(system, MEASURE, tmp_path / "profile-system")
    assert seen["heading"] == "System robot.system.yaml"
