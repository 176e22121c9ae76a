"""The system drawn (compare.graph): what is marked, and the Mermaid, DOT and HTML renderings."""

from __future__ import annotations

import re
from html.parser import HTMLParser

import pytest

from pytest_rmw_introspect.compare import graph
from pytest_rmw_introspect.compare.compatibility import LaunchedProcess, check_launched
from pytest_rmw_introspect.model.project_urls import COMPATIBILITY_RULES
from pytest_rmw_introspect.model.vocabulary import Severity

STRING = "std_msgs/msg/String"


def node(**lists):
    out = {k: [] for k in ("publishers", "subscriptions", "service_servers", "service_clients", "action_servers",
                           "action_clients")}
    for list_name, entries in lists.items():
        out[list_name] = [dict(e) for e in entries]
    return out


def broken_system() -> list[LaunchedProcess]:
    return [
        LaunchedProcess("demo/map_server", None, {"/robot/map_server": node(publishers=[
            {"name": "/robot/map", "type": "nav_msgs/msg/OccupancyGrid", "qos": "map"}])}),
        LaunchedProcess("demo/listener", "/robot/map_listener", {"/robot/map_listener": node(subscriptions=[
            {"name": "/robot/map", "type": STRING, "qos": "default"}])}),
        LaunchedProcess("demo/talker", "/robot/talker", {"/robot/talker": node(publishers=[
            {"name": "/robot/chatter", "type": STRING, "qos": "default"}])}),
        LaunchedProcess("demo/talker #2", "/robot/talker", {"/robot/talker": node(publishers=[
            {"name": "/robot/chatter", "type": STRING, "qos": "default"}])}),
        LaunchedProcess("demo/client", None, {"/robot/client": node(service_clients=[
            {"name": "/robot/enable_motor", "type": "std_srvs/srv/SetBool"}])}),
        LaunchedProcess("demo/silent", "/robot/silent", {}),
    ]


def build():
    processes = broken_system()
    return graph.build(processes, check_launched(processes), title="Broken <robot>")


def test_the_graph_marks_every_problem():
    g = build()
    by_label = {}
    for v in g.vertices.values():
        by_label.setdefault(v.label, []).append(v)
    # a type mismatch marks both edges of the connection
    marked = [(g.vertices[e.source].label, g.vertices[e.target].label, e.rules) for e in g.edges if e.marks]
    assert ("/robot/map_server", "/robot/map", ["TYPE_MISMATCH"]) in marked
    assert ("/robot/map", "/robot/map_listener", ["TYPE_MISMATCH"]) in marked
    # a client without server (nothing declares it comes from outside): its edge and the service
    assert ("/robot/enable_motor", "/robot/client", ["DANGLING_SERVICE_CLIENT"]) in marked
    service = by_label["/robot/enable_motor"][0]
    assert service.kind == "service" and service.severity is Severity.BREAKING
    # duplicate node names: both vertices; a process without its node: a vertex of its own
    talkers = by_label["/robot/talker"]
    assert len(talkers) == 2 and all(v.severity is Severity.BREAKING for v in talkers)
    missing = by_label["/robot/silent"][0]
    assert missing.kind == "missing" and missing.marks[0].rule == "LAUNCHED_NODE_NOT_CREATED"
    assert missing.id in g.groups["demo/silent"]
    # what fits is not marked
    chatter_edges = [e for e in g.edges if g.vertices[e.target].label == "/robot/chatter"]
    assert len(chatter_edges) == 2 and not any(e.marks for e in chatter_edges)
    assert g.vertices[chatter_edges[0].target].types == [STRING]
    # the two ends of a TYPE_MISMATCH: the topic keeps both types
    assert by_label["/robot/map"][0].types == ["nav_msgs/msg/OccupancyGrid", STRING]


def test_several_servers_mark_the_service_and_both_edges():
    processes = [LaunchedProcess(label, None, {f"/{label}": node(service_servers=[
        {"name": "/enable", "type": "std_srvs/srv/SetBool"}])}) for label in ("a", "b")]
    g = graph.build(processes, check_launched(processes))
    service = [v for v in g.vertices.values() if v.kind == "service"][0]
    assert [m.rule for m in service.marks] == ["SERVICE_MULTIPLE_SERVERS"]
    assert sorted(e.rules for e in g.edges) == [["SERVICE_MULTIPLE_SERVERS"], ["SERVICE_MULTIPLE_SERVERS"]]


def test_mermaid():
    text = graph.to_mermaid(build())
    assert text.startswith("flowchart LR\n")
    assert 'subgraph p0["demo/map_server"]' in text
    assert re.search(r'n\d+\["/robot/map_server"\]', text)
    assert re.search(r't\d+\(\["/robot/map<br/><small>nav_msgs/msg/OccupancyGrid</small>'
                     r'<br/><small>std_msgs/msg/String</small>"\]\)', text)
    assert re.search(r's\d+\{\{"/robot/enable_motor<br/><small>std_srvs/srv/SetBool</small><br/><b>DANGLING_SERVICE_CLIENT</b>"\}\}', text)
    assert re.search(r'n\d+ -- "TYPE_MISMATCH" --> t\d+', text)
    # every marked link is styled by its index among all links
    links = [line.strip() for line in text.splitlines() if "-->" in line]
    for index, link in enumerate(links):
        styled = f"linkStyle {index} stroke:" in text
        assert styled == ('-- "' in link), link
    assert "linkStyle" in text and "stroke:#d62728" in text
    assert "class " in text and "classDef breaking" in text
    assert "%% Broken <robot>" in text


def test_dot():
    text = graph.to_dot(build())
    assert text.startswith('digraph "Broken <robot>" {')
    assert 'subgraph cluster_0 { label="demo/map_server";' in text
    assert re.search(r'-> t\d+ \[color="#d62728", penwidth=3, fontcolor="#d62728", label="TYPE_MISMATCH"\]', text)
    assert re.search(r'n\d+ \[label="/robot/talker\\nDUPLICATE_NODE_NAME", shape=box, color="#d62728"', text)
    assert "style=dashed" in text  # the process that created no node
    assert text.count("{") == text.count("}")


class _Collector(HTMLParser):
    def __init__(self):
        super().__init__()
        self.tags: list[str] = []
        self.external: list[str] = []  # what the page would load
        self.links: list[str] = []  # where it links to

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)
        for key, value in attrs:
            if tag == "a" and key == "href":
                self.links.append(value)
            elif key in ("src", "href") and value and not value.startswith("#"):
                self.external.append(value)


def test_html_is_one_self_contained_page():
    page = graph.to_html(build(), threshold=Severity.BREAKING)
    collector = _Collector()
    collector.feed(page)
    assert collector.external == []  # nothing fetched
    # the legend and each rule id of the table link to the compatibility rules' documentation
    assert collector.links and set(collector.links) == {COMPATIBILITY_RULES}
    assert len(collector.links) == 1 + len(build().items)
    assert "script" not in collector.tags
    assert "svg" in collector.tags and "table" in collector.tags
    assert "<title>Broken &lt;robot&gt;</title>" in page
    assert "problem(s) at or above the threshold" in page
    assert page.count('class="edge marked"') == 3  # the two TYPE_MISMATCH edges and the client's
    assert 'data-rules="TYPE_MISMATCH"' in page and 'data-rules="DANGLING_SERVICE_CLIENT"' in page
    for rule in ("TYPE_MISMATCH", "DUPLICATE_NODE_NAME", "DANGLING_SERVICE_CLIENT", "LAUNCHED_NODE_NOT_CREATED"):
        assert f"<code>{rule}</code>" in page
    fine = graph.to_html(graph.build(broken_system()[2:3], []))
    assert "marked" not in fine.split("<svg", 1)[1].split("</svg>")[0]
    assert "No problem at or above the threshold" in fine and "All connections fit together." in fine


def test_render_dispatch():
    g = build()
    assert graph.render(g, "mermaid") == graph.to_mermaid(g)
    assert graph.render(g, "dot") == graph.to_dot(g)
    assert graph.render(g, "html").startswith("<!DOCTYPE html>")
    with pytest.raises(ValueError, match="unknown graph format 'png'"):
        graph.render(g, "png")


def test_dot_keeps_the_types_beside_the_rule_ids():
    text = graph.to_dot(build())
    # both types of the TYPE_MISMATCH topic; a marked service keeps its type above its rule id
    assert re.search(r't\d+ \[label="/robot/map\\nnav_msgs/msg/OccupancyGrid\\nstd_msgs/msg/String", shape=ellipse\]', text)
    assert re.search(r's\d+ \[label="/robot/enable_motor\\nstd_srvs/srv/SetBool\\nDANGLING_SERVICE_CLIENT", '
                     r'shape=hexagon', text)


def _rects(svg: str, cls: str) -> list[tuple[float, float, float, float]]:
    """left, top, right, bottom of the first <rect> of every element of class ``cls``."""
    found = []
    for match in re.finditer(rf'<g class="{cls}[^"]*"[^>]*>.*?<rect[^>]*?x="([\d.]+)" y="([\d.]+)" '
                             rf'width="([\d.]+)" height="([\d.]+)"', svg):
        x, y, w, h = map(float, match.groups())
        found.append((x, y, x + w, y + h))
    return found


def test_the_edge_labels_sit_between_the_columns_clear_of_every_box():
    """Long and stacked labels (two rules on one edge) widen the gap between the columns instead
    of covering a box; labels do not cover each other either. (The browser test measures the same
    on the rendered page, with the real fonts.)"""
    processes = [LaunchedProcess(f"p{i}", None, {f"/sub{i}": node(subscriptions=[
        {"name": "/raw", "type": STRING, "qos": {"reliability": "RELIABLE", "durability": "TRANSIENT_LOCAL"}},
        {"name": f"/odom{i}", "type": "nav_msgs/msg/Odometry"}])}) for i in range(5)]
    processes.append(LaunchedProcess("pub", None, {"/pub": node(publishers=[
        {"name": "/raw", "type": "std_msgs/msg/Int32", "qos": {"reliability": "BEST_EFFORT", "durability": "VOLATILE"}}])}))
    processes.append(LaunchedProcess("pub2", None, {"/pub2": node(publishers=[
        {"name": "/raw", "type": STRING, "qos": {"reliability": "BEST_EFFORT", "durability": "VOLATILE"}}])}))
    g = graph.build(processes, check_launched(processes))
    svg = graph.to_svg(g)
    boxes, labels = _rects(svg, "vertex"), _rects(svg, "edge-label")
    assert len(boxes) == len(g.vertices) and len(labels) == sum(1 for e in g.edges if e.marks) >= 10
    assert any("<text" in part and "TYPE_MISMATCH" in part and "QOS_INCOMPATIBLE" in part
               for part in svg.split('<g class="edge-label">')[1:]), "no edge with two rules: nothing stacked"

    def overlap(a, b):
        return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]

    assert [(label, box) for label in labels for box in boxes if overlap(label, box)] == []
    assert [(a, b) for i, a in enumerate(labels) for b in labels[i + 1:] if overlap(a, b)] == []


def test_a_box_of_a_marked_interface_keeps_its_type_and_adds_its_rule():
    svg = graph.to_svg(build())
    lines = {}
    for group in re.findall(r'<g class="vertex .*?</g>', svg):
        texts = re.findall(r">([^<>]+)</text>", group)
        lines.setdefault(texts[0], []).extend(texts[1:])
    assert lines["service /robot/enable_motor"] == ["std_srvs/srv/SetBool", "DANGLING_SERVICE_CLIENT"]
    assert lines["topic /robot/map"] == ["nav_msgs/msg/OccupancyGrid", STRING]  # both ends' types
    # a node: its process, then its rule
    assert lines["/robot/talker"] == ["demo/talker", "DUPLICATE_NODE_NAME", "demo/talker #2", "DUPLICATE_NODE_NAME"]
    assert lines["/robot/silent"] == ["demo/silent", "not created", "LAUNCHED_NODE_NOT_CREATED"]


def test_a_drawing_is_titled_by_what_it_draws():
    from pytest_rmw_introspect.cli.graph import drawing_title

    assert drawing_title(["contracts/talker.interfaces.yaml"], any_system=False) == "Node contract talker.interfaces.yaml"
    assert drawing_title(["a.yaml", "b/c.yaml"], any_system=False) == "Node contracts a.yaml, c.yaml"
    assert drawing_title(["robot.system.yaml"], any_system=True) == "System robot.system.yaml"
