"""``model/capture_file.py`` is the only module that reads the capture file's mappings (issue 41
item 2): every other module reads its typed records (``Capture.stimuli``, ``.quiescence``, ...).

How it is found, from the package's source (``ast``; nothing runs):

* A value *holds the capture document* when it is the ``raw`` attribute of anything
  (``Capture.raw`` is the document; the package's one other ``raw``, ``capture_view.Node.raw``,
  is a tuple of records and is never read by a string key), the result of
  ``capture_file.read``, a name assigned from such a value in the same function (also through
  ``x if c else y``, ``x or y``, ``dict(x)``, ``x.copy()``), or a parameter of a function that is
  called somewhere in the package with such a value for it. Calls are matched by the function's
  name alone (any function or method of that name, in any module), so a call can mark more
  parameters than it reaches: the scan errs on the side of finding too much.
* A module *reads a capture-file key* when it subscripts such a value with, calls ``.get``,
  ``.pop``, ``.setdefault`` or ``.__getitem__`` on it with, or tests ``in`` it for, one of the
  file's top-level keys (``TOP_LEVEL_KEYS``) written as a string literal.

Its limits, said plainly: a document that travels through a container (a list, a dict, an
attribute stored on an object other than ``raw``), a return value (except
``capture_file.read``'s), a class's constructor, ``*args``/``**kwargs``, ``getattr`` or a key
that is not a literal is not followed; neither is a capture file read with ``json`` directly. Those are not how the
package passes the document today; a reader written that way would get past this test, and the
review would have to catch it.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest_rmw_introspect

PACKAGE = Path(pytest_rmw_introspect.__file__).parent
#: the one reader of the capture file's mappings
READER = PACKAGE / "model" / "capture_file.py"

#: the top-level keys of a capture document (docs/design.md section 1; the middleware's
#: capture_writer.cpp, ``write_document``)
TOP_LEVEL_KEYS = frozenset({
    "format", "format_version", "format_minor", "rmw_implementation", "pid", "argv", "state", "settle_ms",
    "time_to_settle_ms", "elapsed_ms", "settled_by", "ever_waited", "activity_calls", "quiescence", "time",
    "probe", "stimuli", "component_loads", "ended", "nodes", "endpoints", "types",
})

_READS = ("get", "pop", "setdefault", "__getitem__")
_PASS_THROUGH = ("copy",)


def _modules() -> dict[Path, ast.Module]:
    return {path: ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
            for path in sorted(PACKAGE.rglob("*.py")) if "rmw_introspect_cpp" not in path.parts}


def _scopes(tree: ast.Module) -> list[ast.AST]:
    """The module and each function in it: the scopes names are tracked in."""
    return [tree, *(n for n in ast.walk(tree) if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef)))]


def _own_nodes(scope: ast.AST) -> list[ast.AST]:
    """The nodes of ``scope`` outside the functions nested in it."""
    out: list[ast.AST] = []
    stack = list(ast.iter_child_nodes(scope))
    while stack:
        node = stack.pop()
        out.append(node)
        if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            stack.extend(ast.iter_child_nodes(node))
    return out


def _is_read_call(node: ast.AST) -> bool:
    """``capture_file.read(...)`` (how the package calls it)."""
    if not isinstance(node, ast.Call):
        return False
    func = node.func
    return (isinstance(func, ast.Attribute) and func.attr == "read" and isinstance(func.value, ast.Name)
            and func.value.id == "capture_file")


def _holds_document(node: ast.AST | None, names: set[str]) -> bool:
    if node is None:
        return False
    if isinstance(node, ast.Attribute) and node.attr == "raw":
        return True
    if isinstance(node, ast.Name):
        return node.id in names
    if isinstance(node, ast.IfExp):
        return _holds_document(node.body, names) or _holds_document(node.orelse, names)
    if isinstance(node, ast.BoolOp):
        return any(_holds_document(v, names) for v in node.values)
    if isinstance(node, ast.NamedExpr):
        return _holds_document(node.value, names)
    if isinstance(node, ast.Call):
        if _is_read_call(node):
            return True
        func = node.func
        if isinstance(func, ast.Name) and func.id == "dict" and node.args:
            return _holds_document(node.args[0], names)
        if isinstance(func, ast.Attribute) and func.attr in _PASS_THROUGH:
            return _holds_document(func.value, names)
    return False


def _parameters(function: ast.FunctionDef | ast.AsyncFunctionDef) -> list[str]:
    return [a.arg for a in (*function.args.posonlyargs, *function.args.args)]


def _is_method(function: ast.AST, parents: dict[int, ast.AST]) -> bool:
    parent = parents.get(id(function))
    return isinstance(parent, ast.ClassDef) and not any(
        isinstance(d, ast.Name) and d.id == "staticmethod" for d in function.decorator_list)  # type: ignore[attr-defined]


def find_key_reads(modules: dict[Path, ast.Module], reader: Path) -> list[str]:
    """Every read of a top-level capture-file key outside ``reader``, as ``path:line: what``."""
    functions: dict[str, list[tuple[ast.AST, bool]]] = {}  # name → (function, is a method)
    scopes: list[tuple[Path, ast.AST, list[ast.AST]]] = []  # (module, scope, the scope's own nodes)
    for path, tree in modules.items():
        parents = {id(child): node for node in ast.walk(tree) for child in ast.iter_child_nodes(node)}
        for scope in _scopes(tree):
            scopes.append((path, scope, _own_nodes(scope)))
            if isinstance(scope, (ast.FunctionDef, ast.AsyncFunctionDef)):
                functions.setdefault(scope.name, []).append((scope, _is_method(scope, parents)))
    holding: dict[int, set[str]] = {}  # scope → the names in it that hold the document

    def mark_parameters(call: ast.Call, names: set[str]) -> bool:
        given = [i for i, arg in enumerate(call.args) if _holds_document(arg, names)]
        keywords = {k.arg for k in call.keywords if k.arg is not None and _holds_document(k.value, names)}
        if not given and not keywords:
            return False
        func = call.func
        called = func.attr if isinstance(func, ast.Attribute) else func.id if isinstance(func, ast.Name) else ""
        changed = False
        for function, method in functions.get(called, []):
            params = _parameters(function)  # type: ignore[arg-type]
            offset = 1 if method else 0  # self or cls
            marked = {params[i + offset] for i in given if i + offset < len(params)} | (keywords & set(params))
            scope = holding.setdefault(id(function), set())
            if not marked <= scope:
                scope |= marked
                changed = True
        return changed

    flow = [(scope, [n for n in own if isinstance(n, (ast.Assign, ast.AnnAssign, ast.NamedExpr, ast.Call))])
            for _path, scope, own in scopes]
    changed = True
    while changed:  # until no name or parameter is newly found to hold the document
        changed = False
        for scope, nodes in flow:
            names = holding.setdefault(id(scope), set())
            for node in nodes:
                if isinstance(node, ast.Call):
                    changed |= mark_parameters(node, names)
                    continue
                if node.value is None or not _holds_document(node.value, names):  # type: ignore[attr-defined]
                    continue
                targets = node.targets if isinstance(node, ast.Assign) else [node.target]  # type: ignore[attr-defined]
                for target in targets:
                    if isinstance(target, ast.Name) and target.id not in names:
                        names.add(target.id)
                        changed = True

    found = []
    for path, scope, own in scopes:
        if path == reader:
            continue
        names = holding.get(id(scope), set())
        for node in own:
            key, receiver = _key_read(node)
            if key in TOP_LEVEL_KEYS and _holds_document(receiver, names):
                found.append(f"{path.relative_to(PACKAGE.parent)}:{node.lineno}: {ast.unparse(node)}")  # type: ignore[attr-defined]
    return sorted(found)


def _literal(node: ast.AST | None) -> str | None:
    return node.value if isinstance(node, ast.Constant) and isinstance(node.value, str) else None


def _key_read(node: ast.AST) -> tuple[str | None, ast.AST | None]:
    """(the literal key, what it is read from) when ``node`` reads a key by a literal."""
    if isinstance(node, ast.Subscript):
        return _literal(node.slice), node.value
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr in _READS and node.args:
        return _literal(node.args[0]), node.func.value
    if isinstance(node, ast.Compare) and len(node.ops) == 1 and isinstance(node.ops[0], (ast.In, ast.NotIn)):
        return _literal(node.left), node.comparators[0]
    return None, None


def test_only_the_capture_file_module_reads_the_capture_file():
    reads = find_key_reads(_modules(), READER)
    assert reads == [], ("read these through the typed records of model/capture_file.py (add a record or a "
                         "field there when one is missing):\n" + "\n".join(reads))


def test_the_scan_finds_a_read_through_a_parameter_and_a_local_name():
    """The scan itself: a key read on ``.raw`` directly, on a name assigned from it, and in a function
    handed it (two calls away) are found; a read of the same key on other data, and in the
    reader, are not."""
    source = '''
def judge(capture):
    first = capture.raw.get("stimuli")
    document = capture.raw if capture is not None else {}
    second = document["quiescence"]
    return first, second, relay(capture.raw), unrelated({"stimuli": []})

def relay(doc):
    return inner(doc=doc)

def inner(doc):
    return "component_loads" in doc

def unrelated(options):
    return options.get("stimuli")
'''
    module = ast.parse(source)
    reader = ast.parse('def parse(data):\n    return data.get("stimuli")\nparse(capture.raw)\n')
    here, there = PACKAGE / "check" / "probe.py", READER
    reads = find_key_reads({here: module, there: reader}, READER)
    assert [r.split(": ", 1)[0].rsplit(":", 1)[1] for r in reads] == ["12", "3", "5"], reads
    assert all(r.startswith("pytest_rmw_introspect/check/probe.py:") for r in reads)


def test_the_top_level_keys_are_the_ones_the_reader_reads():
    """``TOP_LEVEL_KEYS`` is kept true: the reader reads each of them."""
    text = READER.read_text(encoding="utf-8")
    assert [key for key in sorted(TOP_LEVEL_KEYS) if f'"{key}"' not in text] == []
