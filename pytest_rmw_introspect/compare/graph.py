"""A system drawn: nodes, topics, services and actions, with the compatibility rules' findings on them.

:func:`build` turns the processes of a system (``compare.compatibility.LaunchedProcess``: a system
contract's processes, or one per node contract) and the compatibility rules' items into a
:class:`SystemGraph`: a vertex per node (grouped by process) and per topic, service and action,
an edge per endpoint, from what offers to what requests (publisher → topic → subscription,
service server → service → client, action server → action → action client). Every item marks
what it is about, with its rule id: the two edges
of an incompatible connection, the edge and the interface of a requester without provider, the
vertices of duplicate node names, the interface and the edges of several servers, a process
that created no node.

Three renderings: :func:`to_mermaid` (renders in pull requests and issues inside a
```` ```mermaid ```` block), :func:`to_dot` (Graphviz: ``dot -Tsvg``), :func:`to_html` (one
self-contained page: an SVG drawn here, no script and nothing fetched, and the list of
problems). Marked edges and vertices are red (BREAKING) or orange (RISKY) and carry the rule id;
a vertex keeps its type names beside its rule ids (both of a TYPE_MISMATCH), and the HTML
drawing keeps every edge's label in the gap between two columns, clear of the boxes.
"""

from __future__ import annotations

import html
from collections.abc import Sequence
from dataclasses import dataclass, field

from ..model.project_urls import COMPATIBILITY_RULES
from ..model.vocabulary import DESTROYED_AT, LABELS, LISTS, OFFERING_LISTS, Severity
from .compatibility import CompatItem, LaunchedProcess

#: interface list → the kind of interface vertex it connects to
CATEGORY = {
    "publishers": "topic", "subscriptions": "topic",
    "service_servers": "service", "service_clients": "service",
    "action_servers": "action", "action_clients": "action",
}
COLORS = {Severity.BREAKING: "#d62728", Severity.RISKY: "#ff7f0e", Severity.SAFE: "#1f77b4", Severity.NOTE: "#7f7f7f"}
_CONNECTION_RULES = {"TYPE_MISMATCH", "TYPE_HASH_MISMATCH", "QOS_INCOMPATIBLE", "QOS_MAYBE_INCOMPATIBLE"}


@dataclass
class Mark:
    """A finding on a vertex or an edge."""

    rule: str
    severity: Severity
    message: str


@dataclass
class Vertex:
    id: str
    kind: str  # node, topic, service, action, missing
    label: str
    #: a node's process
    detail: str = ""
    group: str | None = None
    marks: list[Mark] = field(default_factory=list)
    #: a node the program destroyed while it ran: when (seconds of its virtual age)
    destroyed_at: float | None = None
    #: an interface's type names, in the order the endpoints name them: two or more when the
    #: ends disagree (TYPE_MISMATCH), so a drawing shows each of them
    types: list[str] = field(default_factory=list)

    @property
    def severity(self) -> Severity | None:
        return max((m.severity for m in self.marks), default=None)

    @property
    def rules(self) -> list[str]:
        return sorted({m.rule for m in self.marks})

    def detail_lines(self) -> list[str]:
        """What every drawing writes under the name (the rule ids come after): an interface's
        type names, one a line; that a launched node was not created; when it was destroyed."""
        lines = ["not created"] if self.kind == "missing" else list(self.types)
        if self.destroyed_at is not None:
            lines.append(destroyed_text(self.destroyed_at))
        return lines


@dataclass
class Edge:
    source: str
    target: str
    list_name: str
    marks: list[Mark] = field(default_factory=list)
    #: an interface (or its node) the program destroyed while it ran: when (seconds of virtual
    #: age); drawn dashed, with the age
    destroyed_at: float | None = None

    @property
    def severity(self) -> Severity | None:
        return max((m.severity for m in self.marks), default=None)

    @property
    def rules(self) -> list[str]:
        return sorted({m.rule for m in self.marks})


@dataclass
class SystemGraph:
    title: str
    vertices: dict[str, Vertex]
    edges: list[Edge]
    groups: dict[str, list[str]]  # process label → its node vertices
    items: list[CompatItem]

    def node_vertices(self) -> list[Vertex]:
        return [v for v in self.vertices.values() if v.kind in ("node", "missing")]

    def interface_vertices(self) -> list[Vertex]:
        return [v for v in self.vertices.values() if v.kind not in ("node", "missing")]


def build(processes: Sequence[LaunchedProcess], items: Sequence[CompatItem], title: str = "System") -> SystemGraph:
    """The graph of ``processes`` with ``items`` marked on it."""
    vertices: dict[str, Vertex] = {}
    edges: dict[tuple[str, str, str, str], Edge] = {}  # (process, node, list, name) → edge
    node_ids: dict[tuple[str, str], str] = {}
    interface_ids: dict[tuple[str, str], str] = {}
    groups: dict[str, list[str]] = {}

    def interface(category: str, name: str, type_name: str = "") -> str:
        key = (category, name)
        if key not in interface_ids:
            interface_ids[key] = f"{category[0]}{len(interface_ids)}"
            vertices[interface_ids[key]] = Vertex(interface_ids[key], category, name)
        types = vertices[interface_ids[key]].types
        if type_name and type_name not in types:
            types.append(type_name)
        return interface_ids[key]

    for process in processes:
        groups.setdefault(process.label, [])
        for fqn in sorted(process.nodes):
            vid = f"n{len(node_ids)}"
            node_ids[(process.label, fqn)] = vid
            node_entry = process.nodes[fqn] or {}
            node_destroyed = _age(node_entry.get(DESTROYED_AT))
            vertices[vid] = Vertex(vid, "node", fqn, process.label, group=process.label, destroyed_at=node_destroyed)
            groups[process.label].append(vid)
            for list_name in LISTS:
                for entry in node_entry.get(list_name) or []:
                    iid = interface(CATEGORY[list_name], str(entry.get("name")), str(entry.get("type") or ""))
                    source, target = (vid, iid) if list_name in OFFERING_LISTS else (iid, vid)
                    destroyed = _age(entry.get(DESTROYED_AT))
                    edges[(process.label, fqn, list_name, str(entry.get("name")))] = Edge(
                        source, target, list_name, destroyed_at=node_destroyed if destroyed is None else destroyed)

    def mark_edge(label: str, node: str, list_name: str, name: str, mark: Mark) -> None:
        edge = edges.get((label, node, list_name, name))
        if edge is not None:
            edge.marks.append(mark)

    for item in items:
        mark = Mark(item.rule, item.severity, item.message)
        requester, provider = item.requester, item.provider
        if item.rule == "LAUNCHED_NODE_NOT_CREATED":
            vid = f"m{len(vertices)}"
            vertices[vid] = Vertex(vid, "missing", requester.node if requester.node != "(unnamed)" else "no node",
                                   requester.label, group=requester.label, marks=[mark])
            groups.setdefault(requester.label, []).append(vid)
        elif requester.kind == "node":  # duplicate names, what a node ignores: the node vertices
            for end in (requester, provider):
                if end is not None and (end.label, end.node) in node_ids:
                    vertices[node_ids[(end.label, end.node)]].marks.append(mark)
        elif requester.kind in CATEGORY:
            if item.rule not in _CONNECTION_RULES:  # a missing peer, several servers: the interface too
                key = (CATEGORY[requester.kind], item.name)
                if key in interface_ids:
                    marked = vertices[interface_ids[key]]
                    if all(m.rule != item.rule for m in marked.marks):
                        marked.marks.append(mark)
            mark_edge(requester.label, requester.node, requester.kind, item.name, mark)
            if provider is not None:
                mark_edge(provider.label, provider.node, provider.kind, item.other_name or item.name, mark)
    ordered = sorted(edges.values(), key=lambda e: (e.source, e.target, e.list_name))
    return SystemGraph(title, vertices, ordered, groups, list(items))


def _age(value: object) -> float | None:
    return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else None


def destroyed_text(age: float | None) -> str:
    """``destroyed at 8 s`` for something the program destroyed while it ran ("" otherwise)."""
    return "" if age is None else f"destroyed at {age:g} s"


# ---------------------------------------------------------------------------- Mermaid


def _mermaid_text(text: str) -> str:
    return html.escape(text, quote=True).replace("&quot;", "#quot;").replace("&#x27;", "'")


_MERMAID_SHAPES = {"node": ('["', '"]'), "topic": ('(["', '"])'), "service": ('{{"', '"}}'),
                   "action": ('[["', '"]]'), "missing": ('["', '"]')}


def to_mermaid(graph: SystemGraph) -> str:
    """A Mermaid flowchart (wrap it in a ```` ```mermaid ```` block to render it on GitHub or GitLab)."""
    lines = ["flowchart LR", "  %% " + " ".join(graph.title.split())]
    for index, (label, members) in enumerate(graph.groups.items()):
        lines.append(f'  subgraph p{index}["{_mermaid_text(label)}"]')
        for vid in members:
            lines.append("    " + _mermaid_vertex(graph.vertices[vid]))
        lines.append("  end")
    for vertex in graph.interface_vertices():
        lines.append("  " + _mermaid_vertex(vertex))
    styles = []
    for index, edge in enumerate(graph.edges):
        words = " ".join(filter(None, [*edge.rules, destroyed_text(edge.destroyed_at)]))
        # a dotted link: what the program destroyed while it ran
        link = ("-.", ".->") if edge.destroyed_at is not None else ("--", "-->")
        if words:
            lines.append(f'  {edge.source} {link[0]} "{_mermaid_text(words)}" {link[1]} {edge.target}')
        else:
            lines.append(f"  {edge.source} --> {edge.target}")
        if edge.marks:
            styles.append(f"  linkStyle {index} stroke:{COLORS[edge.severity or Severity.SAFE]},stroke-width:3px")
    lines += styles
    lines.append(f"  classDef breaking fill:#fde0e0,stroke:{COLORS[Severity.BREAKING]},stroke-width:3px")
    lines.append(f"  classDef risky fill:#fff0dd,stroke:{COLORS[Severity.RISKY]},stroke-width:3px")
    for vertex in graph.vertices.values():
        if vertex.severity is not None and vertex.severity >= Severity.RISKY:
            lines.append(f"  class {vertex.id} {'breaking' if vertex.severity is Severity.BREAKING else 'risky'}")
    return "\n".join(lines) + "\n"


def _mermaid_vertex(vertex: Vertex) -> str:
    opening, closing = _MERMAID_SHAPES[vertex.kind]
    text = _mermaid_text(vertex.label)
    text += "".join(f"<br/><small>{_mermaid_text(line)}</small>" for line in vertex.detail_lines())
    if vertex.marks:
        text += "<br/><b>" + _mermaid_text(" ".join(vertex.rules)) + "</b>"
    return f"{vertex.id}{opening}{text}{closing}"


# ---------------------------------------------------------------------------- Graphviz


def _dot_text(text: str) -> str:
    return text.replace("\\", "\\\\").replace('"', '\\"')


_DOT_SHAPES = {"node": "box", "topic": "ellipse", "service": "hexagon", "action": "box3d", "missing": "box"}


def to_dot(graph: SystemGraph) -> str:
    """A Graphviz digraph (``dot -Tsvg system.dot -o system.svg``)."""
    lines = [f'digraph "{_dot_text(graph.title)}" {{', "  rankdir=LR;",
             '  node [fontname="Helvetica", fontsize=11]; edge [fontname="Helvetica", fontsize=10];']
    for index, (label, members) in enumerate(graph.groups.items()):
        lines.append(f'  subgraph cluster_{index} {{ label="{_dot_text(label)}"; style=rounded; color="#999999";')
        for vid in members:
            lines.append("    " + _dot_vertex(graph.vertices[vid]))
        lines.append("  }")
    for vertex in graph.interface_vertices():
        lines.append("  " + _dot_vertex(vertex))
    for edge in graph.edges:
        attributes = []
        words = " ".join(filter(None, [*edge.rules, destroyed_text(edge.destroyed_at)]))
        if edge.marks:
            color = COLORS[edge.severity or Severity.SAFE]
            attributes += [f'color="{color}"', "penwidth=3", f'fontcolor="{color}"']
        if edge.destroyed_at is not None:
            attributes.append("style=dashed")
        if words:
            attributes.append(f'label="{_dot_text(words)}"')
        lines.append(f"  {edge.source} -> {edge.target}{' [' + ', '.join(attributes) + ']' if attributes else ''};")
    lines.append("}")
    return "\n".join(lines) + "\n"


def _dot_vertex(vertex: Vertex) -> str:
    lines = [vertex.label, *vertex.detail_lines(), *([" ".join(vertex.rules)] if vertex.marks else [])]
    label = "\\n".join(_dot_text(line) for line in lines)  # Graphviz's own line break, \n
    attributes = [f'label="{label}"', f"shape={_DOT_SHAPES[vertex.kind]}"]
    if vertex.kind == "missing" or vertex.destroyed_at is not None:
        attributes.append("style=dashed")
    if vertex.marks:
        color = COLORS[vertex.severity or Severity.SAFE]
        attributes += [f'color="{color}"', "penwidth=3", f'fontcolor="{color}"']
    return f"{vertex.id} [{', '.join(attributes)}];"


# ---------------------------------------------------------------------------- HTML

_BOX_W, _IFACE_W, _GAP, _MARGIN = 250, 290, 18, 30
#: the least room between two columns (the edges' curves)
_COL_GAP = 170
#: a box: the baseline of its name, the height of each further line, the padding under the last
_FIRST_BASELINE, _LINE, _PAD = 19, 17, 10
#: the width of a character, generously (Helvetica/Arial capitals and wide letters): the box of
#: an edge's label is that wide, and a box's text is cut to fit it. By font: bold 13 px (a name),
#: 11 px (a type, a process), bold 11 px (a rule id)
_NAME_CHAR, _TEXT_CHAR, _RULE_CHAR = 8.2, 6.6, 7.8
#: the room kept between an edge's label and the boxes beside its column gap
_LABEL_CLEARANCE = 28


@dataclass(frozen=True)
class _Box:
    x: float
    y: float
    width: float
    height: float
    #: (text, font size, bold, colour) from the top
    lines: tuple[tuple[str, int, bool, str], ...]


def _box_lines(vertex: Vertex, stroke: str) -> list[tuple[str, int, bool, str]]:
    """The name (with the interface's kind), the node's process, the type names and notes, then
    each rule id on a line of its own: nothing replaces anything else."""
    kind_word = "" if vertex.kind in ("node", "missing") else vertex.kind + " "
    lines = [(kind_word + vertex.label, 13, True, "#222")]
    details = ([vertex.detail] if vertex.kind in ("node", "missing") and vertex.detail else []) + vertex.detail_lines()
    lines += [(text, 11, False, "#555") for text in details]
    lines += [(rule, 11, True, stroke) for rule in vertex.rules]
    return lines


def _label_lines(edge: Edge) -> list[str]:
    """An edge's label: its rule ids, one a line."""
    return edge.rules


def _label_width(lines: Sequence[str]) -> float:
    return max((len(line) for line in lines), default=0) * _RULE_CHAR + 10


def _layout(graph: SystemGraph) -> tuple[dict[str, _Box], float, float, float]:
    """Every vertex's box (providers left, interfaces in the middle, requesters right), the width
    and height of the drawing and the gap between its columns, wide enough for every edge's
    label to sit in it without touching a box."""
    offers: dict[str, int] = {}
    requests: dict[str, int] = {}
    neighbours: dict[str, list[str]] = {}
    for edge in graph.edges:
        node, iface = (edge.source, edge.target) if edge.list_name in OFFERING_LISTS else (edge.target, edge.source)
        counts = offers if edge.list_name in OFFERING_LISTS else requests
        counts[node] = counts.get(node, 0) + 1
        neighbours.setdefault(node, []).append(iface)
    interfaces = sorted(graph.interface_vertices(), key=lambda v: (v.kind != "topic", v.kind, v.label))
    rank = {v.id: i for i, v in enumerate(interfaces)}
    left: list[Vertex] = []
    right: list[Vertex] = []
    for vertex in graph.node_vertices():
        (right if requests.get(vertex.id, 0) > offers.get(vertex.id, 0) else left).append(vertex)

    def centre(vertex: Vertex) -> float:
        near = [rank[i] for i in neighbours.get(vertex.id, []) if i in rank]
        return sum(near) / len(near) if near else len(rank)

    gap = max([_COL_GAP, *(_label_width(_label_lines(e)) + 2 * _LABEL_CLEARANCE for e in graph.edges if e.marks)])
    boxes: dict[str, _Box] = {}
    columns = [(sorted(left, key=lambda v: (centre(v), v.label)), _MARGIN, _BOX_W),
               (interfaces, _MARGIN + _BOX_W + gap, _IFACE_W),
               (sorted(right, key=lambda v: (centre(v), v.label)), _MARGIN + _BOX_W + _IFACE_W + 2 * gap, _BOX_W)]
    height = 0.0
    for column, x, width in columns:
        y = _MARGIN + 20.0
        for vertex in column:
            lines = _box_lines(vertex, _stroke(vertex))
            box_height = _FIRST_BASELINE + _LINE * (len(lines) - 1) + _PAD
            boxes[vertex.id] = _Box(x, y, width, box_height, tuple(lines))
            y += box_height + _GAP
        height = max(height, y)
    return boxes, _MARGIN * 2 + 2 * _BOX_W + _IFACE_W + 2 * gap, height + _MARGIN, gap


_FILL = {"node": "#eef4fb", "topic": "#f4f4f4", "service": "#f1f8ee", "action": "#f7f0fa", "missing": "#ffffff"}


def _stroke(vertex: Vertex) -> str:
    return COLORS[vertex.severity] if vertex.severity is not None else "#888888"


def to_svg(graph: SystemGraph) -> str:
    """The graph as one SVG drawing (used by :func:`to_html`)."""
    boxes, width, height, gap = _layout(graph)
    e = html.escape
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}" '
           f'viewBox="0 0 {width:.0f} {height:.0f}" font-family="Helvetica, Arial, sans-serif" role="img">',
           "<defs>"]
    for name, color in (("plain", "#777777"), *((s.name.lower(), c) for s, c in COLORS.items())):
        out.append(f'<marker id="arrow-{name}" viewBox="0 0 10 10" refX="10" refY="5" markerUnits="userSpaceOnUse" '
                   f'markerWidth="11" markerHeight="11" orient="auto-start-reverse">'
                   f'<path d="M 0 0 L 10 5 L 0 10 z" fill="{color}"/></marker>')
    out.append("</defs>")
    headings = [("nodes", _MARGIN), ("topics, services, actions", _MARGIN + _BOX_W + gap),
                ("nodes", _MARGIN + _BOX_W + _IFACE_W + 2 * gap)]
    for heading, hx in headings:
        out.append(f'<text x="{hx}" y="{_MARGIN}" font-size="12" fill="#666">{e(heading)}</text>')
    labels = _LabelPlaces()
    for edge in sorted(graph.edges, key=lambda edge: edge.severity or -1):  # marked edges drawn last, on top
        if edge.source not in boxes or edge.target not in boxes:
            continue
        source, target = boxes[edge.source], boxes[edge.target]
        y1, y2 = source.y + source.height / 2, target.y + target.height / 2
        x1, x2 = (source.x + source.width, target.x) if source.x < target.x else (source.x, target.x + target.width)
        bend = (x2 - x1) / 2
        severity = edge.severity
        color = COLORS[severity] if severity is not None else "#999999"
        marker = severity.name.lower() if severity is not None else "plain"
        widthpx = 3.5 if severity is not None else 1.3
        title = "; ".join(filter(None, [*(f"{m.rule}: {m.message}" for m in edge.marks),
                                        destroyed_text(edge.destroyed_at)])) or LABELS[edge.list_name]
        edge_dash = ' stroke-dasharray="5 4"' if edge.destroyed_at is not None else ""
        out.append(f'<path class="edge{" marked" if edge.marks else ""}" data-rules="{e(" ".join(edge.rules))}" '
                   f'd="M {x1:.1f} {y1:.1f} C {x1 + bend:.1f} {y1:.1f}, {x2 - bend:.1f} {y2:.1f}, {x2:.1f} {y2:.1f}" '
                   f'fill="none" stroke="{color}" stroke-width="{widthpx}"{edge_dash} marker-end="url(#arrow-{marker})">'
                   f"<title>{e(title)}</title></path>")
        if edge.marks:
            lines = _label_lines(edge)
            mx, my = labels.place(lines, (x1, y1), (x2, y2))
            labels.drawn.append(_edge_label(lines, mx, my, color))
    for vertex in graph.vertices.values():
        if vertex.id in boxes:
            out.append(_vertex_box(vertex, boxes[vertex.id]))
    out += labels.drawn
    out.append("</svg>")
    return "\n".join(out)


def _label_height(lines: Sequence[str]) -> float:
    return 14 * len(lines) + 4


class _LabelPlaces:
    """Where the edges' labels go: on their edge, inside the gap between the two columns the edge
    joins (never over a box), and clear of the labels already placed where the edge allows."""

    #: how far along its edge a label may sit, tried in this order: the middle first, then
    #: outwards in small steps (a steep edge crosses the room a label fits in on a short stretch)
    ALONG = tuple(0.5 + sign * step / 50 for step in range(21) for sign in ((1,) if step == 0 else (-1, 1)))
    #: the least room kept between a label and a box
    CLEARANCE = 8

    def __init__(self) -> None:
        self.taken: list[tuple[float, float, float, float]] = []  # left, top, right, bottom
        self.drawn: list[str] = []

    def place(self, lines: Sequence[str], start: tuple[float, float], end: tuple[float, float]) -> tuple[float, float]:
        """The centre of the label of the edge from ``start`` to ``end`` (the points where it
        leaves one column and enters the other)."""
        width, height = _label_width(lines), _label_height(lines)
        low, high = sorted((start[0], end[0]))
        fitting = []
        for t in self.ALONG:
            x, y = _curve_point(start, end, t)
            if low + self.CLEARANCE <= x - width / 2 and x + width / 2 <= high - self.CLEARANCE:
                fitting.append((x, y))
        if not fitting:  # too steep to fit anywhere else: the middle (the gap is as wide as any label)
            fitting.append(_curve_point(start, end, 0.5))
        # on the edge if a place there is free; else beside its middle, a few lines up or down
        x0, y0 = fitting[0]
        beside = [(x0, y0 + sign * step * (height + 4)) for step in range(1, 9) for sign in (-1, 1)]
        for x, y in [*fitting, *beside]:
            rect = (x - width / 2 - 2, y - height / 2 - 2, x + width / 2 + 2, y + height / 2 + 2)
            if not any(rect[0] < r[2] and r[0] < rect[2] and rect[1] < r[3] and r[1] < rect[3] for r in self.taken):
                break
        else:
            x, y = x0, y0
            rect = (x - width / 2, y - height / 2, x + width / 2, y + height / 2)
        self.taken.append(rect)
        return x, y


def _curve_point(start: tuple[float, float], end: tuple[float, float], t: float) -> tuple[float, float]:
    """The point at ``t`` of an edge's curve (a cubic Bézier whose two control points are half
    way across, at the heights of its ends)."""
    (x1, y1), (x2, y2) = start, end
    mid = (x1 + x2) / 2
    a, b, c, d = (1 - t) ** 3, 3 * (1 - t) ** 2 * t, 3 * (1 - t) * t ** 2, t ** 3
    return a * x1 + (b + c) * mid + d * x2, (a + b) * y1 + (c + d) * y2


def _edge_label(lines: Sequence[str], mx: float, my: float, color: str) -> str:
    """A label centred on (mx, my), the middle of its edge: a box as wide as its longest line."""
    width, height = _label_width(lines), _label_height(lines)
    top = my - height / 2
    texts = "".join(f'<text x="{mx:.1f}" y="{top + 13 + 14 * i:.1f}" font-size="11" font-weight="bold" fill="{color}" '
                    f'text-anchor="middle">{html.escape(line)}</text>' for i, line in enumerate(lines))
    return (f'<g class="edge-label"><rect x="{mx - width / 2:.1f}" y="{top:.1f}" width="{width:.1f}" '
            f'height="{height}" rx="3" fill="#ffffff" stroke="{color}"/>{texts}</g>')


def _vertex_box(vertex: Vertex, box: _Box) -> str:
    severity = vertex.severity
    stroke = _stroke(vertex)
    fill = {Severity.BREAKING: "#fde0e0", Severity.RISKY: "#fff0dd"}.get(severity, _FILL[vertex.kind]) \
        if severity is not None else _FILL[vertex.kind]
    radius = 22 if vertex.kind == "topic" else 4
    dash = ' stroke-dasharray="6 4"' if vertex.kind == "missing" or vertex.destroyed_at is not None else ""
    title = "; ".join(f"{m.rule}: {m.message}" for m in vertex.marks) or vertex.kind
    out = [f'<g class="vertex {vertex.kind}{" marked" if vertex.marks else ""}" id="{vertex.id}">'
           f"<title>{html.escape(title)}</title>"
           f'<rect class="box" x="{box.x}" y="{box.y}" width="{box.width}" height="{box.height}" rx="{radius}" '
           f'fill="{fill}" stroke="{stroke}" stroke-width="{3 if severity is not None else 1.2}"{dash}/>']
    for index, (text, size, bold, color) in enumerate(box.lines):
        char = _NAME_CHAR if size == 13 else _RULE_CHAR if bold else _TEXT_CHAR
        weight = ' font-weight="bold"' if bold else ""
        out.append(f'<text x="{box.x + 10}" y="{box.y + _FIRST_BASELINE + _LINE * index}" font-size="{size}"{weight} '
                   f'fill="{color}">{html.escape(_clip(text, box.width - 20, char))}</text>')
    return "".join(out) + "</g>"


def _clip(text: str, room: float, char: float) -> str:
    limit = int(room / char)
    return text if len(text) <= limit else text[: limit - 1] + "…"


def to_html(graph: SystemGraph, *, threshold: Severity = Severity.BREAKING) -> str:
    """One self-contained HTML page: the drawing and the list of problems (no scripts, nothing
    fetched; the rule ids link to their documentation)."""
    e = html.escape
    rows = []
    for item in graph.items:
        color = COLORS[item.severity]
        ends = str(item.requester) if item.provider is None else f"{item.provider} → {item.requester}"
        rows.append(f'<tr><td><span class="sev" style="background:{color}">{e(item.severity.name)}</span></td>'
                    f'<td><a href="{e(COMPATIBILITY_RULES)}"><code>{e(item.rule)}</code></a></td>'
                    f"<td><code>{e(item.name)}</code></td>"
                    f"<td>{e(ends)}</td><td>{e(item.message)}</td></tr>")
    failing = sum(1 for item in graph.items if item.severity >= threshold)
    verdict = (f'<p class="verdict fail">{failing} problem(s) at or above the threshold</p>' if failing
               else '<p class="verdict pass">No problem at or above the threshold</p>')
    table = ("<table><thead><tr><th>severity</th><th>rule</th><th>name</th><th>where</th><th>why</th></tr></thead>"
             f"<tbody>{''.join(rows)}</tbody></table>") if rows else "<p>All connections fit together.</p>"
    nodes = len([v for v in graph.vertices.values() if v.kind == "node"])
    interfaces = len(graph.interface_vertices())
    return f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>{e(graph.title)}</title>
<style>
body {{ font-family: Helvetica, Arial, sans-serif; margin: 24px; color: #222; }}
h1 {{ font-size: 20px; margin: 0 0 4px 0; }}
.summary {{ color: #555; margin: 0 0 12px 0; }}
.verdict {{ font-weight: bold; margin: 8px 0 16px 0; }}
.verdict.fail {{ color: {COLORS[Severity.BREAKING]}; }}
.verdict.pass {{ color: #2a7d2a; }}
.drawing {{ overflow: auto; border: 1px solid #ddd; border-radius: 6px; background: #fff; }}
table {{ border-collapse: collapse; margin-top: 18px; font-size: 13px; }}
th, td {{ border-bottom: 1px solid #e4e4e4; padding: 6px 10px; text-align: left; vertical-align: top; }}
.sev {{ color: #fff; border-radius: 3px; padding: 1px 6px; font-size: 11px; }}
.legend {{ font-size: 12px; color: #555; margin-top: 10px; }}
</style>
</head>
<body>
<h1>{e(graph.title)}</h1>
<p class="summary">{nodes} node(s), {interfaces} topic(s), service(s) and action(s), {len(graph.groups)} process(es)</p>
{verdict}
<div class="drawing">
{to_svg(graph)}
</div>
<p class="legend">Arrows point from what offers to what requests: publisher → topic → subscription,
service server → service → client, action server → action → action client. Red: BREAKING, orange: RISKY,
each with its rule id: <a href="{e(COMPATIBILITY_RULES)}">the compatibility rules</a> say what each means.</p>
{table}
</body>
</html>
"""


def render(graph: SystemGraph, fmt: str, *, threshold: Severity = Severity.BREAKING) -> str:
    """``mermaid``, ``dot`` or ``html``."""
    if fmt == "mermaid":
        return to_mermaid(graph)
    if fmt == "dot":
        return to_dot(graph)
    if fmt == "html":
        return to_html(graph, threshold=threshold)
    raise ValueError(f"unknown graph format {fmt!r}: expected mermaid, dot or html")


FORMATS = ("mermaid", "dot", "html")

