"""rapp.cases.two_dof_figures: what each figure draws (its data, labels and limits), not pixels."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from rapp import Arm  # noqa: E402
from rapp.ik import ik_2link  # noqa: E402
from rapp.cases import two_dof_figures as tf  # noqa: E402
from rapp.cases.two_dof_workspace import reachable  # noqa: E402

ARM = Arm([2.0, 1.25])
TARGETS = np.array([[2.0, 1.0], [-1.5, 1.8], [0.3, -0.2], [0.0, 3.25]])


@pytest.fixture(autouse=True)
def _close():
    yield
    plt.close("all")


def test_plot_targets_splits_reachable_and_unreachable():
    flags = reachable(ARM, TARGETS)
    ax = tf.plot_targets(plt.figure().add_subplot(), TARGETS, flags)
    ok, bad = ax.collections
    assert np.allclose(ok.get_offsets(), TARGETS[flags]) and np.allclose(bad.get_offsets(), TARGETS[~flags])
    assert [t.get_text() for t in ax.texts] == ["0", "1", "2", "3"]


def test_plot_all_solutions_draws_both_elbows_of_the_reachable_targets():
    flags = reachable(ARM, TARGETS)
    ax = tf.plot_all_solutions(ARM, TARGETS, flags, ik_2link(ARM, TARGETS))
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels[-4:] == [r"elbow-down, $\theta_2 \geq 0$", r"elbow-up, $\theta_2 \leq 0$",
                      "reachable target", "unreachable target"]
    assert ax.get_title() == "every solution of four targets, arm L = (2, 1.25) m"


def test_plot_target_map_names_the_targets_in_the_title():
    ax = tf.plot_target_map(ARM, TARGETS, reachable(ARM, TARGETS))
    assert ax.get_title() == "targets 0-3 in the workspace of L = (2, 1.25) m"
    assert np.allclose(ax.get_xlim(), (-3.8, 3.8))


def test_plot_fan_marks_every_elbow():
    twin = Arm([1.0, 1.0])
    fan = np.stack((np.linspace(-np.pi, np.pi, 9)[:-1], np.full(8, np.pi)), axis=-1)
    ax = tf.plot_fan(twin, fan)
    assert np.allclose(ax.collections[-1].get_offsets(), twin.joint_positions(fan)[:, 1])
    assert r"$\theta_2 = \pi$, eight $\theta_1$" in [t.get_text() for t in ax.get_legend().get_texts()]


def test_plot_elbow_pairs_one_panel_per_target_with_the_base_line():
    fig = tf.plot_elbow_pairs(ARM, [TARGETS[0], np.array([2.5, 0.0])])
    assert [ax.get_title() for ax in fig.axes] == ["target (2, 1) m", "target (2.5, 0) m"]
    line = next(ln for ln in fig.axes[1].lines if ln.get_label() == "base to target")
    assert np.allclose(line.get_xydata(), [[0, 0], [3.25, 0]])


def test_plot_joint_interpolation_in_degrees():
    short = np.linspace([0.0, 0.0], [-1.0, 0.5], 5)
    long = np.linspace([0.0, 0.0], [5.0, 0.5], 5)
    ax = tf.plot_joint_interpolation(short, long)
    assert np.allclose(ax.lines[0].get_ydata(), np.degrees(short[:, 0]))
    assert np.allclose(ax.lines[1].get_ydata(), np.degrees(long[:, 0]))
    assert np.allclose(ax.lines[2].get_ydata(), np.degrees(short[:, 1]))


def test_targets_animation_has_a_frame_per_sample():
    motion = np.linspace([0.0, 0.5], [1.0, 1.5], 6)
    anim = tf.targets_animation(ARM, motion, TARGETS, reachable(ARM, TARGETS))
    ax = plt.gcf().axes[0]
    assert np.allclose(ax.get_xlim(), (-3.8, 3.8)) and len(ax.collections) >= 2
    assert len(list(anim.new_frame_seq())) == 6
