"""The architecture of ARCHITECTURE.md, held: declared seams and the layers.

Declared seams: no module of rapp reaches into another's private names.

A name that starts with one underscore is a module's own business; what another module needs is
public (in its ``__all__``, documented) or lives where both can import it. The scan reads the
source (AST), so it sees ``from rapp.x import _y``, ``from .x import _y``, ``import rapp.x as m;
m._y`` and ``from rapp import x; x._y`` alike.
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "rapp"

#: Private names one module may still import from another, each with the reason (none today).
ALLOWED: set = set()


def module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


def crossings(path: Path, modules: set) -> list:
    """``(importer, owner, name, line)`` for each private name of another rapp module used here."""
    me = module_name(path)
    package = me if path.name == "__init__.py" else me.rpartition(".")[0]
    tree = ast.parse(path.read_text(encoding="utf-8"))
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
        elif isinstance(node, ast.Import):
            for a in node.names:
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
        "import rapp\nm._x(); a._x(); rapp.a._x(); a.__name__; m.public\n")
    monkeypatch.setattr(sys.modules[__name__], "PACKAGE", pkg)
    modules = {module_name(p) for p in pkg.rglob("*.py")}
    lines = sorted(line for *_, line in crossings(pkg / "sub" / "b.py", modules))
    assert lines == [1, 2, 6, 6, 6]
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
    "core": {"arm", "obstacles", "collision", "collision_kernel", "cspace", "cspace_kernel", "search", "ik", "ik_kernel", "symbolic", "trajectory",
             "heap", "jit", "time_scaling", "paths", "cartesian", "manipulability", "checks", "errors",
             "reference"},
    "planners": {"sampling", "sampling_kernel", "grid_route", "rrt", "rrt_connect", "rrt_star", "prm", "planners",
                 "progress"},
    "pipeline": {"scenario", "planner", "timing", "verify", "results", "compare", "files", "recorded",
                 "baseline", "traceability", "schema"},
    "drawing": {"plotting", "widgets", "view_stack", "palette", "raster", "live"},
    "interface": {"cli", "__main__", "__init__", "interrupts"},
    "teaching": {"exercises", "cases", "grading"},
}
DRAWING_LIBRARIES = {"matplotlib", "ipywidgets", "PIL", "IPython", "anywidget"}


def imports_of(path: Path) -> set:
    """Top-level names imported anywhere in ``path``: ``rapp.x`` as ``x``, others by package."""
    out = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
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
    missing = [m for m in top_modules() if f"`{m}`" not in layout and f"rapp/{m}/" not in layout]
    assert missing == [], "README's layout table does not name these modules"
