"""Every chapter runs from an empty folder with only rapp installed.

A reader who downloads one notebook, or opens it next to an installed package, has no
``benchmarks/``, ``book/`` or ``tests/`` around it. Two checks hold that:

- statically, here and fast: no code cell of a chapter names a path outside its own folder
  (``..``, ``benchmarks/``, ``book/``, ``scripts/``, ``_toc.yml``) or puts the repository on the
  import path;
- by running every chapter alone: ``tests/notebook_kernels.py``, installed by the root
  ``conftest.py``, starts the kernel of each notebook that
  nbval checks in an empty temporary folder holding a copy of that notebook only, with
  ``PYTHONPATH`` reduced to a folder that holds ``rapp`` and nothing else of the repository
  (:func:`notebook_kernels.alone`). So the run that checks the committed outputs is the stand-alone run,
  for every chapter, at no extra cost; the slow test below proves that the mechanism does what it
  says, with nbclient on a notebook that looks around.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import nbformat
import nbval.plugin
import pytest

import notebook_kernels as kernels  # what the root conftest.py installs

ROOT = Path(__file__).resolve().parent.parent
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))

# A string literal that leaves the notebook's folder or names the repository's other folders,
# and the ways of reaching the repository's code without installing it.
OUTSIDE = [
    (re.compile(r"""["']\.\.(?:["'/\\]|$)"""), "a path through '..'"),
    (re.compile(r"""["'][^"'\n]*\b(?:benchmarks|book|scripts|notebooks)/"""), "a path into the repository"),
    (re.compile(r"_toc\.yml|\bPath\(__file__\)"), "a file of the repository"),
    (re.compile(r"\bsys\.path\b|spec_from_file_location"), "the import path changed by hand"),
    (re.compile(r"^\s*(?:import|from)\s+(?:benchmarks|tests|scripts|conftest)\b", re.M),
     "an import from outside rapp"),
]


def outside_references(path: Path) -> list[str]:
    """Lines of the code cells of ``path`` that reach outside the notebook's own folder."""
    nb = nbformat.read(path, as_version=4)
    found = []
    for k, cell in enumerate(nb.cells):
        if cell.cell_type != "code":
            continue
        for pattern, what in OUTSIDE:
            for m in pattern.finditer(cell.source):
                line = cell.source[:m.start()].count("\n") + 1
                found.append(f"cell {k}, line {line}: {what}: {m.group(0).strip()!r}")
    return found


def _params():
    for path in NOTEBOOKS:
        marks = []
        if path.name in kernels.RUN_IN_PLACE:
            marks = [pytest.mark.xfail(strict=True, reason=kernels.RUN_IN_PLACE[path.name])]
        yield pytest.param(path, id=path.stem, marks=marks)


@pytest.mark.parametrize("path", list(_params()))
def test_no_code_cell_reaches_outside_its_folder(path):
    assert outside_references(path) == []


def test_the_scan_finds_what_chapters_used_to_do():
    cells = ['ROOT = Path("..").resolve()', 'json.loads((ROOT / "benchmarks" / "results" / "x.json").read_text())',
             'sys.path.insert(0, str(ROOT / "benchmarks"))', 'import baseline', 'from tests import x',
             'open("../book/traceability.json")', 'x = a[..., 0]  # an Ellipsis is fine',
             'print("tests/test_arm.py::test_x")  # a node id is not a path']
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(c) for c in cells])
    found = "\n".join(outside_references_of(nb))
    for k in (0, 2, 4, 5):
        assert f"cell {k}," in found, (k, found)
    assert "cell 6," not in found and "cell 7," not in found


def outside_references_of(nb) -> list[str]:
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "x.ipynb"
        nbformat.write(nb, path)
        return outside_references(path)


def test_nbval_runs_every_chapter_alone():
    # The hook is installed, and only the chapters listed in RUN_IN_PLACE are exempt.
    assert nbval.plugin.IPyNbFile.setup is kernels.setup_alone
    assert set(kernels.RUN_IN_PLACE) <= {p.name for p in NOTEBOOKS}


PROBE = r"""
import importlib.util, json, os, sys
from pathlib import Path
import rapp
print(json.dumps({
    "files": sorted(os.listdir(".")),
    "rapp": str(Path(rapp.__file__).resolve().parent),
    "importable": {name: importlib.util.find_spec(name) is not None
                   for name in ("benchmarks", "tests", "scripts", "conftest")},
    "parent_has_benchmarks": (Path("..") / "benchmarks").exists(),
}))
"""


@pytest.mark.slow
def test_alone_gives_an_empty_folder_and_only_rapp(tmp_path):
    from nbclient import NotebookClient

    notebook = tmp_path / "probe.ipynb"
    nbformat.write(nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(PROBE)]), notebook)
    with kernels.alone(notebook) as (folder, env):
        nb = nbformat.read(folder / notebook.name, as_version=4)
        NotebookClient(nb, timeout=60, kernel_name="python3",
                       resources={"metadata": {"path": str(folder)}}).execute(cwd=str(folder), env=env)
    seen = json.loads(nb.cells[0].outputs[0]["text"])
    assert seen["files"] == ["probe.ipynb"]
    assert seen["rapp"] == str(kernels.RAPP_PACKAGE)
    assert not any(seen["importable"].values()), seen["importable"]
    assert not seen["parent_has_benchmarks"]
