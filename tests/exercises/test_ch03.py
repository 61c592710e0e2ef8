"""Chapter 3's exercises: the model solutions pass, plausible wrong answers fail usefully."""

import numpy as np

import rapp
from rapp.exercises import check


def test_3_1_distance_to_a_link(book_exercises, solution):
    assert check("3.1", np.sqrt(2)) and check("3.1", solution("3.1")["distance"])
    assert "1.414" in book_exercises["3.1"]["solution"]
    assert "infinite line" in check("3.1", 1.0).message              # the unclipped line distance
    assert "end a" in check("3.1", np.sqrt(10)).message              # clipped to the wrong end
    assert "squared" in check("3.1", 2.0).message
    assert "clearance" in check("3.1", np.sqrt(2) - 1.2).message
    assert "clip it to [0, 1]" in check("3.1", 1.7).message                   # the hint


def _unclipped(a, b, center, radius):
    u = b - a
    t = (center - a) @ u / (u @ u)
    return bool(np.linalg.norm(a + t * u - center) <= radius)


def _strict(a, b, center, radius):
    u = b - a
    uu = u @ u
    s = 0.0 if uu == 0 else min(max((center - a) @ u / uu, 0.0), 1.0)
    return bool(np.linalg.norm(a + s * u - center) < radius)


def _clip_at_one_only(a, b, center, radius):
    u = b - a
    uu = u @ u
    s = 0.0 if uu == 0 else min((center - a) @ u / uu, 1.0)
    return bool(np.linalg.norm(a + s * u - center) <= radius)


def _no_point_segment(a, b, center, radius):
    u = b - a
    s = np.clip((center - a) @ u / (u @ u), 0.0, 1.0)   # nan for a point segment
    return bool(np.linalg.norm(a + s * u - center) <= radius)


def test_3_2_model_function_passes_and_slips_fail(solution):
    verdict = check("3.2", solution("3.2")["hits"])
    assert verdict and "all 59 test cases" in verdict.message
    assert check("3.2", lambda a, b, c, r: rapp.collision.segment_hits_circle(a, b, c, r))  # np.bool_

    wrong = check("3.2", _unclipped)
    assert not wrong and "Clip the projection parameter" in wrong.message and "beyond an end" in wrong.message
    assert "center=[3, 0.25]" in wrong.message                      # the first disc beyond the end
    wrong = check("3.2", _clip_at_one_only)
    assert not wrong and "Clip the projection parameter" in wrong.message and "center=[-1, 0.3]" in wrong.message
    wrong = check("3.2", _strict)
    assert not wrong and "touching counts" in wrong.message and "radius=0.5" in wrong.message
    with np.errstate(all="ignore"):
        wrong = check("3.2", _no_point_segment)
    assert not wrong and "single point" in wrong.message
    assert "expected True or False" in check("3.2", lambda a, b, c, r: 1.0).message
    assert "missing return" in check("3.2", lambda a, b, c, r: None).message
    assert "takes" in check("3.2", lambda a, b: True).message


def test_3_3_mis_counterexample(solution):
    verdict = check("3.3", solution("3.3")["answer"])
    assert verdict and "false collision" in verdict.message.lower()
    own = check("3.3", ((0, 0), (1, 0), (1.6, 0.1), 0.3))             # the chapter's own example
    assert not own and "your own" in own.message
    assert not check("3.3", ((1, 0), (0, 0), (1.5, 0.0), 0.3))         # the explorer's, link reversed
    assert check("3.3", ((0, 0), (2, 0), (2.6, 0.1), 0.3))             # the same idea on another link
    real = check("3.3", ((0, 0), (2, 0), (1, 0.1), 0.5))              # the MIS is right here
    assert not real and "really meets" in real.message
    far = check("3.3", ((0, 0), (2, 0), (3, 1), 0.5))                 # no collision claimed at all
    assert not far and "no collision" in far.message
    assert "same point" in check("3.3", ((1, 1), (1, 1), (3, 1), 0.5)).message
    assert "positive radius" in check("3.3", ((0, 0), (1, 0), (3, 0), -1.0)).message
    assert "expected a tuple" in check("3.3", ((0, 0), (1, 0))).message


def test_3_4_touch_the_seed_misses(solution):
    verdict = check("3.4", solution("3.4")["answer"])
    assert verdict and "gap" in verdict.message
    assert check("3.4", ((0.0, -1.0), (4.0, -1.0)))                   # along a side
    end = check("3.4", ((0.0, 0.0), (1.0, 0.0)))                       # the chapter's example
    assert not end and "an end of the link lies on the square" in end.message
    enters = check("3.4", ((0.0, 0.0), (4.0, 0.0)))                    # straight through
    assert not enters and "enters the square" in enters.message
    misses = check("3.4", ((0.0, 2.0), (4.0, 2.0)))
    assert not misses and "misses the square" in misses.message
    assert "same point" in check("3.4", ((1.0, 1.0), (1.0, 1.0))).message


def test_3_5_motion_bounds(book_exercises, solution):
    assert check("3.5", [0.1, 0.4]) and check("3.5", solution("3.5")["bounds"])
    assert "0.4" in book_exercises["3.5"]["solution"]
    assert "L1 + L2" in check("3.5", [0.1, 0.3]).message             # rho_12 taken as L2
    assert "own joint" in check("3.5", [0.1, 0.2]).message
    assert "whole arm" in check("3.5", [0.2, 0.4]).message
    assert "2 numbers" in check("3.5", 0.4).message
