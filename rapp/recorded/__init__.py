"""Benchmark results as recorded by the scripts in the repository's ``benchmarks/`` folder.

They are package data, so that the performance chapter reads the same numbers with only
``rapp`` installed, from any folder. Each file holds the machine it was recorded on (CPUs,
load, platform) and the date beside the timings; the scripts rewrite them
(``python benchmarks/bench_core.py`` writes ``rapp/recorded/core.json``, ...).

Examples
--------
>>> names()
['astar_cpp', 'cli', 'collides', 'core', 'ik', 'kernel', 'live', 'memory', 'motion', 'occupancy', 'planners', 'planners_cpu', 'planners_ompl', 'planners_ompl_kernel', 'roadmap', 'search', 'time_scaling']
>>> core = load("core")
>>> core["machine"]["cpu_count"], sorted(core["results"])[:2]
(2, ['2link_M100', '2link_M360'])
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from importlib import resources

__all__ = ["names", "load", "machine", "Limit", "limits", "format_ratio", "quoted", "CHAPTER_FILES"]


def names() -> list[str]:
    """The recorded results, by name (a file ``NAME.json`` of this package), sorted."""
    return sorted(f.name[:-5] for f in resources.files(__name__).iterdir()
                  if f.name.endswith(".json"))


def load(name: str) -> dict:
    """The recorded result ``name`` (see :func:`names`), parsed from its JSON file.

    Raises
    ------
    KeyError
        When no result of that name is recorded; the message lists those that are.
    """
    if name not in names():
        raise KeyError(f"no recorded result {name!r}; recorded: {', '.join(names())}")
    return json.loads(resources.files(__name__).joinpath(f"{name}.json").read_text("utf-8"))


def machine(result: dict) -> dict:
    """Where and when a recorded result was taken: ``date``, ``load``, ``cpus``, ``platform``.

    The scripts store the machine in a few shapes (``machine.cpu_count`` or ``machine.cpus``, a
    1-minute load or a tuple of three, the date at the top or in ``machine``); this reads them all.
    ``date`` is ``"YYYY-MM-DD HH:MM"``; a field the file does not hold is ``None``.

    Examples
    --------
    >>> m = machine(load("core"))
    >>> sorted(m), m["cpus"] == load("core")["machine"]["cpu_count"]
    (['cpus', 'date', 'load', 'platform'], True)
    """
    m = result.get("machine")
    m = m if isinstance(m, dict) else {}   # a few files name the machine in a sentence
    load_ = (m.get("load_1min") or m.get("load_average_1min") or m.get("load_average_1min_before")
             or (m.get("load_before") or m.get("load_average") or result.get("load_average") or [None])[0])
    date = result.get("date") or m.get("date")
    return {"date": date[:16].replace("T", " ") if date else None, "load": load_,
            "cpus": m.get("cpu_count") or m.get("cpus"), "platform": m.get("platform")}


@dataclass(frozen=True)
class Limit:
    """One line of the performance chapter's "speed toward the limit": a peer's time over rapp's.

    ``ratio`` > 1 means rapp is faster; ``goal`` is the project's bound on the ratio (``None``: no
    goal set) and ``goal_text`` says it in words.
    """

    case: str
    peer: str
    goal_text: str
    ratio: float
    goal: float | None

    @property
    def label(self) -> str:
        """``"case vs peer"`` in the few words the performance chapter's figure has room for.

        Examples
        --------
        >>> Limit("A* on 360²", "scipy BFS + graph build", "≥ 1×", 18.0, 1).label
        'A* on 360² vs scipy + graph build'
        """
        text = f"{self.case} vs {self.peer}"
        for long, brief in _SHORT.items():
            text = text.replace(long, brief)
        return text

    @property
    def met(self) -> bool | None:
        """Whether the ratio reaches its goal; ``None`` where no goal is set."""
        return None if self.goal is None else bool(self.ratio >= self.goal)


#: Words :attr:`Limit.label` shortens, in this order.
_SHORT = {"C-space grid, 3 links, ": "grid ", ", 10 000 targets": "", "robotics-toolbox": "rtb", " (C++)": "",
          "scipy BFS + graph build": "scipy + graph build", "scipy BFS, graph given": "scipy, graph given",
          "its floor: painting given intervals": "its floor", ", Python callback, CPU time": " (callback)",
          ", callback costed as compiled": " (as compiled)", "with rapp's numpy checker": "(numpy checker)",
          ", fastest call": "", "python -m rapp plan": "plan", "python -c 'import numpy'": "import numpy",
          "previous certified_free": "previous", ", 20 seeds": "",
          "RRT-Connect, 3 links": "RRT-Connect", "PRM, 3 links": "PRM", "RRT*, 3 links": "RRT*"}


def limits() -> list[Limit]:
    """Every recorded ratio of rapp against a favourable baseline and its fairest peer, with goals.

    Read from the recorded files ``core``, ``ik``, ``occupancy``, ``search``, ``astar_cpp``,
    ``kernel``, ``collides``, ``planners_ompl``, ``planners_cpu``, ``time_scaling`` and ``cli``; each ratio
    divides two times of the same file. The OMPL rows are CPU times (``planners_cpu``): OMPL
    calling rapp's compiled checker through its Python callback as measured, and with each of
    its checker calls costed as a compiled check instead.

    Examples
    --------
    >>> rows = limits()
    >>> rows[0].case, rows[0].peer, rows[0].goal
    ('C-space grid, 3 links, 128³', 'previous rapp grid', 4)
    >>> rows[0].ratio == load("core")["results"]["3link_M128"]["grid_ratio_previous_over_rapp"]
    True
    """
    core, ik, occ, search, cpp, kern, ompl, ompl_cpu, ts, cli = (load(n) for n in (
        "core", "ik", "occupancy", "search", "astar_cpp", "kernel", "planners_ompl",
        "planners_cpu", "time_scaling", "cli"))
    m128, a2, rtb = core["results"]["3link_M128"], ik["analytic_2link"], ik["rtb_ik_GN"]
    o128, sr, g = occ["results"]["3link_M128"], search["results"], cpp["grids"]
    kp, pc = kern["planners"], ompl_cpu["planners"]
    rows = [
        ("C-space grid, 3 links, 128³", "previous rapp grid", "≥ 4×", m128["grid_ratio_previous_over_rapp"], 4),
        ("C-space grid, 3 links, 128³", "its floor: painting given intervals", "≥ 0.5×",
         1 / o128["ratio_rapp_new_scene_over_floor"], 0.5),
        ("same grid, same obstacles again", "its floor: painting given intervals", "none",
         1 / o128["ratio_rapp_over_floor"], None)]
    for key, size in (("2link_M360", "360²"), ("2link_M720", "720²"), ("3link_M64", "64³")):
        rows += [(f"A* on {size}", "scipy BFS + graph build", "≥ 1×", sr[key]["ratio_scipy_over_rapp"], 1),
                 (f"A* on {size}", "scipy BFS, graph given", "none", sr[key]["ratio_scipy_given_graph_over_rapp"], None)]
    for key, size in (("2link_M360", "360²"), ("2link_M720", "720²")):
        rows += [(f"A* on {size}", "pyastar2d (C++), plain grid", "≥ 1×", g[key]["pyastar2d_no_wrap_over_rapp"], 1),
                 (f"A* on {size}", "pyastar2d, unrolled torus", "none", g[key]["pyastar2d_over_rapp"], None)]
    rows += [
        ("IK, 2 links, 10 000 targets", "loop of rapp.ik", "≥ 100×", a2["speedup"], 100),
        ("IK, 2 links, 10 000 targets", "loop of ik_2link", "none", a2["speedup_over_loop_ik_2link"], None),
        ("IK, 2 links, 10 000 targets", "numpy one-liner", "none", 1 / a2["ratio_batch_over_numpy"], None),
        ("IK, 3 links, 10 000 targets", "robotics-toolbox ik_GN, fastest call", "≥ 150×", rtb["ratio_cpu_rtb_over_rapp"], 150),
        ("IK, 3 links, 10 000 targets", "robotics-toolbox Robot.ik_GN", "none", rtb["ratio_cpu_rtb_robot_over_rapp"], None),
        ("IK, 3 links, random starts", "robotics-toolbox ik_GN, fastest call", "none",
         rtb["ratio_cpu_rtb_over_rapp_random_starts"], None),
        ("collides, one configuration", "numpy checker", "≥ 20×", kern["single"]["collides_one_us"]["ratio"], 20),
        ("collides, one configuration", "minimal numba test", "≥ 0.5×",
         1 / load("collides")["ratio_rapp_over_minimal"], 0.5),
        ("rrt_connect, 20 seeds", "numpy checker", "≥ 3×", kp["rrt_connect"]["ratio_total"], 3),
        ("prm, 20 seeds", "numpy checker", "≥ 3×", kp["prm"]["ratio_total"], 3),
        ("rrt_star, 20 seeds", "numpy checker", "none", kp["rrt_star"]["ratio_total"], None),
        ("RRT-Connect, 3 links", "OMPL with rapp's numpy checker", "none", ompl["median_ratio_ompl_over_rapp"], None),
        ("RRT-Connect, 3 links", "OMPL, Python callback, CPU time", "none", pc["rrt_connect"]["ratio_ompl_over_rapp_cpu"], None),
        ("RRT-Connect, 3 links", "OMPL, callback costed as compiled", "≥ 1×", pc["rrt_connect"]["ratio_ompl_corrected_over_rapp_cpu"], 1),
        ("PRM, 3 links", "OMPL, Python callback, CPU time", "none", pc["prm"]["ratio_ompl_over_rapp_cpu"], None),
        ("PRM, 3 links", "OMPL, callback costed as compiled", "≥ 1×", pc["prm"]["ratio_ompl_corrected_over_rapp_cpu"], 1),
        ("RRT*, 3 links", "OMPL, Python callback, CPU time", "none", pc["rrt_star"]["ratio_ompl_over_rapp_cpu"], None),
        ("RRT*, 3 links", "OMPL, callback costed as compiled", "≥ 1×", pc["rrt_star"]["ratio_ompl_corrected_over_rapp_cpu"], 1),
        ("one trapezoidal move", "ruckig (C++)", "≥ 0.33×", 1 / ts["ratios"]["rapp_trapezoidal_over_ruckig"], 1 / 3),
        ("one move, trapezoidal_moves", "ruckig (C++)", "none",
         1 / ts["ratios"]["rapp_moves_one_over_ruckig"], None),
        ("python -m rapp plan", "python -c 'import numpy'", "≥ 0.5×",
         1 / kern["start_up"]["plan_over_import_numpy_median"], 0.5),
        ("certified cells, 40³", "previous certified_free", "none", cli["stages"]["ratio"], None),
    ]
    return [Limit(case, peer, text, float(ratio), goal) for case, peer, text, ratio, goal in rows]


def format_ratio(k: float) -> str:
    """A ratio with the digits that matter at its size, as the performance chapter prints it.

    Examples
    --------
    >>> [format_ratio(k) for k in (1234.5, 42.0, 3.14159, 0.25, 0.01234)]
    ['1,234×', '42.0×', '3.14×', '0.25×', '0.012×']
    """
    return f"{k:,.0f}×" if k >= 100 else f"{k:.1f}×" if k >= 10 else f"{k:.2f}×" if k >= 0.1 else f"{k:.3f}×"


#: The recorded files the performance chapter reads, by name.
CHAPTER_FILES = ("core", "ik", "occupancy", "search", "astar_cpp", "kernel", "collides", "planners_ompl",
                 "planners_ompl_kernel", "time_scaling", "cli", "planners_cpu")


def quoted() -> dict:
    """Every number the performance chapter quotes about rapp and its peers, by its name there.

    Each is read from the recorded files of :data:`CHAPTER_FILES` (a ratio from two times of
    the same file, a share, a count), so that a re-recorded file changes the chapter's
    sentences with it; the chapter's hidden checks then hold what the sentences say.
    Counts are ints, everything else floats.

    Examples
    --------
    >>> q = quoted()
    >>> q["ompl_prm"] == load("planners_cpu")["planners"]["prm"]["ratio_ompl_over_rapp_cpu"]
    True
    >>> q["n_missed"] == sum(row.met is False for row in limits())
    True
    """
    f = {name: load(name) for name in CHAPTER_FILES}
    res, ik, kern, cpu, ts, cli = f["core"]["results"], f["ik"], f["kernel"], f["planners_cpu"], f["time_scaling"], f["cli"]
    m128, m64, o128 = res["3link_M128"], res["3link_M64"], f["occupancy"]["results"]["3link_M128"]
    sr, g, a2, rtb = f["search"]["results"], f["astar_cpp"]["grids"], ik["analytic_2link"], ik["rtb_ik_GN"]
    pc, ck, pl, problem = cpu["planners"], cpu["checker"], f["planners_ompl_kernel"]["planners"], f["planners_ompl_kernel"]["problem"]
    ru, stage, c, parts = ts["ruckig"], cli["stages"]["stage_s"], cli["cli"], cli["plot_parts"]
    loads = [machine(x)["load"] for x in f.values() if machine(x)["load"] is not None]
    figure_s = parts["import_matplotlib_plotting_s"] + parts["figure_s"] + parts["save_png_s"]
    scipy_k = [s["ratio_scipy_over_rapp"] for s in sr.values()]
    old_k = [s["ratio_old_over_rapp"] for s in sr.values()]
    given = [s["ratio_scipy_given_graph_over_rapp"] for s in sr.values()]
    out = {
        "load_lo": min(loads), "load_hi": max(loads),
        "lim_grid": m128["grid_ratio_previous_over_rapp"], "lim_grid64": m64["grid_ratio_previous_over_rapp"],
        "mem_new": m128["peak_bytes_per_cell_rapp"], "mem_old": m128["peak_bytes_per_cell_previous"],
        "tangent": m128["mismatched_max_abs_clearance"], "occ_floor": o128["ratio_rapp_new_scene_over_floor"],
        "occ_floor_warm": o128["ratio_rapp_over_floor"],
        "astar_scipy_min": min(scipy_k), "astar_scipy_max": max(scipy_k),
        "astar_old_min": min(old_k), "astar_old_max": max(old_k), "given_min": min(given), "given_max": max(given),
        "cpp_plain360": g["2link_M360"]["pyastar2d_no_wrap_over_rapp"], "cpp_plain720": g["2link_M720"]["pyastar2d_no_wrap_over_rapp"],
        "cpp_torus360": g["2link_M360"]["pyastar2d_over_rapp"], "cpp_torus720": g["2link_M720"]["pyastar2d_over_rapp"],
        "ns_exp": sum(v["rapp_ns_per_expansion"] for v in g.values()) / len(g),
        "exp2": (sr["2link_M360"]["expanded_fraction_of_free"] + sr["2link_M720"]["expanded_fraction_of_free"]) / 2,
        "exp3": sr["3link_M64"]["expanded_fraction_of_free"],
        "ik2_speedup": a2["speedup"], "ik2_err": a2["batch_max_error_m"], "ik2_loop2": a2["speedup_over_loop_ik_2link"],
        "ik2_numpy": a2["ratio_batch_over_numpy"], "ik2_numpy_err": a2["numpy_max_error_m"],
        "ik3_us": rtb["rapp_cpu_us_per_target"], "ik3_err": ik["batched"]["max_error_m"],
        "rtb_fast": rtb["ratio_cpu_rtb_over_rapp"], "rtb_robot": rtb["ratio_cpu_rtb_robot_over_rapp"],
        "rtb_random": rtb["ratio_cpu_rtb_over_rapp_random_starts"],
        "kern_one": kern["single"]["collides_one_us"]["ratio"], "kern_rrtc": kern["planners"]["rrt_connect"]["ratio_total"],
        "kern_prm": kern["planners"]["prm"]["ratio_total"], "kern_star": kern["planners"]["rrt_star"]["ratio_total"],
        "kern_min": f["collides"]["ratio_rapp_over_minimal"], "kern_min_us": f["collides"]["cpu_us"]["minimal_numba"],
        "kern_rapp_us": f["collides"]["cpu_us"]["rapp_collides"],
        "cb_us": ck["callback_us"], "compiled_us": ck["compiled_us"], "cpu_seeds": cpu["problem"]["seeds"],
        "len_star_step": pl["rrt_star"]["rapp_step_radius"]["median_length"],
        "len_star_long": pl["rrt_star"]["ompl_long_range"]["median_length"],
        "ompl_long_ratio": pl["rrt_star"]["ompl_long_range"]["median_s"] / pl["rrt_star"]["rapp"]["median_s"],
        "star_radius_steps": problem["rrt_star_radius"] / problem["rrt_star_step"], "seeds": problem["seeds"],
        "ts_one": ts["ratios"]["rapp_trapezoidal_over_ruckig"], "ts_moves_one": ts["ratios"]["rapp_moves_one_over_ruckig"],
        "ts_batch": 1 / ts["ratios"]["rapp_moves_batch_over_ruckig"],
        "ts_gain_max": ru["their_duration_gain_max"], "ts_gain_med": ru["their_duration_gain_median"],
        "ts_on": ru["moves_on_segment"], "ts_off": ru["moves_leaving_segment"], "ts_moves": ts["problem"]["moves"],
        "startup": kern["start_up"]["plan_over_import_numpy_median"], "cert_ratio": cli["stages"]["ratio"],
        "cspace_share": stage["cspace"] / stage["total"], "search_share": stage["search"] / stage["total"],
        "cli_ratio": c["ratio"], "cli_plot": c["plan_plot_s"], "cli_plan": c["plan_s"], "cli_load": cli["machine"]["load_1min"],
        "mpl_import": parts["import_matplotlib_plotting_s"], "parts_plan": parts["plan_s"],
        "import_share": parts["import_matplotlib_plotting_s"] / figure_s, "draw_s": parts["figure_s"],
        "write_s": parts["save_png_s"], "figure_s": figure_s, "cells128": m128["cells"],
        "intervals": o128["intervals"], "painted": o128["intervals_painted"],
        "n_missed": sum(row.met is False for row in limits()),
    }
    for key, short in (("rrt_connect", "rrtc"), ("prm", "prm"), ("rrt_star", "star")):
        out[f"ompl_{short}"] = pc[key]["ratio_ompl_over_rapp_cpu"]
        out[f"ompl_{short}_c"] = pc[key]["ratio_ompl_corrected_over_rapp_cpu"]
        out[f"len_{short}_r"] = pl[key]["rapp"]["median_length"]
        out[f"len_{short}_o"] = pl[key]["ompl"]["median_length"]
    counts = {"cells128", "intervals", "painted", "n_missed", "ts_on", "ts_off", "ts_moves", "seeds", "cpu_seeds"}
    return {k: int(v) if k in counts else float(v) for k, v in out.items()}
