"""Traceability: every SRS item (seed 000) has a chapter section that teaches it and tests that hold it.

The map is package data (rapp/traceability.json, read by rapp.traceability) and is shown in
notebooks/09_requirements.ipynb. These tests fail when an item of the SRS list is missing from the
map or an unknown one is in it, when a section label is not defined in a chapter of the toc (the
SRS page's own `srs-...` labels do not count), when a test node id names a function that is not in
its file (found by parsing the file, so a renamed or deleted test breaks the map), when the
chapter's static table with {ref} links disagrees with the JSON, and when the record of what the
repository defines (rapp/traceability_found.json, which chapter 9 checks the map against outside
the repository) is not what the chapters and test files define today.

The last part holds the boundaries of the items the package leaves out by design (LC4, LC6, LC7,
LC8) and two items no other test file states (A4 rigid links, NFR4 docstrings).
"""

from __future__ import annotations

import ast
import dataclasses
import inspect
import json
import re
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

import rapp
from rapp import traceability
from rapp.planner import STAGES
from rapp.traceability import NODE_ID, OUT_OF_SCOPE, SRS_ITEMS, load_map, static_table

ROOT = Path(__file__).resolve().parent.parent
CHAPTER = ROOT / "notebooks" / "09_requirements.ipynb"
LABEL_LINE = re.compile(r"^\(([A-Za-z0-9_.:-]+)\)=\s*$", re.MULTILINE)


# ---- what the repository defines: the chapters' labels and the test files' tests ---------------

def toc_files(node) -> list[str]:
    found = []
    if isinstance(node, dict):
        found += [node[k] for k in ("root", "file") if k in node]
        for value in node.values():
            if isinstance(value, (list, dict)):
                found += toc_files(value)
    elif isinstance(node, list):
        for item in node:
            found += toc_files(item)
    return found


def chapter_files(root: Path = ROOT) -> list[Path]:
    """The chapters of the book: the notebooks that _toc.yml lists."""
    toc = yaml.safe_load((root / "_toc.yml").read_text(encoding="utf-8"))
    return [root / f"{entry}.ipynb" for entry in toc_files(toc)
            if entry.startswith("notebooks/") and (root / f"{entry}.ipynb").is_file()]


def labels_in(path: Path) -> list[str]:
    """MyST target labels `(name)=` defined in a notebook's markdown cells or a .md page."""
    # Every item's check reads every chapter: parse each file once per version of it (a file
    # that changes, even within a session, has a new modification time or size and is re-read).
    stat = path.stat()
    return list(_labels_in(path, stat.st_mtime_ns, stat.st_size))


@lru_cache(maxsize=None)
def _labels_in(path: Path, mtime_ns: int, size: int) -> tuple[str, ...]:
    if path.suffix == ".ipynb":
        # Plain JSON: nbformat.read validates every output of the chapter, seconds for none used.
        cells = json.loads(path.read_text(encoding="utf-8"))["cells"]
        text = "\n".join("".join(c["source"]) for c in cells if c["cell_type"] == "markdown")
    else:
        text = path.read_text(encoding="utf-8")
    return tuple(LABEL_LINE.findall(text))


def chapter_labels(root: Path = ROOT) -> dict[str, list[str]]:
    """label -> the chapters (file names) that define it."""
    where: dict[str, list[str]] = {}
    for path in chapter_files(root):
        for label in labels_in(path):
            where.setdefault(label, []).append(path.name)
    return where


@lru_cache(maxsize=None)
def _test_names(path: Path) -> frozenset[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.name.startswith("test"):
            names.add(node.name)
        elif isinstance(node, ast.ClassDef) and node.name.startswith("Test"):
            names |= {f"{node.name}::{f.name}" for f in node.body
                      if isinstance(f, (ast.FunctionDef, ast.AsyncFunctionDef))
                      and f.name.startswith("test")}
    return frozenset(names)


def node_exists(node_id: str, root: Path = ROOT) -> bool:
    """Whether `tests/test_x.py::test_y` (or `::TestX::test_y`) is a test defined in that file."""
    m = NODE_ID.match(node_id)
    if not m:
        return False
    path = root / m.group(1)
    return path.is_file() and m.group(2) in _test_names(path)


def defined_in(mapping: dict, root: Path = ROOT) -> dict:
    """What the repository defines of the map: the record rapp.traceability.found() holds."""
    labels = chapter_labels(root)
    return {"labels": sorted({i.get("section", "") for i in mapping["items"]} & set(labels)),
            "tests": sorted({t for i in mapping["items"] for t in i.get("tests", [])
                             if node_exists(t, root)})}


def problems(mapping: dict, root: Path = ROOT) -> list[str]:
    """The package's checker, run on what the repository defines today."""
    return traceability.problems(mapping, defined_in(mapping, root))


# ---- the map is complete ------------------------------------------------------------------------

def test_map_lists_exactly_the_srs_items_in_order():
    ids = [item["id"] for item in load_map()["items"]]
    assert ids == SRS_ITEMS


def test_srs_labels_are_the_srs_page_headings():
    srs = set(labels_in(ROOT / "book" / "srs.md"))
    for item in load_map()["items"]:
        assert item["srs_label"] in srs, item["id"]


@pytest.mark.parametrize("item", load_map()["items"], ids=lambda it: it["id"])
def test_every_item_has_a_section_and_tests(item):
    mine = problems({"items": [item]})
    mine = [p for p in mine if "missing from the map" not in p]
    assert not mine, "\n".join(mine)


def test_out_of_scope_items_say_why():
    for item in load_map()["items"]:
        assert (item["scope"] == "out") == (item["id"] in OUT_OF_SCOPE), item["id"]
        assert (item["scope"] == "out") == bool(item.get("why")), item["id"]


def test_im1_matrix_uses_the_pipeline_stages():
    mapping = load_map()
    stages = mapping["im1_stages"]
    # The stages timed by rapp.plan, plus reading/echoing the scenario before and the output after.
    planner = set(STAGES)
    assert set(stages) - {"scenario", "echo", "output"} <= planner
    used = {s for item in mapping["items"] for s in item.get("im1", [])}
    assert used == set(stages)
    for i in ("R1", "R2", "R3", "R4", "R5"):
        assert next(it for it in mapping["items"] if it["id"] == i).get("im1"), i


def test_static_table_in_the_chapter_agrees_with_the_map():
    table = static_table(CHAPTER)
    expected = {it["id"]: (it["section"], it["tests"]) for it in load_map()["items"]}
    assert table == expected


def test_the_recorded_findings_are_what_the_repository_defines():
    """Chapter 9 checks the map against rapp/traceability_found.json; it must not go stale."""
    assert traceability.found() == defined_in(load_map()), (
        "rapp/traceability_found.json is stale: run python scripts/record_traceability.py")


# ---- the checker itself finds what it must ------------------------------------------------------

def test_checker_finds_broken_entries():
    assert node_exists("tests/test_traceability.py::test_checker_finds_broken_entries")
    assert not node_exists("tests/test_traceability.py::test_no_such_test")
    assert not node_exists("tests/test_nowhere.py::test_x")
    assert not node_exists("tests/test_arm.py::fk_srs")  # a helper, not a test
    assert not node_exists("test_arm.py::test_fk_batch_matches_srs_sum")  # path without tests/
    good = load_map()["items"][0]
    broken = [
        dict(good, id="A0"),
        dict(good, id="A1", section="srs-a1"),  # the SRS page's label is not a teaching section
        dict(good, id="A2", section="ch99-nowhere"),
        dict(good, id="A3", tests=[]),
        dict(good, id="A4", tests=["tests/test_arm.py::test_renamed_away"]),
    ]
    found = problems({"items": broken})
    for expected in ("A0: not an SRS item", "A1: section label 'srs-a1'",
                     "A2: section label 'ch99-nowhere'", "A3: no test",
                     "A4: no test tests/test_arm.py::test_renamed_away", "R1: missing from the map"):
        assert any(p.startswith(expected) for p in found), expected


def test_checker_reads_test_classes(tmp_path):
    (tmp_path / "tests").mkdir()
    (tmp_path / "tests" / "test_k.py").write_text(
        "class TestK:\n    def test_y(self):\n        pass\n    def helper(self):\n        pass\n")
    assert node_exists("tests/test_k.py::TestK::test_y", root=tmp_path)
    assert not node_exists("tests/test_k.py::TestK::helper", root=tmp_path)
    assert not node_exists("tests/test_k.py::test_y", root=tmp_path)


# ---- boundaries of what the package leaves out, and items no other file states ------------------

SCENARIO = {"arm": {"link_lengths": [1.0, 1.0]}, "obstacles": [], "start": [0.0, 0.0],
            "goal": {"joints": [1.0, 0.5]}}


def test_boundary_planar_only():
    """LC4: positions are 2-vectors; a third coordinate is an error, never silently dropped."""
    arm = rapp.Arm([1.0, 0.5, 0.25])
    assert arm.joint_positions(np.zeros((4, 3))).shape == (4, 4, 2)
    with pytest.raises(ValueError):
        rapp.Circle((0.0, 0.0, 1.0), 0.5)
    with pytest.raises(ValueError):
        rapp.Polygon([(0, 0, 0), (1, 0, 0), (0, 1, 0)])
    bad = dict(SCENARIO, obstacles=[{"type": "circle", "center": [1, 1, 1], "radius": 0.2}])
    with pytest.raises(rapp.InvalidValue):
        rapp.load_scenario(bad)


def test_boundary_link_lengths_are_fixed():
    """A2, LC6: an Arm's lengths cannot change after construction; non-positive lengths are errors."""
    arm = rapp.Arm([1.0, 0.5])
    with pytest.raises(dataclasses.FrozenInstanceError):
        arm.link_lengths = (2.0, 2.0)
    lengths = arm.lengths
    with pytest.raises(ValueError):
        lengths[:] = 5.0  # read-only: no caller can change the arm through it
    assert arm.lengths.tolist() == [1.0, 0.5]
    assert np.allclose(arm.end_effector([0.0, 0.0]), [1.5, 0.0])
    for bad in ([1.0, 0.0], [1.0, -0.5]):
        with pytest.raises(ValueError):
            rapp.Arm(bad)


def test_boundary_kinematic_only():
    """A1, LC7: no masses, torques or inertia enter; a plan is q, q', q'' in time, nothing more."""
    for key in ("masses", "inertia", "torque_limits"):
        arm = dict(SCENARIO["arm"], **{key: [1.0, 1.0]})
        with pytest.raises(rapp.InvalidFormat) as e:
            rapp.load_scenario(dict(SCENARIO, arm=arm))
        assert e.value.field == f"arm.{key}"
    fields = {f.name for f in dataclasses.fields(rapp.Plan)}
    assert {"t", "q", "qd", "qdd", "xy"} <= fields
    assert not {f for f in fields if re.search(r"torque|force|mass|inertia|tau", f)}


def test_boundary_static_obstacles():
    """LC8: obstacles are frozen values; a scenario cannot give one a velocity."""
    circle, square = rapp.Circle((1.0, 1.0), 0.3), rapp.Polygon.rectangle((0, 0), 1, 1)
    for obstacle, name in ((circle, "center"), (square, "vertices")):
        with pytest.raises(dataclasses.FrozenInstanceError):
            setattr(obstacle, name, None)
    moving = dict(SCENARIO, obstacles=[{"type": "circle", "center": [1.5, 1.5], "radius": 0.2,
                                        "velocity": [0.1, 0.0]}])
    with pytest.raises(rapp.InvalidFormat) as e:
        rapp.load_scenario(moving)
    assert e.value.field == "obstacles[0].velocity"


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(0.05, 3.0), min_size=1, max_size=5), st.integers(0, 2**32 - 1))
def test_links_are_rigid_segments(lengths, seed):
    """A4: in every configuration, consecutive joints are exactly one link length apart."""
    arm = rapp.Arm(lengths)
    q = np.random.default_rng(seed).uniform(-10, 10, (50, arm.n))
    gaps = np.linalg.norm(np.diff(arm.joint_positions(q), axis=-2), axis=-1)
    np.testing.assert_allclose(gaps, np.broadcast_to(lengths, gaps.shape), rtol=1e-12, atol=1e-12)


def public_names_without_docs() -> list[str]:
    """Public functions of rapp without an Examples section, public classes without a docstring."""
    missing = []
    for name in sorted(n for n in dir(rapp) if not n.startswith("_")):
        obj = getattr(rapp, name)
        doc = inspect.getdoc(obj) or ""
        if inspect.isfunction(obj) and not re.search(r"^Examples\n-+$", doc, re.MULTILINE):
            missing.append(name)
        elif inspect.isclass(obj) and not doc.strip():
            missing.append(name)
    return missing


def test_every_public_function_has_a_docstring_with_examples():
    """NFR4: documented interfaces; every public function shows a runnable example (a doctest)."""
    assert public_names_without_docs() == []
    modules = sorted((ROOT / "rapp").glob("*.py"))
    assert modules
    for path in modules:
        assert ast.get_docstring(ast.parse(path.read_text(encoding="utf-8"))), path.name
