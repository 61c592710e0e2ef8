"""rapp.recorded: the machine of every recorded file, and the performance chapter's ratios."""

import math

import pytest

from rapp import recorded


@pytest.mark.parametrize("name", recorded.names())
def test_every_file_names_its_date_and_the_machine_fields_it_records(name):
    result = recorded.load(name)
    m = recorded.machine(result)
    assert set(m) == {"date", "load", "cpus", "platform"}
    assert m["date"] is not None and len(m["date"]) in (10, 16) and m["date"][4] == "-"
    raw = result.get("machine")
    if isinstance(raw, dict) and ("cpu_count" in raw or "cpus" in raw):
        assert m["cpus"] == raw.get("cpu_count", raw.get("cpus"))
    if m["load"] is not None:
        assert m["load"] >= 0


def test_machine_reads_each_shape_the_scripts_write():
    assert recorded.machine({"date": "2026-01-02T03:04:05", "machine": {"cpus": 8, "load_average": [1.5, 1, 1]}}) == {
        "date": "2026-01-02 03:04", "load": 1.5, "cpus": 8, "platform": None}
    assert recorded.machine({"machine": {"date": "2026-01-02", "cpu_count": 4, "load_1min": 0.25,
                                         "platform": "Linux"}}) == {
        "date": "2026-01-02", "load": 0.25, "cpus": 4, "platform": "Linux"}
    assert recorded.machine({"date": "2026-01-02", "machine": "a laptop"})["cpus"] is None


def test_limits_are_ratios_of_times_of_one_file_with_their_verdicts():
    rows = recorded.limits()
    assert len({(r.case, r.peer) for r in rows}) == len(rows)   # one row per comparison
    for r in rows:
        assert math.isfinite(r.ratio) and r.ratio > 0
        assert (r.goal is None) == (r.goal_text == "none")
        assert r.met is None if r.goal is None else r.met == (r.ratio >= r.goal)
    core = recorded.load("core")["results"]["3link_M128"]
    first = rows[0]
    assert math.isclose(first.ratio, core["grid_previous_rapp_s"] / core["grid_rapp_s"], rel_tol=1e-6)


def test_a_limit_misses_its_goal_below_it():
    row = recorded.Limit("case", "peer", "≥ 2×", 1.5, 2)
    assert row.met is False and recorded.Limit("c", "p", "none", 1.5, None).met is None


@pytest.mark.parametrize("k", [0.0123, 0.5, 3.0, 42.0, 1234.0])
def test_format_ratio_keeps_about_three_digits(k):
    text = recorded.format_ratio(k)
    assert text.endswith("×") and math.isclose(float(text[:-1].replace(",", "")), k, rel_tol=0.05)


def test_quoted_numbers_are_read_from_their_files():
    q = recorded.quoted()
    files = {name: recorded.load(name) for name in recorded.CHAPTER_FILES}
    search = files["search"]["results"]
    assert q["astar_scipy_min"] == min(s["ratio_scipy_over_rapp"] for s in search.values())
    assert q["astar_scipy_max"] == max(s["ratio_scipy_over_rapp"] for s in search.values())
    assert q["kern_min"] == files["collides"]["cpu_us"]["rapp_collides"] / files["collides"]["cpu_us"]["minimal_numba"]
    assert q["ts_one"] == files["time_scaling"]["ratios"]["rapp_trapezoidal_over_ruckig"]
    for key, short in (("rrt_connect", "rrtc"), ("prm", "prm"), ("rrt_star", "star")):
        p = files["planners_cpu"]["planners"][key]
        assert q[f"ompl_{short}"] == p["ratio_ompl_over_rapp_cpu"]
        assert q[f"ompl_{short}_c"] == p["ratio_ompl_corrected_over_rapp_cpu"]
    loads = [recorded.machine(f)["load"] for f in files.values() if recorded.machine(f)["load"] is not None]
    assert (q["load_lo"], q["load_hi"]) == (min(loads), max(loads))
    assert q["n_missed"] == sum(row.met is False for row in recorded.limits())
    assert all(type(v) is (int if k in {"cells128", "intervals", "painted", "n_missed", "ts_on", "ts_off",
                                         "ts_moves", "seeds", "cpu_seeds"} else float) for k, v in q.items())


def test_every_number_chapter_10_glues_from_the_files_is_quoted():
    """The chapter's prose names each glued number; those of the peers' section come from quoted()."""
    import json
    import re
    from pathlib import Path
    nb = json.loads((Path(__file__).resolve().parents[1] / "notebooks" / "10_performance.ipynb").read_text())
    prose = "".join("".join(c["source"]) for c in nb["cells"] if c["cell_type"] == "markdown")
    used = set(re.findall(r"\{glue:text\}`(\w+)", prose))
    glued_in_cells = set(re.findall(r'glue\("(\w+)"', "".join("".join(c["source"]) for c in nb["cells"]
                                                            if c["cell_type"] == "code")))
    assert used <= set(recorded.quoted()) | glued_in_cells, used - set(recorded.quoted()) - glued_in_cells


def test_limit_labels_are_short():
    rows = recorded.limits()
    assert len({row.label for row in rows}) == len(rows)
    assert all(len(row.label) <= len(f"{row.case} vs {row.peer}") for row in rows)
    assert "RRT-Connect vs OMPL (as compiled)" in [row.label for row in rows]
