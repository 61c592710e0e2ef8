"""rapp.raster: the plan figure drawn with Pillow, checked pixel by pixel where things must be.

Every check maps data through the panel's :class:`rapp.raster.Panel` and reads the pixel there:
the obstacles, the occupancy cells, the start and goal markers and the paths are where the plan
says, in the palette's colours; and ``--plot fig.png`` writes it without importing matplotlib.
"""

import os
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image, ImageColor

import rapp
from rapp import palette, raster
from rapp.errors import NoPathFound
from rapp.paths import split_at_seam


def rgb(color):
    return np.array(ImageColor.getrgb(color)[:3], dtype=float)


def pixel(image, uv):
    u, v = np.floor(np.asarray(uv, dtype=float)).astype(int)
    return np.array(image.getpixel((int(u), int(v)))[:3], dtype=float)


def near(image, uv, color, radius=2, tol=40.0):
    """Whether some pixel within ``radius`` of ``uv`` is within ``tol`` of ``color``."""
    u, v = np.floor(np.asarray(uv, dtype=float)).astype(int)
    target = rgb(color)
    for du in range(-radius, radius + 1):
        for dv in range(-radius, radius + 1):
            if np.abs(pixel(image, (u + du, v + dv)) - target).max() <= tol:
                return True
    return False


@pytest.fixture(scope="module")
def planned():
    """name -> (plan, scenario) for the scenarios used below, planned once."""
    out = {}
    for name in ("default", "three_link", "rectangles"):
        s = rapp.load_scenario(name)
        out[name] = (rapp.plan(s), s)
    return out


def cspace_frame(p):
    ext = rapp.cspace.cell_extent(p.grid)
    lo = np.array([ext[0], ext[2]])
    span = np.array([ext[1] - ext[0], ext[3] - ext[2]])
    return lo, span, np.asarray(p.grid.wraps[:2], dtype=bool)


def far_from(points_px, uv, distance):
    pts = np.asarray(points_px, dtype=float).reshape(-1, 2)
    pts = pts[np.isfinite(pts).all(axis=1)]
    return np.hypot(*(pts - uv).T).min() > distance


def dense(points, k=20):
    """``k`` points on each segment of a polyline (NaN rows break it)."""
    p = np.asarray(points, dtype=float)
    t = np.linspace(0.0, 1.0, k)[:, None, None]
    return (p[:-1] + t * (p[1:] - p[:-1])).transpose(1, 0, 2).reshape(-1, 2)


# --------------------------------------------------------------------------- the image


def test_size_white_background_and_two_framed_square_panels(planned):
    p, s = planned["default"]
    image = raster.render_plan(p, s)
    assert image.size == (raster.WIDTH, raster.HEIGHT) == (1050, 500) and image.mode == "RGB"
    for corner in ((0, 0), (1049, 0), (0, 499), (1049, 499), (525, 250)):
        assert image.getpixel(corner) == (255, 255, 255)
    cspace, workspace = raster.plan_panels(p, s)
    assert cspace.right <= 525 <= workspace.left
    for panel in (cspace, workspace):
        # equal aspect: a data unit is as many pixels across as up
        w, h = panel.right - panel.left, panel.bottom - panel.top
        assert w / (panel.xlim[1] - panel.xlim[0]) == pytest.approx(
            h / (panel.ylim[1] - panel.ylim[0]))
        # the frame: the pixels just outside the drawing area, in the text colour
        for uv in ((panel.left - 1, (panel.top + panel.bottom) // 2),
                   ((panel.left + panel.right) // 2, panel.bottom)):
            assert np.abs(pixel(image, uv) - rgb(palette.TEXT)).max() <= 2
        # text above (title) and below (tick labels, axis label) each panel
        title = np.asarray(image.crop((panel.left, 0, panel.right, panel.top - 2)))
        below = np.asarray(image.crop((panel.left, panel.bottom + 8, panel.right, 500)))
        assert (title.min(axis=-1) < 100).sum() > 50 and (below.min(axis=-1) < 100).sum() > 100
    assert cspace.xlim == pytest.approx(rapp.cspace.cell_extent(p.grid)[:2], abs=0.02)


def test_panels_map_data_limits_to_their_edges(planned):
    p, s = planned["default"]
    for panel in raster.plan_panels(p, s):
        corners = panel.to_pixel([[panel.xlim[0], panel.ylim[1]], [panel.xlim[1], panel.ylim[0]]])
        np.testing.assert_allclose(corners, [[panel.left, panel.top],
                                             [panel.right, panel.bottom]], atol=1e-9)
    workspace = raster.plan_panels(p, s)[1]
    r = s.arm.reach[1]
    assert workspace.xlim[1] >= 1.1 * r and workspace.ylim == pytest.approx(workspace.xlim)


@pytest.mark.parametrize("name", ["default", "three_link", "rectangles"])
def test_obstacles_are_drawn_where_they_are(planned, name):
    p, s = planned[name]
    image = raster.render_plan(p, s, legend=False)
    workspace = raster.plan_panels(p, s)[1]
    # 85 % obstacle grey over the light workspace (white, sky tint, a grid line: >= 200)
    grey = 0.85 * rgb(palette.OBSTACLE)
    lo, hi = grey + 0.15 * 200 - 1, grey + 0.15 * 255 + 1
    for ob in s.obstacles:
        inside = ob.center if hasattr(ob, "radius") else np.mean(ob.vertices, axis=0)
        colour = pixel(image, workspace.to_pixel(inside))
        assert np.all((lo <= colour) & (colour <= hi)), (ob, colour)


def test_the_base_and_the_arms_are_drawn(planned):
    p, s = planned["default"]
    image = raster.render_plan(p, s)
    workspace = raster.plan_panels(p, s)[1]
    assert np.abs(pixel(image, workspace.to_pixel([0.0, 0.0])) - rgb(palette.TEXT)).max() <= 2
    start = s.arm.joint_positions(p.q[0])
    final = s.arm.joint_positions(p.q[-1])
    # the middle of each link of the start and final arms, in their colours
    for pts, colour in ((start, palette.START), (final, palette.ARM)):
        for a, b in zip(pts[:-1], pts[1:]):
            assert near(image, workspace.to_pixel((a + b) / 2), colour, radius=1, tol=10)
    # the end effector of the final arm: a vermillion dot (under the goal star, same colour)
    assert np.abs(pixel(image, workspace.to_pixel(final[-1])) - rgb(palette.EFFECTOR)).max() <= 2


def test_two_link_cells_are_occupied_grey_and_free_white(planned):
    p, s = planned["default"]
    image = raster.render_plan(p, s, legend=False)
    cspace = raster.plan_panels(p, s)[0]
    lo, span, wraps = cspace_frame(p)
    path_px = cspace.to_pixel(dense(split_at_seam(p.q[:, :2], lo, span, wraps)))
    occ = np.asarray(p.occupancy)
    a0, a1 = (np.asarray(a, dtype=float) for a in p.grid.axes[:2])
    checked = {True: 0, False: 0}
    for i in range(1, len(a0) - 1, 3):
        for j in range(1, len(a1) - 1, 3):
            block = occ[i - 1:i + 2, j - 1:j + 2]
            uv = cspace.to_pixel([a0[i], a1[j]])
            if block.min() != block.max() or not far_from(path_px, uv, 12):
                continue
            expected = rgb(palette.OCCUPIED) if occ[i, j] else np.array([255.0, 255, 255])
            assert np.array_equal(pixel(image, uv), expected), (i, j, occ[i, j])
            checked[bool(occ[i, j])] += 1
    assert checked[True] > 50 and checked[False] > 200


def test_three_link_grey_level_is_the_fraction_in_collision(planned):
    p, s = planned["three_link"]
    image = raster.render_plan(p, s, legend=False)
    cspace = raster.plan_panels(p, s)[0]
    lo, span, wraps = cspace_frame(p)
    path_px = cspace.to_pixel(dense(split_at_seam(p.q[:, :2], lo, span, wraps)))
    occ = np.asarray(p.occupancy)
    frac = occ.reshape(occ.shape[:2] + (-1,)).mean(axis=-1)
    a0, a1 = (np.asarray(a, dtype=float) for a in p.grid.axes[:2])
    levels = set()
    for i in range(len(a0)):
        for j in range(len(a1)):
            uv = cspace.to_pixel([a0[i], a1[j]])
            if not far_from(path_px, uv, 12):
                continue
            grey = pixel(image, uv)
            assert grey[0] == grey[1] == grey[2]
            assert abs(grey[0] - 255 * (1 - frac[i, j])) <= 1, (i, j, frac[i, j], grey)
            levels.add(round(frac[i, j], 2))
    assert len(levels) > 10 and 0.0 in levels and 1.0 in levels


@pytest.mark.parametrize("name", ["default", "three_link", "rectangles"])
def test_start_goal_and_path_in_cspace(planned, name):
    p, s = planned[name]
    image = raster.render_plan(p, s)  # with its legend, which must not hide them
    cspace = raster.plan_panels(p, s)[0]
    lo, span, wraps = cspace_frame(p)
    start = split_at_seam(p.q[0, :2], lo, span, wraps)[0]
    goal = split_at_seam(p.q[-1, :2], lo, span, wraps)[0]
    assert np.abs(pixel(image, cspace.to_pixel(start)) - rgb(palette.START)).max() <= 2
    assert np.abs(pixel(image, cspace.to_pixel(goal)) - rgb(palette.GOAL)).max() <= 2
    marks = cspace.to_pixel([start, goal])
    samples = [uv for uv in cspace.to_pixel(dense(split_at_seam(p.q[:, :2], lo, span, wraps), 5))
               if np.isfinite(uv).all() and far_from(marks, uv, 10)
               and cspace.left + 2 < uv[0] < cspace.right - 2
               and cspace.top + 2 < uv[1] < cspace.bottom - 2]
    assert len(samples) > 20
    assert all(near(image, uv, palette.PATH, radius=1, tol=30) for uv in samples)


@pytest.mark.parametrize("name", ["default", "rectangles"])
def test_end_effector_path_in_workspace(planned, name):
    p, s = planned[name]
    image = raster.render_plan(p, s, legend=False)
    workspace = raster.plan_panels(p, s)[1]
    joints = workspace.to_pixel(np.concatenate([s.arm.joint_positions(p.q[0]),
                                                s.arm.joint_positions(p.q[-1])]))
    samples = [uv for uv in workspace.to_pixel(p.xy[::7]) if far_from(joints, uv, 10)]
    assert len(samples) > 10
    hits = [near(image, uv, palette.PATH, radius=1, tol=30) for uv in samples]
    assert np.mean(hits) > 0.9  # a ghost arm's effector dot may sit on a sample


def test_cartesian_goal_is_a_star_at_goal_xy(planned):
    p, s = planned["default"]
    assert s.goal_xy is not None
    image = raster.render_plan(p, s)
    workspace = raster.plan_panels(p, s)[1]
    uv = workspace.to_pixel(s.goal_xy)
    assert np.abs(pixel(image, uv) - rgb(palette.GOAL)).max() <= 2
    # a star, not a dot: its upper point reaches about 9 pixels above its centre
    assert np.abs(pixel(image, uv - (0, 7)) - rgb(palette.GOAL)).max() <= 40


def test_every_embedded_scenario_renders():
    for name in rapp.scenario.list_scenarios():
        s = rapp.load_scenario(name)
        try:
            p = rapp.plan(s)
        except NoPathFound:
            continue  # no plan to draw (the no_solution scenario)
        image = raster.render_plan(p, s)
        assert image.size == (1050, 500), name
        cspace, workspace = raster.plan_panels(p, s)
        start = split_at_seam(p.q[0, :2], *cspace_frame(p))[0]
        assert np.abs(pixel(image, cspace.to_pixel(start)) - rgb(palette.START)).max() <= 2, name


def test_a_plan_without_a_grid_draws_the_joint_path_alone(tmp_path):
    s = rapp.load_scenario({
        "name": "rrt_example", "arm": {"link_lengths": [1.0, 1.0]},
        "obstacles": [{"type": "circle", "center": [0.5, 0.5], "radius": 0.3}],
        "start": [0.0, 0.0], "goal": {"position": [1.0, 1.0]},
        "planner": {"algorithm": "rrt", "step": 0.1, "goal_bias": 0.1, "goal_threshold": 0.01,
                    "max_iterations": 20000, "seed": 7}})
    p = rapp.plan(s)
    assert getattr(p, "grid", None) is None
    image = raster.render_plan(p, s, legend=False)
    cspace, workspace = raster.plan_panels(p, s)
    assert cspace.xlim == pytest.approx((-np.pi, np.pi), abs=0.02)
    lo, hi = s.arm.lower[:2], s.arm.upper[:2]
    wraps = ~s.arm.limited[:2]
    start = split_at_seam(p.q[0, :2], lo, hi - lo, wraps)[0]
    goal = split_at_seam(p.q[-1, :2], lo, hi - lo, wraps)[0]
    assert np.abs(pixel(image, cspace.to_pixel(start)) - rgb(palette.START)).max() <= 2
    assert np.abs(pixel(image, cspace.to_pixel(goal)) - rgb(palette.GOAL)).max() <= 2
    # no occupancy: the panel is white away from the path
    path_px = cspace.to_pixel(dense(split_at_seam(p.q[:, :2], lo, hi - lo, wraps)))
    for uv in cspace.to_pixel(np.stack(np.meshgrid(np.linspace(-3, 3, 9),
                                                   np.linspace(-3, 3, 9)), -1).reshape(-1, 2)):
        if far_from(path_px, uv, 8) and far_from(cspace.to_pixel([start, goal]), uv, 10):
            assert tuple(pixel(image, uv)) == (255, 255, 255)
    # the Cartesian goal in the workspace
    assert np.abs(pixel(image, workspace.to_pixel(s.goal_xy)) - rgb(palette.GOAL)).max() <= 2
    raster.save_plan(p, s, tmp_path / "f.png")
    assert Image.open(tmp_path / "f.png").size == (1050, 500)


def test_colours_and_seam_split_have_one_home():
    import rapp.plotting as plotting

    for name in palette.__all__:
        assert getattr(plotting, name) is getattr(palette, name)
    assert plotting.split_at_seam is rapp.paths.split_at_seam


# --------------------------------------------------------------------------- the command line


def test_cli_png_is_drawn_without_matplotlib(tmp_path):
    fig = tmp_path / "f.png"
    code = ("import sys; from rapp.cli import main; "
            f"code = main(['plan', 'default', '--plot', {str(fig)!r}, '-q']); "
            "print(code, 'matplotlib' in sys.modules)")
    env = {k: v for k, v in os.environ.items() if k != "MPLBACKEND"}
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                       cwd=tmp_path, env=env)
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines()[-1] == "0 False", r.stdout
    with Image.open(fig) as image:
        image.verify()
    with Image.open(fig) as image:
        assert image.format == "PNG" and image.size == (1050, 500)
    assert sorted(os.listdir(tmp_path)) == ["f.png"]  # no temporary file left


def test_python_m_rapp_plot_png(tmp_path):
    r = subprocess.run([sys.executable, "-m", "rapp", "plan", "default", "--plot", "f.png", "-q"],
                       capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert r.returncode == 0 and r.stderr == "", r.stderr
    with Image.open(tmp_path / "f.png") as image:
        assert image.size == (1050, 500)
