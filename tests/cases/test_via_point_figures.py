"""rapp.cases.via_point_figures: what each figure draws (its data, labels and limits), not pixels."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from rapp import Arm, Circle  # noqa: E402
from rapp.collision import clearance  # noqa: E402
from rapp.trajectory import via_points  # noqa: E402
from rapp.cases import via_point_figures as vf  # noqa: E402
from rapp.cases.via_point_detour import path_clearance, printed_ik  # noqa: E402
from rapp.view_stack import overlays_of, selected  # noqa: E402

A, B, C = np.array([2.0, 5.0]), np.array([5.0, 8.0]), np.array([14.0, 7.0])
V_B, REST = np.array([0.25, 0.25]), np.zeros(2)
OBS, ARM = Circle((10.0, 7.0), 1.5), Arm([9.0, 9.0])
TIMES = np.array([0.0, 3.0, 5.5, 8.0])
VELS = [REST, V_B, REST, REST]
D3 = np.array([9.86, 5.32])


@pytest.fixture(autouse=True)
def _close():
    yield
    plt.close("all")


def traj(D=D3):
    return via_points(TIMES, [A, B, D, C], velocities=VELS)


def test_plot_arm_along_draws_the_tip_path_and_names_the_points():
    ax = vf.plot_arm_along(ARM, traj(), {"A": A, "B": B, "D": D3, "C": C}, [OBS])
    path = next(line for line in ax.lines if line.get_label() == "tip path")
    assert np.allclose(path.get_xydata(), traj().evaluate(np.linspace(0, 8, 801)))
    assert [t.get_text() for t in ax.texts] == list("ABDC")
    assert "arm every 0.5 s (elbow down)" in [t.get_text() for t in ax.get_legend().get_texts()]


def test_plot_xy_profiles_plots_positions_and_velocities_against_time():
    fig = vf.plot_xy_profiles(traj(), "title", TIMES)
    (x, y), (vx, vy) = np.array(fig.axes).reshape(2, 2)
    t = np.linspace(0, 8, 801)
    assert np.allclose(x.lines[0].get_ydata(), traj().evaluate(t)[:, 0])
    assert np.allclose(vy.lines[0].get_ydata(), traj().evaluate(t, 1)[:, 1])
    assert len(x.lines) == 1 + len(TIMES) and fig.get_suptitle() == "title"


def test_plot_via_choices_draws_one_path_per_via_point_and_zooms():
    vias = [("a", D3), ("b", np.array([10.2, 8.54]))]
    fig = vf.plot_via_choices((A, B, C), vias, OBS, TIMES, VELS, zoom=((9.4, 10.7), (8.2, 8.7)))
    left, right = fig.axes
    paths = [line for line in left.lines if line.get_label().startswith("cubic path")]
    assert [p.get_label() for p in paths] == ["cubic path, a", "cubic path, b"]
    assert np.allclose(paths[1].get_xydata()[-1], C)
    assert np.allclose(right.get_xlim(), (9.4, 10.7)) and np.allclose(right.get_ylim(), (8.2, 8.7))


def test_plot_formula_vs_atan2_draws_both_solutions_and_the_target():
    cases = {"x < 0": ((1.0, 1.0), np.array([-1.0, 0.5]))}
    (ax,) = vf.plot_formula_vs_atan2(cases).axes
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["atan2 form (rapp.ik_2link)", "eqs. 36–37 (arctan, arcsin)", "target"]
    star = next(line for line in ax.lines if line.get_label() == "target")
    assert np.allclose(star.get_xydata(), [[-1.0, 0.5]])


def test_plot_postures_draws_the_marks_the_path_and_the_title():
    ax = vf.plot_postures(ARM, [(printed_ik(C, 1), "down"), (printed_ik(C, -1), "up")], [OBS],
                          marks=([A, B, C], "ABC"), path=np.zeros((4, 2)), title="T")
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels[:2] == ["down", "up"] and "ABC" in labels and "path" in labels
    assert ax.get_title() == "T" and np.allclose(ax.get_xlim(), vf.SCENE_LIMITS[0])


def test_closest_approach_animation_zooms_on_the_smallest_clearance():
    frames = np.linspace(0.0, 8.0, 9)
    anim = vf.closest_approach_animation(ARM, traj(), OBS, frames, window=0.05)
    fig = plt.gcf()
    q = printed_ik(traj().evaluate(frames), +1)
    k = int(np.argmin(clearance(ARM, q, [OBS])))
    tip = ARM.end_effector(q[k])
    az = fig.axes[1]
    assert np.allclose(np.mean(az.get_xlim()), tip[0]) and np.isclose(np.ptp(az.get_ylim()), 0.05)
    assert az.get_title() == f"zoom: closest approach at t = {frames[k]:.2f} s"
    arrow = next(a for a in az.texts if a.get_text() == "")          # the gap, tip to disc
    assert np.isclose(np.linalg.norm(np.subtract(arrow.xy, tip)), np.linalg.norm(tip - OBS.center) - OBS.radius)
    assert np.isclose(np.linalg.norm(np.subtract(arrow.xy, OBS.center)), OBS.radius)   # on the disc's edge
    assert anim is not None


def test_plot_spline_vs_cubic_plots_speed_and_acceleration_magnitudes():
    tr = traj()
    fig = vf.plot_spline_vs_cubic({"cubic": tr}, [A, B, D3, C], OBS)
    t = np.linspace(0, 8, 1601)
    assert np.allclose(fig.axes[1].lines[0].get_ydata(), np.linalg.norm(tr.evaluate(t, 1), axis=-1))
    assert np.allclose(fig.axes[2].lines[0].get_ydata(), np.linalg.norm(tr.evaluate(t, 2), axis=-1))


def test_via_point_explorer_reports_the_default_view():
    w = vf.via_point_explorer(ARM, (A, B, C), OBS, TIMES, VELS, [9.86, 10.2], [5.32], default=(9.86, 5.32))
    status = selected(w)[1]
    pc = float(path_clearance(D3, B, C, OBS.center, v_start=V_B)) - OBS.radius
    assert f"path clearance {pc:+.3f} m" in status and len(overlays_of(w).children) == 2
