"""book/scenario_format.md stays true to rapp/scenario.py.

Every JSON block on the page is a captioned ``{code-block} json``. A caption starting "Valid" must
load (through a real file, as an instructor's would) and plan; "Valid with warnings at F1, F2"
must also warn once per listed field; "<ErrorClass> at FIELD" must raise exactly that ScenarioError
subclass with that ``.field``. The key tables (``{table}`` with ``:name: keys-...``) must list
exactly the keys the loader accepts. Those keys are read from the module: its key tuples
(``_TOP_KEYS``, ``_PLANNER_KEYS``, ``_SAMPLING_KEYS``) and, for the objects it validates with inline
tuples, the "known keys" its own unknown-key error reports. The planner tables are checked against
the planner table, ``rapp.planners.PLANNERS`` (:func:`planner_doc_problems`), which the loader and
``rapp.plan`` read too. Nothing here is a second copy.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

import rapp.errors
import rapp.planners
from rapp import cli
from rapp import scenario as sc
from rapp import plan

ROOT = Path(__file__).resolve().parent.parent
PAGE = (ROOT / "book" / "scenario_format.md").read_text(encoding="utf-8")

BLOCK = re.compile(r"^```\{code-block\} (\w+)\n((?::[\w-]+:[^\n]*\n)*)\n(.*?)^```$", re.M | re.S)
TABLE = re.compile(r"^:::\{table\} (.*?)\n:name: (\S+)\n\n(.*?)^:::$", re.M | re.S)
ERROR_CAPTION = re.compile(r"^(\w+) at (\S+)$")
WARN_CAPTION = re.compile(r"^Valid with warnings at (.+)$")
#: Plan a valid example only when the search is small enough for a unit test.
SMALL_GRID = 200_000


def code_blocks():
    out = []
    for m in BLOCK.finditer(PAGE):
        opts = dict(re.findall(r"^:([\w-]+): ?(.*)$", m.group(2), re.M))
        out.append((m.group(1), opts.get("caption", ""), m.group(3)))
    return out


JSON_BLOCKS = [(cap, body) for lang, cap, body in code_blocks() if lang == "json"]


def tables():
    found = {}
    for m in TABLE.finditer(PAGE):
        rows = [line for line in m.group(3).splitlines() if line.startswith("|")]
        cells = [[c.strip() for c in row.strip("|").split("|")] for row in rows[2:]]
        assert m.group(2) not in found, f"table name {m.group(2)} used twice"
        found[m.group(2)] = cells
    return found


TABLES = tables()


def first_column_keys(name):
    keys = []
    for row in TABLES[name]:
        m = re.fullmatch(r"`([^`]+)`", row[0])
        assert m, f"table {name}: first cell {row[0]!r} is not a `key`"
        keys.append(m.group(1))
    assert len(keys) == len(set(keys)), f"table {name} lists a key twice"
    return set(keys)


# --------------------------------------------------------------------------- the examples


def test_tables_use_colon_fences():
    # A backtick fence may not hold a backtick in its info string, so a ```{table} titled
    # "Keys of `arm`" would silently render as text and lose its label.
    assert "```{table}" not in PAGE
    assert len(TABLES) >= 13


def test_every_json_block_is_a_checked_example():
    assert "```json" not in PAGE, "use a captioned {code-block} json so the test checks it"
    assert len(JSON_BLOCKS) >= 10
    for caption, _ in JSON_BLOCKS:
        assert caption.startswith("Valid") or ERROR_CAPTION.match(caption), (
            f"caption {caption!r} says neither 'Valid ...' nor '<ErrorClass> at <field>'")
    assert sum(c.startswith("Valid") for c, _ in JSON_BLOCKS) >= 3
    assert sum(bool(ERROR_CAPTION.match(c)) for c, _ in JSON_BLOCKS) >= 8


def _load_as_file(body, tmp_path):
    path = tmp_path / "scenario.json"
    path.write_text(body, encoding="utf-8")
    return sc.load_scenario(path)


VALID = [(c, b) for c, b in JSON_BLOCKS if c.startswith("Valid")]
BAD = [(c, b) for c, b in JSON_BLOCKS if ERROR_CAPTION.match(c)]


@pytest.mark.parametrize("caption, body", VALID, ids=[c for c, _ in VALID])
def test_valid_example_loads_and_plans(caption, body, tmp_path):
    s = _load_as_file(body, tmp_path)
    m = WARN_CAPTION.match(caption)
    if m:
        fields = [f.strip() for f in m.group(1).split(",")]
        assert len(s.warnings) == len(fields), s.warnings
        for f in fields:
            assert sum(w.startswith(f + " ") for w in s.warnings) == 1, (f, s.warnings)
    else:
        assert s.warnings == (), f"a plain 'Valid' example must not warn: {s.warnings}"
    # The page promises the file is the input: its canonical form loads back to the same scenario.
    assert sc.load_scenario(s.to_dict()) == s
    if s.planner.algorithm != "astar" or math.prod(s.planner.cells) <= SMALL_GRID:
        p = plan(s)
        assert p.report.ok
        # At least the samples asked: short pieces of the motion (and, for a line goal, every
        # breakpoint) add sample times.
        assert p.q.shape[1] == s.arm.n and len(p.q) >= s.trajectory.samples


@pytest.mark.parametrize("caption, body", BAD, ids=[c for c, _ in BAD])
def test_bad_example_raises_the_documented_error(caption, body, tmp_path):
    cls_name, field = ERROR_CAPTION.match(caption).groups()
    cls = getattr(rapp.errors, cls_name, None)
    assert isinstance(cls, type) and issubclass(cls, rapp.errors.ScenarioError), cls_name
    with pytest.raises(rapp.errors.ScenarioError) as info:
        _load_as_file(body, tmp_path)
    assert type(info.value) is cls, f"raised {type(info.value).__name__}: {info.value}"
    assert info.value.field == field, str(info.value)
    # The same text through the command line: one line naming the field, exit code 2.
    path = tmp_path / "scenario.json"
    err = io.StringIO()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
        code = cli.main(["check", str(path)])
    assert code == cli.EXIT_BAD_INPUT == 2
    assert err.getvalue().startswith(f"rapp: error: {field}: ")


def test_examples_cover_every_key_and_obstacle_type():
    data = [json.loads(b) for c, b in VALID]
    top = set().union(*data)
    assert top == set(sc._TOP_KEYS)
    planner = set().union(*(d.get("planner", {}) for d in data))
    assert planner == set(sc._PLANNER_KEYS)
    kinds = {ob["type"] for d in data for ob in d.get("obstacles", [])}
    assert kinds == set(_obstacle_types())


# --------------------------------------------------------------------------- the key tables

BASE = {"arm": {"link_lengths": [1.0, 1.0]}, "start": [0.0, 0.0], "goal": {"joints": [1.0, 0.0]}}
PROBE = "zz_not_a_key"


def _known_keys(data, field):
    """The keys the loader accepts at ``field``, as its unknown-key error lists them."""
    with pytest.raises(rapp.errors.InvalidFormat) as info:
        sc.load_scenario(data, check=False)
    assert info.value.field == field, str(info.value)
    m = re.search(r"known keys: ([^)]*)\)", info.value.message)
    assert m, info.value.message
    return {k.strip() for k in m.group(1).split(",")}


def _object_sections():
    """Top-level keys whose value is an object, with the keys the loader accepts in each."""
    out = {}
    for key in sc._TOP_KEYS:
        data = dict(BASE, **{key: {PROBE: 0}})
        try:
            sc.load_scenario(data, check=False)
        except rapp.errors.InvalidFormat as e:
            if e.field == f"{key}.{PROBE}":
                out[key] = _known_keys(data, e.field)
    return out


def _obstacle_types():
    with pytest.raises(rapp.errors.InvalidValue) as info:
        sc.load_scenario(dict(BASE, obstacles=[{"type": PROBE}]), check=False)
    assert info.value.field == "obstacles[0].type"
    return re.findall(r"'(\w+)'", info.value.message.split("got")[0])


def test_probes_agree_with_the_module_constants():
    sections = _object_sections()
    assert _known_keys(dict(BASE, **{PROBE: 0}), PROBE) == set(sc._TOP_KEYS)
    assert sections["planner"] == set(sc._PLANNER_KEYS)
    assert set(sc._SAMPLING_KEYS) < set(sc._PLANNER_KEYS)
    assert {"arm", "goal", "units", "planner", "trajectory"} <= set(sections)


def test_key_tables_list_exactly_the_accepted_keys():
    expected = {"top": set(sc._TOP_KEYS)}
    for section, keys in _object_sections().items():
        expected[section] = keys
    for kind in _obstacle_types():
        data = dict(BASE, obstacles=[{"type": kind, PROBE: 0}])
        expected[f"obstacles-{kind}"] = _known_keys(data, f"obstacles[0].{PROBE}")

    documented = {}
    for name in TABLES:
        if name.startswith("keys-"):
            section = name[len("keys-"):]
            if section.startswith("planner-"):  # one table per algorithm, one planner object
                section = "planner"
            documented.setdefault(section, set()).update(first_column_keys(name))
    assert documented == expected


def planner_doc_problems(tables=None) -> list:
    """What the page's planner tables say that the planner table does not (empty: they agree).

    ``keys-planner-astar`` holds the settings of the grid planners, ``keys-planner-rrt`` every
    other setting, each with its default; ``planner-table`` has one row per planner with the
    keys it reads, what its ``max_iterations`` counts and its default, and its capability flags
    (``complete``, ``optimizing``: :class:`rapp.planners.Planner`).
    """
    tables = TABLES if tables is None else tables
    table = rapp.planners.PLANNERS
    grid_keys = {k for p in table.values() if p.grid for k in p.keys}
    every = rapp.planners.all_settings()
    problems = []

    def rows(name):
        return {row[0].strip("`"): row for row in tables.get(name, [])}

    for name, keys in (("keys-planner-astar", grid_keys), ("keys-planner-rrt", set(every) - grid_keys)):
        documented = set(rows(name)) - {"algorithm"}
        if documented != keys:
            problems.append(f"{name} lists {sorted(documented)}, the planner table {sorted(keys)}")
        for key, row in rows(name).items():
            m = re.fullmatch(r"`([^`]+)`", row[3])
            if key in every and m and json.loads(m.group(1)) != every[key].default:
                problems.append(f"{name}: default of {key} is {m.group(1)}, the table's "
                                f"{every[key].default!r}")
    listed = {row[0].strip('`"'): row for row in tables.get("planner-table", [])}
    if set(listed) != set(table):
        problems.append(f"planner-table has {sorted(listed)}, the planner table {sorted(table)}")
    for name, p in table.items():
        if name not in listed:
            continue
        row = listed[name]
        if re.findall(r"`(\w+)`", row[1]) != list(p.keys):
            problems.append(f"{name} reads {p.keys}, the page says {row[1]}")
        its = str(p.default("max_iterations")) if "max_iterations" in p.keys else ""
        if row[3] != its:
            problems.append(f"{name}: max_iterations default {its or 'none'}, the page says {row[3]}")
        counts = (p.iteration + (", all run" if p.anytime else "")) if p.iteration else ""
        if not row[2].startswith(counts) or bool(row[2]) != bool(counts):
            problems.append(f"{name}: max_iterations counts {counts or 'nothing'}, the page says {row[2]}")
        for column, flag in ((4, p.complete), (5, p.optimizing)):
            said = row[column].split(":")[0].strip()
            if said != (flag or "no"):
                problems.append(f"{name}: {tables_header(column)} is {flag or 'no'}, the page says {said}")
    return problems


def tables_header(column: int) -> str:
    return ("algorithm", "reads", "counts", "default", "complete", "optimizing")[column]


def test_planner_tables_are_the_planner_table():
    assert planner_doc_problems() == []
    rrt, astar = first_column_keys("keys-planner-rrt"), first_column_keys("keys-planner-astar")
    assert set(sc._SAMPLING_KEYS) <= rrt, "every setting A* warns about belongs in the sampling table"
    assert not set(sc._SAMPLING_KEYS) & astar
    assert not rrt & astar


def _straight(arm, start, goal, obstacles=(), *, tries=1, seed=0, raise_on_failure=True):
    """A planner of the contract: the straight segment to the first goal it can certify."""
    from rapp.collision import segment_collision_free
    from rapp.paths import PlannerResult, path_length
    start = np.asarray(start, float)
    for g in np.atleast_2d(goal)[:tries]:
        b = start + arm.joint_delta(start, g)
        if segment_collision_free(arm, start, b, list(obstacles)):
            path = np.array([start, b])
            return PlannerResult(path, True, path_length(path), {"tries": int(tries)})
    if raise_on_failure:
        raise rapp.errors.NoPathFound("no straight segment is free")
    return PlannerResult(np.empty((0, arm.n)), False, math.inf, {}, "iteration cap")


def test_a_planner_registered_in_the_table_is_parsed_planned_and_checked_on_the_page(monkeypatch):
    tries = rapp.planners.Setting("tries", "integer", None, 1, 10, label="tries")  # default: _straight's
    entry = rapp.planners.Planner("straight", _straight, (tries, rapp.planners.SEED),
                                  "the straight segment, if it is free")
    monkeypatch.setattr(rapp.planners, "PLANNERS",
                        type(rapp.planners.PLANNERS)({**rapp.planners.PLANNERS, "straight": entry}))
    # Parsed: the new name and its own setting are accepted, checked and echoed ...
    s = sc.load_scenario(dict(BASE, planner={"algorithm": "straight", "tries": 3}))
    assert s.planner.algorithm == "straight" and s.planner.tries == 3 and s.warnings == ()
    assert "  tries" in sc.echo(s) and sc.load_scenario(s.to_dict()) == s
    with pytest.raises(rapp.errors.InvalidValue) as info:
        sc.load_scenario(dict(BASE, planner={"algorithm": "straight", "tries": 0}))
    assert info.value.field == "planner.tries"
    other = sc.load_scenario(dict(BASE, planner={"algorithm": "rrt", "tries": 3}))
    assert other.warnings == ("planner.tries is not a setting of rrt and is ignored",)
    # ... planned by rapp.plan with the settings it reads ...
    p = plan(s)
    assert p.report.ok and len(p.waypoints) == 2
    assert np.allclose(s.arm.wrap(p.waypoints[-1]), s.arm.wrap(np.array(s.goal_q)))
    # ... and the page check names what the page does not document yet.
    problems = planner_doc_problems()
    assert any("straight" in m for m in problems) and any("tries" in m for m in problems)


def _row(table, key):
    for row in TABLES[table]:
        if row[0] == f"`{key}`":
            return row
    raise KeyError(key)


@pytest.mark.parametrize("table, settings", [
    ("keys-planner-astar", sc.PlannerSettings()),
    ("keys-planner-rrt", sc.PlannerSettings()),
    ("keys-trajectory", sc.TrajectorySettings()),
])
def test_documented_defaults_are_the_loader_defaults(table, settings):
    loaded = sc.load_scenario(BASE)
    section = loaded.trajectory if table == "keys-trajectory" else loaded.planner
    checked = 0
    for row in TABLES[table]:
        key = row[0].strip("`")
        m = re.fullmatch(r"`([^`]+)`", row[3])
        if key == "algorithm" or not m or not hasattr(settings, key):
            continue
        assert json.loads(m.group(1)) == getattr(section, key) == getattr(settings, key), key
        checked += 1
    assert checked >= 2


def test_choices_and_limits_on_the_page_are_the_modules():
    for choice in sc.ALGORITHMS + sc.PROFILES:
        assert f'`"{choice}"`' in PAGE, choice
    for n in (2, 3, 4):
        assert f"{sc.max_cells(n):,}" in PAGE, n
    for name in ("MIN_LENGTH", "MAX_LENGTH", "MAX_COORDINATE", "MAX_ANGLE", "MIN_DURATION",
                 "MAX_DURATION", "MAX_LINKS", "MAX_HEURISTIC_WEIGHT", "MAX_GOAL_THRESHOLD",
                 "MIN_RATE_LIMIT", "MAX_RATE_LIMIT"):
        assert f"`{name}`" in PAGE, name
    assert (sc.MIN_LENGTH, sc.MAX_LENGTH, sc.MAX_COORDINATE, sc.MAX_ANGLE) == (1e-3, 1e3, 1e4, 100)
    assert (sc.MIN_DURATION, sc.MAX_DURATION, sc.MAX_LINKS) == (1e-3, 1e6, 16)
    assert (sc.MIN_RATE_LIMIT, sc.MAX_RATE_LIMIT) == (1e-6, 1e6)
    assert (f"{sc.BYTES_PER_CELL_FIXED} + {sc.BYTES_PER_CELL_PER_JOINT}\\,n + "
            f"{sc.BYTES_PER_CELL_PER_JOINT_SQUARED}\\,n^2") in PAGE
    assert int(sc.max_cells(2) ** 0.5) == 2886 and 177 ** 3 <= sc.max_cells(3) < 178 ** 3
    assert f"[{sc.L_MIN}, {sc.L_MAX}]" in PAGE and f"{sc.R_MAX}$ m" in PAGE
    default_cells = sc.load_scenario(dict(BASE, arm={"link_lengths": [1, 1, 1]}, start=[0, 0, 0],
                                          goal={"joints": [1, 0, 0]}), check=False).planner.cells
    assert f"({default_cells[0]} for 3 joints)" in PAGE


# --------------------------------------------------------------------------- CLI facts


def test_exit_code_table_matches_the_cli():
    codes = {int(row[0].strip("`")) for row in TABLES["exit-codes"]}
    assert codes == {cli.EXIT_OK, cli.EXIT_NO_PLAN, cli.EXIT_BAD_INPUT, cli.EXIT_INTERNAL,
                     cli.EXIT_INTERRUPTED, cli.EXIT_TERMINATED, cli.EXIT_BROKEN_PIPE}


def test_exception_table_names_the_scenario_errors():
    named = {row[0].strip("`") for row in TABLES["scenario-exceptions"]}
    subclasses = {c.__name__ for c in vars(rapp.errors).values()
                  if isinstance(c, type) and issubclass(c, rapp.errors.ScenarioError)
                  and c is not rapp.errors.ScenarioError}
    assert named == subclasses


def test_check_output_on_the_page_is_what_the_cli_prints():
    shown = [(cap, body) for lang, cap, body in code_blocks()
             if lang == "text" and cap.startswith("Output of python -m rapp check ")]
    assert shown
    for cap, body in shown:
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            assert cli.main(["check", cap.split()[-1]]) == cli.EXIT_OK
        assert out.getvalue() == body


def test_embedded_scenario_table_lists_every_embedded_scenario():
    names = [row[0].strip("`") for row in TABLES["embedded-scenarios"]]
    assert sorted(names) == sc.list_scenarios()
    for name in names:  # each is a valid file (no_solution is valid; it just has no path)
        sc.load_scenario(name)


def test_cross_references_point_at_existing_labels():
    srs = (ROOT / "book" / "srs.md").read_text(encoding="utf-8")
    labels = set(re.findall(r"^\(([\w-]+)\)=$", srs, re.M))
    refs = set(re.findall(r"\{ref\}`([\w-]+)`", PAGE))
    assert {"srs-r1", "srs-r2", "srs-nfr5"} <= refs
    assert {r for r in refs if r.startswith("srs-")} <= labels
    own = set(TABLES) | set(re.findall(r"^\(([\w-]+)\)=$", PAGE, re.M))
    assert {r for r in refs if not r.startswith("srs-")} <= own
    assert PAGE.startswith("(scenario-format)=\n")
    for doc in re.findall(r"\{doc\}`([^`]+)`", PAGE):
        target = ROOT / "book" / doc
        assert any(target.with_suffix(s).resolve().is_file() for s in (".ipynb", ".md")), doc
