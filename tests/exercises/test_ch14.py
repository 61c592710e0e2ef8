"""Chapter 14's exercises: the model solutions pass, plausible wrong answers fail usefully."""

import numpy as np

import rapp
from rapp.exercises import check


def test_14_1_all_successes(book_exercises, solution):
    assert check("14.1", 35) and check("14.1", solution("14.1")["answer"])
    assert "$n = 35$" in book_exercises["14.1"]["solution"]
    assert "width 0" in check("14.1", 1).message                     # the textbook (Wald) interval
    assert "rule of three" in check("14.1", 30).message
    assert "z = 1.645" in check("14.1", 25).message
    assert "rounds z to 2" in check("14.1", 37).message
    assert "still below 0.9" in check("14.1", 34).message
    assert "whole number" in check("14.1", 34.6).message


def _wrap(d):
    return (np.asarray(d, dtype=float) + np.pi) % (2 * np.pi) - np.pi


def test_14_2_model_choose_parent_passes_and_slips_fail(solution):
    assert check("14.2", solution("14.2")["choose_parent"])

    def nearest(arm, near, costs, q_new, obstacles):           # RRT's parent
        d = arm.joint_delta(near, q_new)
        dist = np.linalg.norm(d, axis=1)
        i = int(np.argmin(dist))
        return (i, float(costs[i] + dist[i]))

    wrong = check("14.2", nearest)
    assert not wrong and "nearest node" in wrong.message and "case 2 of" in wrong.message

    def unchecked(arm, near, costs, q_new, obstacles):         # the collision check forgotten
        d = arm.joint_delta(near, q_new)
        through = costs + np.linalg.norm(d, axis=1)
        i = int(np.argmin(through))
        return (i, float(through[i]))

    wrong = check("14.2", unchecked)
    assert not wrong and "not certified" in wrong.message and "case 4 of" in wrong.message

    def plain(arm, near, costs, q_new, obstacles):             # the long way across the seam
        d = np.asarray(q_new) - near
        through = costs + np.linalg.norm(d, axis=1)
        order = np.argsort(through)
        free = rapp.segment_collision_free(arm, near[order], near[order] + d[order], obstacles)
        if not free.any():
            return (-1, float("inf"))
        i = int(order[np.argmax(free)])
        return (i, float(through[i]))

    wrong = check("14.2", plain)
    assert not wrong and "seam" in wrong.message and "case 3 of" in wrong.message

    def edge_only(arm, near, costs, q_new, obstacles):         # the parent's cost forgotten
        i, c = solution("14.2")["choose_parent"](arm, near, costs, q_new, obstacles)
        return (i, c - costs[i]) if i >= 0 else (i, c)

    wrong = check("14.2", edge_only)
    assert not wrong and "edge length alone" in wrong.message

    def never_none(arm, near, costs, q_new, obstacles):        # always some parent
        i, c = solution("14.2")["choose_parent"](arm, near, costs, q_new, obstacles)
        return (0, float(costs[0])) if i < 0 else (i, c)

    wrong = check("14.2", never_none)
    assert not wrong and "(-1, inf)" in wrong.message and "case 5 of" in wrong.message
    assert "pair (index, cost)" in check("14.2", lambda a, n, c, q, o: 3).message


def test_14_3_staircase(solution):
    verdict = check("14.3", solution("14.3")["answer"])
    assert verdict and "√3" in verdict.message
    flat = check("14.3", ([-1.5, -1.5, 0.0], [1.5, 1.5, 0.0]))       # the two-joint diagonal
    assert not flat and "1.65 is wanted" in flat.message
    close = check("14.3", ([0.0, 0.0, 0.0], [0.5, 0.5, 0.5]))
    assert not close and "at least 2 rad apart" in close.message
    seam = check("14.3", ([3.0, 3.0, 3.0], [-3.0, -3.0, -3.0]))      # far apart only the long way
    assert not seam and "short way round" in seam.message
    assert "3 finite joint angles" in check("14.3", ([0, 0], [1, 1])).message
    assert "pair" in check("14.3", 5).message
    # Snapping to the 24 cells can take the reported ratio above √3 (1.98 here): the message says
    # why, and never that the ratio is at most √3.
    above = check("14.3", ([-1.2] * 3, [1.2] * 3))
    assert above and "1.98" in above.message and "above √3" in above.message
    assert "above √3" not in verdict.message


def _gap(half, radius=0.25):
    cx, cy = np.cos(0.5) + 0.5, np.sin(0.5)
    return {"arm": {"link_lengths": [1.0, 1.0]}, "start": [np.pi / 2, 0.0], "goal": {"joints": [0.5, -0.5]},
            "obstacles": [{"type": "circle", "center": [round(cx, 3), round(cy + s * (radius + half), 3)],
                           "radius": radius} for s in (1, -1)]}


def test_14_4_refuted_no(solution):
    verdict = check("14.4", solution("14.4")["answer"])
    assert verdict and "RRT-Connect plans a verified path" in verdict.message
    chapter = check("14.4", (_gap(0.1), 60))                          # the chapter's own scene
    assert not chapter and "half the thinnest" in chapter.message
    wide = check("14.4", (_gap(0.1), 128))                            # 128 cells see the 0.2 m gap
    assert not wide and "finds a path" in wide.message
    impossible = check("14.4", (rapp.load_scenario("no_solution").to_dict(), 90))  # truly no path
    assert not impossible and "found none either" in impossible.message
    assert "from 2 to 200" in check("14.4", (_gap(0.07), 400)).message
    assert "does not load" in check("14.4", ({"arm": {}}, 128)).message
    assert "no obstacle" in check("14.4", (dict(_gap(0.07), obstacles=[]), 128)).message
    three = dict(_gap(0.07), arm={"link_lengths": [1.0, 0.5, 0.5]}, start=[np.pi / 2, 0.0, 0.0],
                 goal={"joints": [0.5, -0.5, 0.0]})
    assert "2-link arm" in check("14.4", (three, 128)).message
