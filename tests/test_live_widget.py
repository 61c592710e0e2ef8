"""rapp.live's Python side: the state an explorer starts from (no browser needed)."""

import numpy as np
import pytest

import rapp
from rapp import live


def test_scenario_dict_round_trips_through_the_scenario_format():
    arm = rapp.Arm([1.0, 0.7])
    square = rapp.Polygon.rectangle((-1.75, -0.2), 0.4, 0.4)
    d = live.scenario_dict((arm, [rapp.Circle((1.0, 0.5), 0.3), square]))
    s = rapp.load_scenario({**d, "start": [0.0, 3.0], "goal": {"joints": [0.0, 3.0]}})
    assert s.arm == arm
    assert s.obstacles[0] == rapp.Circle((1.0, 0.5), 0.3)
    assert np.allclose(s.obstacles[1].array, square.array)


def test_explorers_start_where_the_grid_puts_their_configurations():
    w = live.astar_explorer("default", cells=100, start=(0.0, 0.0), goal=(-2.9, -1.5))
    grid = rapp.JointGrid(rapp.Arm([1.0, 1.0]), 100)
    assert w.start == grid.index([0.0, 0.0]).tolist() and w.goal == grid.index([-2.9, -1.5]).tolist()
    p = live.astar_explorer(source="paint", paint_cells=12, walls=[(6, 0)], paint_start=(2, 6), paint_goal=(9, 5))
    assert (p.start, p.goal, p.walls, p.paint_cells) == ([2, 6], [9, 5], [[6, 0]], 12)
    c = live.cspace_explorer(cells=120, q=(0.45, 0.2))
    assert c.q == [0.45, 0.2] and not c.search and "rappLive" in c._esm and "export default" in c._esm


def test_the_sweep_explorer_starts_on_its_obstacle():
    w = live.sweep_explorer("default", obstacle=2, cells=48, q2=0.3)
    assert (w.sweep, w.cells, w.q, w.search) == (2, 48, [0.0, 0.3], False)
    assert live.cspace_explorer().sweep == -1 and live.astar_explorer().sweep == -1


def test_the_explorer_module_is_its_parts_in_order():
    """One ES module (anywidget stores one string; the static book loads nothing else), made of
    the core, the state, the drawing, the dragging and the page, and exporting render."""
    from pathlib import Path

    esm = live.explorer_js()
    here = Path(live.__file__).parent
    offsets = [esm.index((here / name).read_text(encoding="utf-8")) for name in live.PARTS]
    assert offsets == sorted(offsets) and offsets[0] == 0
    assert esm.count("export default") == 1 and esm.rstrip().endswith("export default { render };")
    assert "import " not in esm.replace("await import(", "")


def test_the_explorer_module_parses_under_node(tmp_path):
    import shutil
    import subprocess

    node = shutil.which("node")
    if node is None:
        pytest.skip("no node on PATH")
    (tmp_path / "explorer.mjs").write_text(live.explorer_js(), encoding="utf-8")
    done = subprocess.run([node, "--check", str(tmp_path / "explorer.mjs")], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr


@pytest.mark.parametrize("call, field", [
    (lambda: live.cspace_explorer(cells=300), "cells"),
    (lambda: live.cspace_explorer((rapp.Arm([1.0, 1.0, 1.0]), []),), "scenario"),
    (lambda: live.cspace_explorer((rapp.Arm([1.0, 1.0], [None, (-1.0, 1.0)]), []),), "scenario"),
    (lambda: live.astar_explorer(weight=0.5), "weight"),
    (lambda: live.astar_explorer(source="maze"), "source"),
    (lambda: live.astar_explorer(source="paint", paint_cells=100), "paint_cells"),
    (lambda: live.sweep_explorer(obstacle=3), "obstacle"),
    (lambda: live.sweep_explorer(cells=10), "cells"),
])
def test_bad_input_names_the_field(call, field):
    with pytest.raises(ValueError, match=f"^{field}"):
        call()


@pytest.mark.parametrize("name", ["04_configuration_space.ipynb", "05_astar.ipynb", "05_astar_variants.ipynb"])
def test_the_chapters_carry_the_current_explorer(name):
    """The static book runs the JavaScript saved in the notebook's widget state: after a change
    to rapp/live/*.js, chapters 4 and 5 must be re-executed (scripts/execute_notebooks.py)."""
    import json
    from pathlib import Path

    nb = json.loads((Path(__file__).resolve().parents[1] / "notebooks" / name).read_text())
    state = nb["metadata"]["widgets"]["application/vnd.jupyter.widget-state+json"]["state"]
    esm = [m["state"]["_esm"] for m in state.values() if m["model_module"] == "anywidget"]
    assert esm and all(e == live.explorer_js() for e in esm)
