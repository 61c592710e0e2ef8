"""The architecture of ARCHITECTURE.md, held: declared seams and the layers.

Declared seams: no module of rapp reaches into another's private names.

A name that starts with one underscore is a module's own business; what another module needs is
public (in its ``__all__``, documented) or lives where both can import it. The scan reads the
source (AST), so it sees ``from rapp.x import _y``, ``from .x import _y``, ``import rapp.x as m;
m._y`` and ``from rapp import x; x._y`` alike.
"""

from __future__ import annotations

import ast
import functools
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "rapp"

def parse(path: Path) -> ast.Module:
    """The syntax tree of ``path``, parsed once per text (every scan here walks the same files)."""
    return _parse(path.read_text(encoding="utf-8"))


@functools.lru_cache(maxsize=None)
def _parse(text: str) -> ast.Module:
    return ast.parse(text)


#: Private names one module may still import from another, each with the reason (none today).
ALLOWED: set = set()


def module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


def _private_prefix(module: str) -> str:
    """The dotted path of ``module`` up to its first private part (``rapp._x`` of ``rapp._x.y``), or ''."""
    parts = module.split(".")
    for i, part in enumerate(parts):
        if _private(part):
            return ".".join(parts[: i + 1])
    return ""


def _outside(me: str, module: str) -> bool:
    """True when ``module`` is private (:func:`_private_prefix`) and ``me`` is not inside it."""
    prefix = _private_prefix(module)
    return bool(prefix) and not (me == prefix or me.startswith(prefix + "."))


def crossings(path: Path, modules: set) -> list:
    """``(importer, owner, name, line)`` for each private name of another rapp module used here."""
    me = module_name(path)
    package = me if path.name == "__init__.py" else me.rpartition(".")[0]
    tree = parse(path)
    aliases, found = {}, []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(up + ([base] if base else []))
            for a in node.names:
                full = f"{base}.{a.name}"
                if full in modules:
                    aliases[a.asname or a.name] = full
                elif base.startswith("rapp") and base != me and _private(a.name):
                    found.append((me, base, a.name, node.lineno))
            # The package rule: a private module or package (rapp._x, rapp.x._y) is its
            # parent's own business too; what another module imports lives in a public one.
            if base.startswith("rapp") and _outside(me, base):
                found.append((me, base, "(private module)", node.lineno))
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.startswith("rapp") and _outside(me, a.name):
                    found.append((me, a.name, "(private module)", node.lineno))
                if a.name.startswith("rapp"):
                    aliases[a.asname or a.name.split(".")[0]] = a.name if a.asname else "rapp"
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and _private(node.attr):
            chain, v = [node.attr], node.value
            while isinstance(v, ast.Attribute):
                chain.append(v.attr)
                v = v.value
            if isinstance(v, ast.Name) and v.id in aliases:
                owner = ".".join([aliases[v.id]] + chain[:0:-1])
                if owner in modules and owner != me:
                    found.append((me, owner, node.attr, node.lineno))
    return found


def test_the_scan_finds_every_form_of_crossing(tmp_path, monkeypatch):
    pkg = tmp_path / "rapp"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "sub" / "__init__.py").write_text("")
    (pkg / "a.py").write_text("def _x(): pass\n")
    (pkg / "sub" / "b.py").write_text(
        "from rapp.a import _x\nfrom ..a import _x as y\nimport rapp.a as m\nfrom rapp import a\n"
        "import rapp\nm._x(); a._x(); rapp.a._x(); a.__name__; m.public\n"
        "from rapp._hidden import x\nimport rapp._hidden.y\nfrom rapp import __version__\n")
    monkeypatch.setattr(sys.modules[__name__], "PACKAGE", pkg)
    modules = {module_name(p) for p in pkg.rglob("*.py")}
    lines = sorted(line for *_, line in crossings(pkg / "sub" / "b.py", modules))
    assert lines == [1, 2, 6, 6, 6, 7, 8]
    assert crossings(pkg / "a.py", modules) == []


def test_no_module_imports_another_modules_private_name():
    files = sorted(PACKAGE.rglob("*.py"))
    modules = {module_name(p) for p in files}
    assert len(modules) > 40, "the scan reads the package"
    found = [c for p in files for c in crossings(p, modules)]
    bad = [f"{me}:{line} uses {owner}.{name}" for me, owner, name, line in found
           if (me, owner, name) not in ALLOWED]
    assert bad == []


@pytest.mark.parametrize("module", ["rapp.reference", "rapp.planners", "rapp.timing"])
def test_the_new_homes_are_documented(module):
    import importlib
    m = importlib.import_module(module)
    assert m.__doc__ and ">>>" in m.__doc__
    for name in m.__all__:
        assert getattr(m, name).__doc__ or not callable(getattr(m, name)), name


# --------------------------------------------------------------------------- the layers

#: The layers of ARCHITECTURE.md. Each module of rapp/ is in exactly one.
LAYERS = {
    "core": {"arm", "obstacles", "collision", "kernels", "motion", "cspace", "search", "ik", "symbolic", "trajectory",
             "heap", "jit", "time_scaling", "paths", "cartesian", "manipulability", "checks", "errors",
             "reference", "validity", "student_t"},
    # and every planner's own module, which the planner table names (planner_modules below)
    "planners": {"sampling", "planners", "progress"},
    "pipeline": {"scenario", "planner", "timing", "verify", "results", "compare", "journal", "files", "interrupts", "roadmap",
                 "recorded", "baseline", "traceability", "schema"},
    "drawing": {"plotting", "widgets", "view_stack", "palette", "raster", "live", "plot_arms", "plot_benchmark",
                "plot_cspace_views", "plot_ik", "plot_motion", "plot_search"},
    "interface": {"cli", "compare_command", "__main__", "__init__"},
    "teaching": {"exercises", "cases", "grading"},
}
DRAWING_LIBRARIES = {"matplotlib", "ipywidgets", "PIL", "IPython", "anywidget"}


def planner_modules() -> set:
    """The modules of the planner table's functions: a planner added to the table is in the
    planners layer by that alone (ARCHITECTURE.md, adding a planner)."""
    from rapp.planners import PLANNERS
    return {p.function.__module__.split(".")[1] for p in PLANNERS.values()}


LAYERS["planners"] |= planner_modules()


def imports_of(path: Path) -> set:
    """Top-level names imported anywhere in ``path``: ``rapp.x`` as ``x``, others by package."""
    out = set()
    for node in ast.walk(parse(path)):
        if isinstance(node, ast.ImportFrom) and node.module and not node.level:
            if node.module == "rapp":
                out |= {a.name for a in node.names}
            elif node.module.startswith("rapp."):
                out.add(node.module.split(".")[1])
            else:
                out.add(node.module.split(".")[0])
        elif isinstance(node, ast.Import):
            out |= {a.name.split(".")[1] if a.name.startswith("rapp.") else a.name.split(".")[0]
                    for a in node.names}
    return out


def top_modules():
    """Module name -> file; a subpackage's file is its ``__init__.py`` (its own imports)."""
    return {p.stem: p for p in PACKAGE.glob("*.py")} | {
        p.parent.name: p for p in PACKAGE.glob("*/__init__.py")}


def members(layer: str) -> set:
    return LAYERS[layer] & set(top_modules())


def test_every_module_has_a_layer():
    # A module removed may stay listed (rapp/raster.py is on its way out); a new one needs a layer.
    missing = set(top_modules()) - set().union(*LAYERS.values())
    assert not missing, f"add {sorted(missing)} to a layer here and in ARCHITECTURE.md"


@pytest.mark.parametrize("layer", ["core", "planners", "pipeline"])
def test_the_core_the_planners_and_the_pipeline_never_draw(layer):
    for name in members(layer):
        used = imports_of(top_modules()[name])
        assert not used & (DRAWING_LIBRARIES | LAYERS["drawing"]), (name, used & (
            DRAWING_LIBRARIES | LAYERS["drawing"]))


def test_planners_never_read_scenarios():
    for name in members("planners") | members("core"):
        assert not imports_of(top_modules()[name]) & (LAYERS["pipeline"] | LAYERS["interface"]), name


def test_the_library_never_imports_the_teaching_code():
    for layer in ("core", "planners", "pipeline", "drawing"):
        for name in members(layer):
            assert not imports_of(top_modules()[name]) & LAYERS["teaching"], name


def test_the_readme_layout_names_every_module():
    readme = (PACKAGE.parent / "README.md").read_text(encoding="utf-8")
    layout = readme.split("## Layout", 1)[1].split("\n## ", 1)[0]
    missing = [m for m in set(top_modules()) - planner_modules()
               if f"`{m}`" not in layout and f"rapp/{m}/" not in layout]
    assert missing == [], "README's layout table does not name these modules"


# --------------------------------------------------------------------------- the import graph

#: The layers' order, top first: a module may import its own layer and those above it.
ORDER = ["core", "planners", "pipeline", "drawing", "interface", "teaching"]

#: Imports allowed against the layer order, ``(importer, imported)`` with the reason. Short.
ALLOWED_UPWARD = {
}


def all_modules() -> dict:
    """Dotted name -> file, for every module of the package (subpackages' modules too)."""
    return {module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def import_edges(path: Path, modules: dict) -> set:
    """``(module, line)`` for each rapp module ``path`` imports, anywhere in it (functions too,
    and those under ``if TYPE_CHECKING:``: an annotation that names a module above is an arrow
    running back up as much as a call is).

    ``from rapp import x`` is the module ``rapp.x`` where that is a module, else ``rapp`` (the
    package's front door); ``from rapp.a import b`` likewise; relative imports are resolved.
    """
    me = module_name(path)
    package = me if path.name == "__init__.py" else me.rpartition(".")[0]
    out = set()
    tree = parse(path)
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(up + ([base] if base else []))
            if base != "rapp" and not base.startswith("rapp."):
                continue
            for a in node.names:
                full = f"{base}.{a.name}"
                out.add((full if full in modules else base, node.lineno))
        elif isinstance(node, ast.Import):
            out |= {(a.name, node.lineno) for a in node.names
                    if a.name == "rapp" or a.name.startswith("rapp.")}
    return out


def graph() -> dict:
    modules = all_modules()
    return {m: {t for t, _ in import_edges(p, modules) if t != m} for m, p in modules.items()}


def layer_of(module: str) -> str:
    parts = module.split(".")
    top = "__init__" if len(parts) == 1 else parts[1]
    found = [name for name, members in LAYERS.items() if top in members]
    assert len(found) == 1, f"{module} is in {found or 'no'} layer"
    return found[0]


def cycles(edges: dict) -> list:
    """The strongly connected components of more than one module (Tarjan), each sorted."""
    index, low, stack, on, out, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(edges.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return out


def test_the_cycle_finder_finds_cycles():
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert cycles({"a": {"b"}, "b": set()}) == []


def test_the_edges_include_imports_inside_functions(tmp_path, monkeypatch):
    pkg = tmp_path / "rapp"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("")
    (pkg / "b.py").write_text("def f():\n    from rapp import a\n    import rapp\n    from . import a as c\n")
    monkeypatch.setattr(sys.modules[__name__], "PACKAGE", pkg)
    modules = all_modules()
    assert import_edges(pkg / "b.py", modules) == {("rapp.a", 2), ("rapp", 3), ("rapp.a", 4)}


#: Imports allowed to close a cycle, ``(importer, imported)``: with the reason. Short.
#: None today: time_path, which needs the trapezoid and the peak rates, lives in
#: rapp.time_scaling above the polynomials of rapp.trajectory.
ALLOWED_CYCLE: set = set()


def test_no_import_cycle():
    edges = {m: {t for t in ts if (m, t) not in ALLOWED_CYCLE} for m, ts in graph().items()}
    assert cycles(edges) == []


def test_imports_for_type_checkers_are_edges_too(tmp_path, monkeypatch):
    pkg = tmp_path / "rapp"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("")
    (pkg / "b.py").write_text("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n"
                              "    from rapp.a import x\nimport rapp.a\n")
    monkeypatch.setattr(sys.modules[__name__], "PACKAGE", pkg)
    assert import_edges(pkg / "b.py", all_modules()) == {("rapp.a", 3), ("rapp.a", 4)}


def test_every_import_follows_the_layer_order():
    bad = []
    for importer, targets in graph().items():
        for target in targets:
            if ORDER.index(layer_of(target)) > ORDER.index(layer_of(importer)) \
                    and (importer, target) not in ALLOWED_UPWARD:
                bad.append(f"{importer} ({layer_of(importer)}) imports {target} ({layer_of(target)})")
    assert sorted(bad) == []


def test_nothing_in_the_package_imports_the_reference_implementations():
    assert [m for m, targets in graph().items() if "rapp.reference" in targets] == []


#: What the oracle may take from rapp.collision: the contract's limit, and the thick-link
#: reduction its occupancy paints (itself checked against reference.capsule_distance in
#: tests/test_thick_links.py). No geometry: the oracle computes its own.
ORACLE_MAY_IMPORT = {"rapp.collision": {"MAX_PENDING_INTERVALS", "scene"}}


def test_the_oracle_shares_no_code_with_the_kernels():
    tree = parse(PACKAGE / "reference.py")
    bad = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            base = node.module or ""
            names = {a.name for a in node.names}
            if base.startswith("rapp.kernels") or base.startswith("rapp._kernels") \
                    or base == "rapp" and names & {"kernels", "_kernels", "collision", "cspace", "search"}:
                bad.append(f"{base}: {sorted(names)}")
            elif base in ORACLE_MAY_IMPORT and not names <= ORACLE_MAY_IMPORT[base]:
                bad.append(f"{base}: {sorted(names - ORACLE_MAY_IMPORT[base])}")
        elif isinstance(node, ast.Import):
            bad += [a.name for a in node.names if a.name.startswith(("rapp.kernels", "rapp._kernels",
                                                                     "rapp.collision"))]
    assert bad == []
    # and nothing reaches the kernels at run time either: the names it uses are its own
    import rapp.reference as oracle
    for name in oracle.__all__:
        assert getattr(oracle, name).__module__ == "rapp.reference", name


def test_no_test_reaches_another_folder_through_sys_path():
    # Shared scenes live in tests/scenes.py, helpers in tests/helpers.py (imported as
    # tests.scenes, tests.helpers); scripts are loaded from their file (helpers.load_script).
    found = []
    for path in sorted((PACKAGE.parent / "tests").rglob("*.py")):
        for node in ast.walk(parse(path)):
            f = node.func if isinstance(node, ast.Call) else None
            if isinstance(f, ast.Attribute) and f.attr in ("insert", "append", "extend") \
                    and isinstance(f.value, ast.Attribute) and f.value.attr == "path" \
                    and isinstance(f.value.value, ast.Name) and f.value.value.id == "sys":
                found.append(f"{path.name}:{node.lineno}")
    assert found == []


# --------------------------------------------------------------------------- kernels that read

#: Internal functions still over the limits, to be cut down (issue 36); a new one may not join.
LONG_OR_WIDE: set = set()


def internal_functions():
    """``(qualified name, parameters, lines of body without the docstring)`` of every private
    function of rapp (``_name``, or any function of a private module)."""
    for path in sorted(PACKAGE.rglob("*.py")):
        module = module_name(path)
        for node in ast.walk(parse(path)):
            if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            if not (_private(node.name) or "._" in module):
                continue
            a = node.args
            params = (len(a.posonlyargs) + len(a.args) + len(a.kwonlyargs) + bool(a.vararg)
                      + bool(a.kwarg))
            body = node.body
            if isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
                    and isinstance(body[0].value.value, str):
                body = body[1:]
            lines = node.end_lineno - body[0].lineno + 1 if body else 0
            yield f"{module}.{node.name}", params, lines


def test_no_internal_function_takes_more_than_12_parameters_or_runs_over_80_lines():
    measured = list(internal_functions())
    assert len(measured) > 100, "the scan reads the package"
    over = {name for name, params, lines in measured if params > 12 or lines > 80}
    assert over - LONG_OR_WIDE == set(), "pass a scene, a grid or buffers as a named tuple"
    assert LONG_OR_WIDE - over == set(), "cut down: remove it from LONG_OR_WIDE"
