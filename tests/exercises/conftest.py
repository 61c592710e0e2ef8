"""What the exercise tests share: the exercises as the notebooks print them.

``book_exercises`` maps an id such as "5.2" to the exercise's text, its solution's text, its
kind and difficulty as printed, and the source of the reader's check cell under it.
``solution(id)`` runs the Python blocks of that solution, as a reader would paste them, and
returns their namespace: the model answer a test passes to ``rapp.exercises.check``.
"""

from __future__ import annotations

import functools
import json
import re
from pathlib import Path

import numpy as np
import pytest

import rapp

NOTEBOOKS = Path(__file__).resolve().parents[2] / "notebooks"
_BLOCK = re.compile(r"^:::\{(exercise|solution)\}\s*(.*?)\n(.*?)^:::\s*$", re.S | re.M)
_KIND = re.compile(r"^\*Kind:\* (\w+) · \*difficulty:\* (\d) of 3\s*$", re.M)
_CODE = re.compile(r"^```python\n(.*?)^```", re.S | re.M)


@functools.cache
def parse_book() -> dict[str, dict]:
    found: dict[str, dict] = {}
    for path in sorted(NOTEBOOKS.glob("[0-9][0-9]_*.ipynb")):
        chapter = int(path.name[:2])
        cells = json.loads(path.read_text())["cells"]
        for i, cell in enumerate(cells):
            text = "".join(cell["source"])
            if cell["cell_type"] != "markdown":
                continue
            for kind, arg, body in _BLOCK.findall(text):
                label = re.search(r"^:label: (\S+)", body, re.M)
                if kind == "exercise":
                    ex_id = label.group(1).removeprefix("ex-").replace("-", ".")
                    m = _KIND.search(body)
                    nxt = cells[i + 1] if i + 1 < len(cells) else None
                    found[ex_id] = {
                        "chapter": chapter, "notebook": path.name, "title": arg.strip(),
                        "text": body, "kind": m and m.group(1), "difficulty": m and int(m.group(2)),
                        "solution": None, "label": label.group(1),
                        "check_cell": "".join(nxt["source"]) if nxt and nxt["cell_type"] == "code" else None,
                    }
                else:
                    target = arg.strip().removeprefix("ex-").replace("-", ".")
                    if target in found:
                        found[target]["solution"] = body
    return found


@pytest.fixture(scope="session")
def book_exercises() -> dict[str, dict]:
    return parse_book()


def run_solution(ex_id: str) -> dict:
    """Execute the solution's Python blocks with numpy and rapp imported; return the namespace."""
    body = parse_book()[ex_id]["solution"]
    namespace = {"np": np, "rapp": rapp}
    for block in _CODE.findall(body or ""):
        exec(compile(block, f"<solution {ex_id}>", "exec"), namespace)
    return namespace


@pytest.fixture(scope="session")
def solution():
    return run_solution
