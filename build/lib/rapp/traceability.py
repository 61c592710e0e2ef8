"""The book's traceability map: each SRS item, the section that teaches it, the tests that hold it.

Two files of package data, so that the requirements chapter runs wherever ``rapp`` is installed:

- ``traceability.json``, the map: one entry per SRS item (seed 000) with its ``id``, ``title``,
  ``srs_label``, ``scope``, the teaching ``section`` (a chapter's ``(label)=``) and the ``tests``
  (pytest node ids);
- ``traceability_found.json``, what the repository defined of it when it was last checked: the
  section labels of the map that a chapter of the table of contents defines, and the test node
  ids of the map that name a test function of their file. The repository's
  ``tests/test_traceability.py`` reads the chapters and parses the test files, and holds this
  record equal to them (``python scripts/record_traceability.py`` rewrites it).

:func:`problems` is the checker of the book's algorithm *Checking a traceability map*: it needs
the map and that record, nothing else.

Examples
--------
>>> mapping = load_map()
>>> [item["id"] for item in mapping["items"]] == SRS_ITEMS
True
>>> problems(mapping, found())
[]
>>> one = {"items": [dict(mapping["items"][0], tests=[])]}  # A1 alone, with no test
>>> [line for line in problems(one, found()) if "missing" not in line]
['A1: no test']
"""

from __future__ import annotations

import json
import re
from importlib import resources
from pathlib import Path

__all__ = ["SRS_ITEMS", "srs_label", "OUT_OF_SCOPE", "NODE_ID", "load_map", "found", "problems",
           "static_table"]

#: The items of seed 000, in the SRS's order (book/srs.md restates them).
SRS_ITEMS = (
    [f"A{i}" for i in range(1, 8)]
    + ["TM:FWDKinematics", "TM:SegmentCircleCollision", "TM:AStarJointSpace", "GD1", "DD1", "IM1"]
    + [f"R{i}" for i in range(1, 6)]
    + [f"NFR{i}" for i in range(1, 6)]
    + [f"LC{i}" for i in range(1, 9)]
)
#: The SRS page's labels of the theory-model items, whose ids are too long for a label.
_TM_LABELS = {"TM:FWDKinematics": "srs-tm-fk", "TM:SegmentCircleCollision": "srs-tm-collision",
              "TM:AStarJointSpace": "srs-tm-astar"}


def srs_label(item: str) -> str:
    """The label of an SRS item's heading on book/srs.md.

    Examples
    --------
    >>> [srs_label(item) for item in ("A1", "TM:AStarJointSpace", "NFR3")]
    ['srs-a1', 'srs-tm-astar', 'srs-nfr3']
    """
    if item not in SRS_ITEMS:
        raise ValueError(f"item must be one of the SRS items, got {item!r}")
    return _TM_LABELS.get(item, "srs-" + item.lower())


#: The items the package leaves out by design; boundary tests hold them.
OUT_OF_SCOPE = frozenset({"LC4", "LC6", "LC7", "LC8", "NFR2"})
#: A test node id of the map: ``tests/test_x.py::test_y`` or ``tests/test_x.py::TestX::test_y``.
NODE_ID = re.compile(r"^(tests/test_\w+\.py)::((?:Test\w+::)?test_\w+)$")
_REF = re.compile(r"\{ref\}`(?:[^`<]*<)?([^`<>]+)>?`")


def _data(name: str) -> dict:
    return json.loads(resources.files(__package__).joinpath(name).read_text("utf-8"))


def load_map() -> dict:
    """The traceability map: ``{"im1_stages": [...], "items": [...]}`` (see the module notes).

    Examples
    --------
    >>> len(load_map()["items"])
    31
    """
    return _data("traceability.json")


def found() -> dict:
    """What the repository defined of the map when it was last checked.

    Returns
    -------
    dict
        ``"labels"``: the map's section labels that a chapter defines; ``"tests"``: the map's
        test node ids that name a test of their file. Both sorted.

    Examples
    --------
    >>> record = found()
    >>> "tests/test_obstacles.py::test_circle" in record["tests"], "ch02-fk-derivation" in record["labels"]
    (True, True)
    """
    return _data("traceability_found.json")


def problems(mapping: dict, defined: dict) -> list[str]:
    """Everything wrong with a traceability map, one line each; empty when it is complete.

    Parameters
    ----------
    mapping : dict
        A map as :func:`load_map` returns it (only ``"items"`` is read).
    defined : dict
        The section labels the chapters define and the test node ids that exist, as
        :func:`found` returns them (``"labels"``, ``"tests"``).

    Examples
    --------
    >>> item = load_map()["items"][0]
    >>> report = problems({"items": [dict(item, id="A0", section="srs-a1")]}, found())
    >>> [line for line in report if line.startswith("A0")]
    ['A0: not an SRS item', "A0: section label 'srs-a1' is not defined in a toc'd chapter"]
    """
    labels, tests = set(defined["labels"]), set(defined["tests"])
    out = []
    ids = [item["id"] for item in mapping["items"]]
    out += [f"{i}: listed twice" for i in sorted({i for i in ids if ids.count(i) > 1})]
    out += [f"{i}: not an SRS item" for i in ids if i not in SRS_ITEMS]
    out += [f"{i}: missing from the map" for i in SRS_ITEMS if i not in ids]
    for item in mapping["items"]:
        section = item.get("section", "")
        if section.startswith("srs-") or section not in labels:
            out.append(f"{item['id']}: section label {section!r} is not defined in a toc'd chapter")
        if not item.get("tests"):
            out.append(f"{item['id']}: no test")
        out += [f"{item['id']}: no test {t}" for t in item.get("tests", [])
                if not NODE_ID.match(t) or t not in tests]
    return out


def static_table(path) -> dict[str, tuple[str, list[str]]]:
    """The map as a chapter's markdown table shows it: item id -> (section label, test node ids).

    A row counts when its second column holds a ``{ref}`` to the section; the tests are the
    ```tests/...``` names of its last column.

    Examples
    --------
    >>> import json, tempfile, os
    >>> row = "| {ref}`A1 <srs-a1>` | {ref}`ch09-scope` | `tests/test_x.py::test_y` |"
    >>> nb = {"cells": [{"cell_type": "markdown", "source": [row]}]}
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     path = os.path.join(tmp, "c.ipynb")
    ...     with open(path, "w") as fh:
    ...         json.dump(nb, fh)
    ...     static_table(path)
    {'A1': ('ch09-scope', ['tests/test_x.py::test_y'])}
    """
    cells = json.loads(Path(path).read_text(encoding="utf-8"))["cells"]
    rows = {}
    for cell in cells:
        if cell["cell_type"] != "markdown":
            continue
        source = cell["source"] if isinstance(cell["source"], str) else "".join(cell["source"])
        for line in source.splitlines():
            cols = [c.strip() for c in line.strip().strip("|").split("|")]
            if len(cols) < 3 or not _REF.search(cols[1]):
                continue
            item = re.sub(r"\{ref\}`([^`<]*)<[^`]*>`", r"\1", cols[0]).strip(" *`")
            rows[item] = (_REF.search(cols[1]).group(1), re.findall(r"`(tests/[^`]+)`", cols[-1]))
    return rows
