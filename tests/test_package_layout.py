"""The package layout: no import cycles among rotorkit's modules, no private names imported across modules,
and the old import paths of moved modules still give the same objects.

The import graph is read from the source with :mod:`ast` (nothing is imported to build it). A module imports
another when it has, anywhere (at module level or inside a function: a function-level import is still a
dependency, only a later one):

- ``import rotorkit.a.b`` or ``from rotorkit.a import b`` (``b`` a submodule): an edge to ``rotorkit.a.b``;
- ``from rotorkit.a import name`` (``name`` not a submodule): an edge to ``rotorkit.a`` (its ``__init__``);
- relative imports (``from . import x``, ``from ..x import y``) resolved the same way;
- when the importer is outside package ``rotorkit.a``, importing ``rotorkit.a.b`` also runs ``rotorkit.a``'s
  ``__init__``: an edge to ``rotorkit.a`` as well. (From inside the package the ``__init__`` is already
  running or done, so a submodule importing a sibling is not counted as importing its own package.)
- an old path of a moved module (``rotorkit.analysis.campbell``, see :data:`rotorkit.analysis.MOVED`) is the
  module at its new path.

Dynamic imports (``importlib.import_module`` with a computed name, as in the lazy ``__getattr__`` of
``rotorkit/__init__.py``) are not edges: they name no module in the source, and they only run on first
attribute access, after every module involved has finished importing.

A private name (one starting with ``_``) is private to its module: no other module imports it
(``from rotorkit.a import _helper``) or reaches it through an imported module (``from rotorkit import a`` then
``a._helper``). A name two modules share is public in its home module (a module meant to be shared, such as
``rotorkit.engines.rk_common``, exports public names), or it moves to a module both import.

There are no exceptions: no cycle, no private import.
"""

import ast
import importlib
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1] / "rotorkit"

def _modules():
    out = {}
    for path in sorted(ROOT.rglob("*.py")):
        parts = list(path.relative_to(ROOT.parent).with_suffix("").parts)
        is_package = parts[-1] == "__init__"
        if is_package:
            parts.pop()
        out[".".join(parts)] = (path, is_package)
    return out


MODULES = _modules()


def _moved():
    import rotorkit.analysis

    return dict(rotorkit.analysis.MOVED)


MOVED = _moved()


def _existing(name):
    """The module ``name`` is (after the moved-module aliases), or its deepest existing parent."""
    name = MOVED.get(name, name)
    while name not in MODULES and "." in name:
        name = name.rsplit(".", 1)[0]
    return MOVED.get(name, name)


def _base(module, is_package, node):
    if not node.level:
        return node.module
    parts = module.split(".") if is_package else module.split(".")[:-1]
    parts = parts[: len(parts) - (node.level - 1)]
    return ".".join(parts + ([node.module] if node.module else []))


def _parents_outside(importer, target):
    """The packages above ``target`` whose __init__ runs when ``importer`` imports it (those not holding it)."""
    parts = target.split(".")
    return [p for p in (".".join(parts[:i]) for i in range(2, len(parts)))
            if not (importer == p or importer.startswith(p + "."))]


def module_imports(module, is_package, tree):
    """``(targets, private)`` of one module's syntax tree: ``[(imported module, line)]`` and the private names it
    takes from other modules, ``[(module, home, name, line)]`` (imported, or read as ``home_alias._name``)."""
    targets, private, aliases = [], [], {}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                if a.name.split(".")[0] == "rotorkit":
                    targets.append((_existing(a.name), node.lineno))
                    if a.asname:
                        aliases[a.asname] = _existing(a.name)
        elif isinstance(node, ast.ImportFrom):
            base = _base(module, is_package, node)
            if not base or base.split(".")[0] != "rotorkit":
                continue
            for alias in node.names:
                sub = MOVED.get(f"{base}.{alias.name}", f"{base}.{alias.name}")
                if sub in MODULES:
                    targets.append((sub, node.lineno))
                    aliases[alias.asname or alias.name] = sub
                    continue
                target = _existing(base)
                targets.append((target, node.lineno))
                if alias.name.startswith("_") and target != module:
                    private.append((module, target, alias.name, node.lineno))
    for node in ast.walk(tree):  # module._name, where module is an imported rotorkit module
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id in aliases \
                and node.attr.startswith("_") and not node.attr.startswith("__") \
                and aliases[node.value.id] != module:
            private.append((module, aliases[node.value.id], node.attr, node.lineno))
    return targets, private


def import_graph():
    """``(edges, private)``: module -> {imported module: line}, and the private names imported across modules."""
    edges = {m: {} for m in MODULES}
    private = []
    for module, (path, is_package) in MODULES.items():
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        targets, found = module_imports(module, is_package, tree)
        private += found
        for target, line in targets:
            for t in [*_parents_outside(module, target), target]:
                if t != module:
                    edges[module].setdefault(t, line)
    return edges, private


def strongly_connected(edges):
    """The strongly connected components of more than one module (Tarjan, iterative)."""
    index, low, on_stack, stack, out, counter = {}, {}, set(), [], [], [0]
    for root in edges:
        if root in index:
            continue
        work = [(root, iter(edges[root]))]
        index[root] = low[root] = counter[0]
        counter[0] += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            v, children = work[-1]
            for w in children:
                if w not in edges:
                    continue
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(edges[w])))
                    break
                if w in on_stack:
                    low[v] = min(low[v], index[w])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[v])
                if low[v] == index[v]:
                    component = set()
                    while True:
                        w = stack.pop()
                        on_stack.discard(w)
                        component.add(w)
                        if w == v:
                            break
                    if len(component) > 1:
                        out.append(frozenset(component))
    return out


def one_cycle(edges, component):
    """A cycle through the component, as ``a (line) -> b (line) -> ... -> a``, to name in a failure."""
    start = min(component)
    paths = {start: [start]}
    frontier = [start]
    while frontier:
        nxt = []
        for v in frontier:
            for w in sorted(edges[v]):
                if w == start:
                    path = paths[v] + [start]
                    return " -> ".join(f"{a} (line {edges[a][b]})" for a, b in zip(path, path[1:])) + f" -> {start}"
                if w in component and w not in paths:
                    paths[w] = paths[v] + [w]
                    nxt.append(w)
        frontier = nxt
    return str(sorted(component))


EDGES, PRIVATE = import_graph()


def test_the_graph_sees_imports():
    """The parser finds the edges it must: relative, absolute, function-level, submodule and old-path imports."""
    assert "rotorkit.errors" in EDGES["rotorkit.linear.campbell"]  # from ..errors import ParameterError
    assert "rotorkit.linear.linear_model" in EDGES["rotorkit.linear.speed_modes"]  # inside a function
    assert "rotorkit.signals.sampling" in EDGES["rotorkit.signals.spectra"]
    assert "rotorkit.linear.campbell" in EDGES["rotorkit.analysis.modes"]  # the shim imports from the new home
    assert "rotorkit.signals" in EDGES["rotorkit.analysis"]  # from ..signals import ... (the package)
    assert {"rotorkit.plotting", "rotorkit.plotting.campbell"} <= set(EDGES["rotorkit.linear.campbell_result"])
    cyclic = {"a": {"b": 1}, "b": {"c": 2}, "c": {"a": 3}, "d": {"a": 4}}
    assert strongly_connected(cyclic) == [frozenset("abc")]
    assert one_cycle(cyclic, frozenset("abc")) == "a (line 1) -> b (line 2) -> c (line 3) -> a"


def test_private_names_are_seen():
    """The private-name check finds an imported private name and one read through an imported module."""
    source = ("from rotorkit.engines import rk_common\nfrom rotorkit.codegen.emit import _x, hoist\n"
              "from . import cache as c\n\ndef f():\n    return rk_common._y, c._z, c.__name__, hoist\n")
    _, private = module_imports("rotorkit.codegen.demo", False, ast.parse(source))
    assert sorted(private) == [("rotorkit.codegen.demo", "rotorkit.codegen.cache", "_z", 6),
                               ("rotorkit.codegen.demo", "rotorkit.codegen.emit", "_x", 2),
                               ("rotorkit.codegen.demo", "rotorkit.engines.rk_common", "_y", 6)]


def test_no_import_cycles():
    found = strongly_connected(EDGES)
    assert not found, "import cycles:\n" + "\n".join(one_cycle(EDGES, c) for c in found)


def test_no_private_imports_across_modules():
    assert not PRIVATE, "private names used across modules (make them public in their home, or move them):\n" + \
        "\n".join(f"{a} line {line}: {b}.{name}" for a, b, name, line in PRIVATE)


def test_analysis_packages_are_clean():
    """The packages issue 24 laid out: no cycle touches them, no private import into or out of them."""
    ours = ("rotorkit.analysis", "rotorkit.linear", "rotorkit.signals")
    touched = [sorted(c) for c in strongly_connected(EDGES) if any(m.startswith(ours) for m in c)]
    assert not touched
    assert not [p for p in PRIVATE if p[0].startswith(ours) or p[1].startswith(ours)]


def test_internal_code_imports_the_new_homes():
    """Only the old paths' own machinery (rotorkit.analysis) refers to the old module paths."""
    old = set(MOVED)
    offenders = []
    for module, (path, is_package) in MODULES.items():
        if module == "rotorkit.analysis":
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom):
                base = _base(module, is_package, node) or ""
                names = [base] + [f"{base}.{a.name}" for a in node.names]
            elif isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            else:
                continue
            offenders += [f"{module} line {node.lineno}: {n}" for n in names if n in old]
    assert not offenders, offenders


@pytest.mark.parametrize("old, new", sorted(MOVED.items()))
def test_old_paths_are_the_moved_modules(old, new):
    assert importlib.import_module(old) is importlib.import_module(new)
    assert sys.modules[old] is sys.modules[new]
    assert sys.modules[new].__spec__.name == new  # the alias leaves the module's own spec alone
    parent, _, leaf = old.rpartition(".")
    assert getattr(importlib.import_module(parent), leaf) is sys.modules[new]


def test_old_import_statements_still_work():
    from rotorkit.analysis.campbell import Campbell, campbell
    from rotorkit.analysis.signals import Spectrum, find_peaks, label_orders
    from rotorkit.analysis.unbalance import unbalance_response
    from rotorkit.linear.campbell import Campbell as campbell_class
    from rotorkit.linear.unbalance import unbalance_response as new_unbalance_response
    from rotorkit.signals import orders, peaks, spectra

    assert Campbell is campbell_class and campbell.__module__ == "rotorkit.linear.campbell"
    assert unbalance_response is new_unbalance_response
    assert (Spectrum, find_peaks, label_orders) == (spectra.Spectrum, peaks.find_peaks, orders.label_orders)


def test_the_modes_module_keeps_its_former_names():
    import rotorkit.analysis.modes as old

    homes = {"natural_frequencies": "modes", "averaged_jacobian": "modes", "Modes": "modal", "Campbell": "campbell",
             "campbell": "campbell", "LinearModel": "linear_model", "linear_model": "linear_model",
             "linearize": "linearize", "static_equilibrium": "linearize", "DEFAULT_CAGE_SAMPLES": "linearize",
             "DEFAULT_EQUILIBRIUM_TOL": "linearize", "DEFAULT_RELATIVE_STEP": "linearize"}
    assert set(old.__all__) == set(homes)
    for name, home in homes.items():
        assert getattr(old, name) is getattr(importlib.import_module(f"rotorkit.linear.{home}"), name), name


def test_analysis_package_still_exports_the_signal_functions():
    import rotorkit.analysis as analysis
    import rotorkit.signals as signals

    assert set(analysis.__all__) == set(signals.__all__)
    for name in analysis.__all__:
        assert getattr(analysis, name) is getattr(signals, name)


def test_linear_package_entries():
    """One module per analysis, its entry named in the package docstring; the first ones also at the top level."""
    import rotorkit
    import rotorkit.linear

    entries = {"linear_model": "linear_model", "natural_frequencies": "modes", "campbell": "campbell",
               "critical_speed_map": "critical_map", "unbalance_response": "unbalance", "frequency_response": "frf",
               "static_deflection": "static", "static_equilibrium": "linearize", "linearize": "linearize"}
    for entry, module in entries.items():
        function = getattr(importlib.import_module(f"rotorkit.linear.{module}"), entry)
        assert callable(function) and f":func:`{entry}`" in rotorkit.linear.__doc__, entry
        if entry in rotorkit.__all__:
            assert getattr(rotorkit, entry) is function


def test_every_package_is_installed():
    """Each folder of rotorkit with an ``__init__.py`` is listed in pyproject's packages (else a
    non-editable install, as in CI, lacks it)."""
    import tomllib

    root = Path(__file__).resolve().parents[1]
    listed = set(tomllib.loads((root / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    found = {
        ".".join(p.parent.relative_to(root).parts)
        for p in (root / "rotorkit").rglob("__init__.py")
        if "__pycache__" not in p.parts
    }
    assert found - listed == set(), f"add to pyproject.toml [tool.setuptools] packages: {sorted(found - listed)}"
