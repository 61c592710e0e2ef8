"""rapp.plotting.plot_torus: the 2-link C-space drawn on a torus."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import rapp  # noqa: E402
from rapp.plotting import plot_torus  # noqa: E402


@pytest.fixture
def scene():
    arm = rapp.Arm([1.0, 1.0])
    grid = rapp.JointGrid(arm, (20, 16))
    occ = rapp.occupancy(arm, [rapp.Circle((1.5, 0.5), 0.45)], grid)
    yield grid, occ
    plt.close("all")


def test_one_patch_per_cell_grey_where_occupied(scene):
    grid, occ = scene
    ax = plot_torus(occ, grid)
    surf = ax.collections[0]
    colors = surf.get_facecolor()
    assert len(colors) == occ.size
    # Two clearly separated tones (matplotlib may reorder the faces, so they are counted).
    lum = np.sort(colors[:, :3].mean(axis=1))
    k = int(occ.sum())
    assert 0 < k < occ.size and lum[k - 1] + 0.2 < lum[k]


def test_path_lies_on_the_torus_and_crosses_the_seam_unbroken(scene):
    grid, occ = scene
    path = np.array([[3.0, 0.2], [-3.0, 0.2], [-2.5, -0.4]])  # crosses theta1 = +-pi
    ax = plot_torus(occ, grid, path=path, major=2.0, minor=0.9, elev=90.0, azim=0.0)
    line = next(ln for ln in ax.lines if ln.get_label() == "path")
    x, y, z = (np.asarray(c, float) for c in line.get_data_3d())
    ok = np.isfinite(x)
    rho = np.hypot(x[ok], y[ok])
    assert np.allclose((rho - 2.0) ** 2 + z[ok] ** 2, (0.9 * 1.04) ** 2)
    # Consecutive drawn points stay close: the seam crossing is a short step, not a jump across.
    step = np.sqrt(np.diff(x) ** 2 + np.diff(y) ** 2 + np.diff(z) ** 2)
    assert np.nanmax(step) < 0.5


def test_refuses_a_bounded_axis_and_a_wrong_shape():
    arm = rapp.Arm([1.0, 1.0], [None, (-1.0, 1.0)])
    grid = rapp.JointGrid(arm, 10)
    with pytest.raises(ValueError, match="wrap"):
        plot_torus(np.zeros((10, 10), bool), grid)
    with pytest.raises(ValueError, match="shape"):
        plot_torus(np.zeros((4, 4), bool), rapp.JointGrid(rapp.Arm([1.0, 1.0]), 10))
