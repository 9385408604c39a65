"""The import graph of spectex: no circles, nothing importing upward.

Every ``import`` inside the package, at the top of a module or inside a
function, is an edge from the importing module to the module it names (or,
for ``from m import name``, to ``m.name`` when that is a module). A circle is a
strongly connected set of two or more modules; an upward import is a module
importing a package that contains it (its ``__init__``), which runs the
package's own imports and is a circle in waiting.
"""

from __future__ import annotations

import ast
import pathlib

import spectex

SRC = pathlib.Path(spectex.__file__).parent

#: Circles still there, each with the reason. The test asks for this list exactly: none is left.
KNOWN_CIRCLES = []


def _module_name(path: pathlib.Path, src: pathlib.Path) -> str:
    parts = path.relative_to(src.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def import_graph(src: pathlib.Path = SRC) -> dict[str, set[str]]:
    """``{module: modules it imports}`` for every module of the package at ``src``."""
    paths = {_module_name(p, src): p for p in sorted(src.rglob("*.py"))}
    top = src.name
    graph = {}
    for name, path in paths.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        targets = set()
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                targets.update(alias.name for alias in node.names)
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package.split(".")[:len(package.split(".")) - (node.level - 1)]
                    module = ".".join(base + ([node.module] if node.module else []))
                else:
                    module = node.module or ""
                targets.update(f"{module}.{alias.name}" if f"{module}.{alias.name}" in paths else module
                               for alias in node.names)
        edges = set()
        for target in targets:
            if target.split(".")[0] != top:
                continue
            while target not in paths and "." in target:  # a name inside a module: the module
                target = target.rpartition(".")[0]
            if target != name:
                edges.add(target)
        graph[name] = edges
    return graph


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected sets of two or more modules (Tarjan), each sorted, sorted."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return sorted(found)


def upward(graph: dict[str, set[str]]) -> list[str]:
    """``"a.b.c -> a.b"`` for every module that imports a package containing it."""
    return sorted(f"{m} -> {t}" for m, targets in graph.items() for t in targets if m.startswith(t + "."))


def test_no_import_circles():
    assert circles(import_graph()) == KNOWN_CIRCLES


def test_nothing_imports_a_package_above_it():
    assert upward(import_graph()) == []


def test_the_graph_sees_the_imports_it_should():
    graph = import_graph()
    assert "spectex.spectral._filters" in graph["spectex.spectral._magnify_gl"]  # from ._filters import ...
    assert "spectex.render.cpu" in graph["spectex.render"]  # an import inside a function counts
    assert "spectex._version" in graph["spectex"]


def test_the_checks_find_a_circle_and_an_upward_import(tmp_path):
    # The control: a package with a circle (a <-> b, one side inside a function), a longer one
    # (c -> d -> e -> c) and a subpackage module importing its package; the checks must see them.
    pkg = tmp_path / "fake"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from . import b\n")
    (pkg / "b.py").write_text("def f():\n    from .a import thing\n")
    (pkg / "c.py").write_text("import fake.d\n")
    (pkg / "d.py").write_text("from .e import x\n")
    (pkg / "e.py").write_text("from fake import c\nimport numpy\n")
    (pkg / "sub" / "__init__.py").write_text("from .m import y\n")
    (pkg / "sub" / "m.py").write_text("from . import CONSTANT\nfrom .. import a\n")
    graph = import_graph(pkg)
    # (the package fake.sub imports m, which imports the package: a circle as well)
    assert circles(graph) == [["fake.a", "fake.b"], ["fake.c", "fake.d", "fake.e"], ["fake.sub", "fake.sub.m"]]
    assert upward(graph) == ["fake.sub.m -> fake.sub"]
    (pkg / "b.py").write_text("")  # cut one circle: it is gone, the others stay
    assert circles(import_graph(pkg)) == [["fake.c", "fake.d", "fake.e"], ["fake.sub", "fake.sub.m"]]


def below(graph: dict[str, set[str]], module: str, forbidden: tuple[str, ...], allowed: tuple[str, ...] = ()):
    """The imports of ``module`` into the packages ``forbidden`` (each with its submodules), ``allowed`` excepted."""
    return sorted(t for t in graph[module] if t not in allowed
                  and any(t == f or t.startswith(f + ".") for f in forbidden))


def test_the_texture_imports_nothing_from_the_shading_core_or_the_renderers():
    # The texture is plain data (issue 25): its derived resources are spectex.shading.resources',
    # its bake spectex.render's. Only the shading constants, a leaf of plain values, are shared.
    graph = import_graph()
    assert below(graph, "spectex.texture", ("spectex.shading", "spectex.render", "spectex.export"),
                 allowed=("spectex.shading.constants",)) == []
    assert graph["spectex.shading.constants"] == set()  # the leaf imports nothing of spectex
    # the control: the check sees an import of the shading core inside a method
    assert below(graph, "spectex.shading.tables", ("spectex.texture", "spectex.shading")) != []
    assert below(graph, "spectex.render.cpu", ("spectex.shading",), allowed=("spectex.shading.camera",)) != []
