"""Chapter 12's exercises: the model solutions pass, plausible wrong answers fail usefully."""

import numpy as np

import rapp
from rapp.cases import rrt_report as s3
from rapp.exercises import check


def _wrap(d):
    return (np.asarray(d, dtype=float) + np.pi) % (2 * np.pi) - np.pi


def test_12_1_jacobian_upright(book_exercises):
    J = np.array([1.5, 1.0, 0.5])
    assert check("12.1", J) and check("12.1", J.tolist())
    assert "[1.5, 1.0, 0.5]" in book_exercises["12.1"]["solution"]
    printed = check("12.1", -J)                                      # the report's matrix
    assert not printed and "every sign" in printed.message
    assert "shape (3,)" in check("12.1", np.array([J, 0 * J])).message
    assert "not it" in check("12.1", np.ones(3)).message


def test_12_2_separating_gap(book_exercises):
    u = np.array([np.cos(0.3), np.sin(0.3)])
    gap = 1.2 * u[0] + 0.6 * u[1] - 1.0
    assert check("12.2", gap) and check("12.2", 0.324)
    assert "0.324" in book_exercises["12.2"]["solution"]
    assert "far end" in check("12.2", 1.6 * u[0] + 1.4 * u[1] - 1.0).message
    assert "other edge direction" in check("12.2", -1.2 * u[1] + 0.6 * u[0] - 1.0).message
    assert "degrees" in check("12.2", 1.2 * np.cos(np.radians(0.3)) + 0.6 * np.sin(np.radians(0.3)) - 1.0).message
    assert "x axis" in check("12.2", 1.2 - np.cos(0.3)).message


def test_12_3_wrap_distance(book_exercises):
    qa, qb = np.array([2.9, -3.0, 3.0]), np.array([-2.8, 2.7, -3.1])
    d = qb - qa
    right = np.linalg.norm([_wrap(d[0]), _wrap(d[1]), d[2]])
    assert check("12.3", right) and check("12.3", 6.156)
    assert "6.156" in book_exercises["12.3"]["solution"]
    plain = check("12.3", np.linalg.norm(d))
    assert not plain and "plain Euclidean" in plain.message
    assert "limited joint" in check("12.3", np.linalg.norm(_wrap(d))).message
    assert "absolute differences" in check("12.3", abs(_wrap(d[0])) + abs(_wrap(d[1])) + abs(d[2])).message
    assert "squared" in check("12.3", right**2).message


def test_12_4_model_steer_passes_and_slips_fail(solution):
    assert check("12.4", solution("12.4")["steer"])

    def no_wrap(q_near, q_rand, step):
        d = np.asarray(q_rand) - q_near
        n = np.linalg.norm(d)
        return np.asarray(q_rand, float) if n <= step else q_near + step * d / n

    wrong = check("12.4", no_wrap)
    assert not wrong and "long way" in wrong.message and "seam" in wrong.message
    assert "case 3 of" in wrong.message                               # the first case across the seam

    def no_clip(q_near, q_rand, step):
        d = _wrap(np.asarray(q_rand) - q_near)
        return q_near + step * d / np.linalg.norm(d)

    wrong = check("12.4", no_clip)
    assert not wrong and "overshoots" in wrong.message and "case 2 of" in wrong.message

    def no_norm(q_near, q_rand, step):
        return q_near + step * _wrap(np.asarray(q_rand) - q_near)

    wrong = check("12.4", no_norm)
    assert not wrong and "step × d" in wrong.message and "case 1 of" in wrong.message

    def jumps(q_near, q_rand, step):
        return np.asarray(q_rand, float)

    assert "all the way" in check("12.4", jumps).message

    def divides_by_zero(q_near, q_rand, step):
        d = _wrap(np.asarray(q_rand) - q_near)
        with np.errstate(invalid="ignore", divide="ignore"):
            return q_near + min(1.0, step / np.linalg.norm(d)) * d * np.linalg.norm(d) / np.linalg.norm(d)

    wrong = check("12.4", divides_by_zero)
    assert not wrong and "q_rand is q_near" in wrong.message

    def half_step(q_near, q_rand, step):
        d = _wrap(np.asarray(q_rand) - q_near)
        return q_near + min(1.0, 0.5 * step / np.linalg.norm(d)) * d

    assert "not as far" in check("12.4", half_step).message
    assert "3 joint angles" in check("12.4", lambda a, b, s: np.zeros(2)).message


def test_12_5_node_test_counterexample(solution):
    verdict = check("12.5", solution("12.5")["answer"])
    assert verdict and "node test accepts" in verdict.message
    start, goal = s3.report_to_rapp(s3.START_THETA), s3.report_to_rapp(s3.GOAL_THETA)
    far = check("12.5", (start, goal))                                # the report's jump: too long here
    assert not far and "apart" in far.message
    free_edge = check("12.5", (start, start + [0.1, 0.0, 0.0]))
    assert not free_edge and "no counterexample" in free_edge.message
    upright = s3.report_to_rapp([0.0, 0.0, 0.0])
    hits = check("12.5", (upright, upright + [0.2, 0.0, 0.0]))
    assert not hits and "q_a collides" in hits.message
    report_angles = check("12.5", ([0.25, 0.0, 0.0], [-0.25, 0.0, 0.0]))  # not converted
    assert not report_angles and "joint limits" in report_angles.message
    assert "pair" in check("12.5", 3).message


def test_12_6_fraction_rule(book_exercises):
    assert check("12.6", 8)
    assert "= 8" in book_exercises["12.6"]["solution"]
    assert "still above" in check("12.6", 7).message
    assert "fixed step" in check("12.6", 4).message
    assert "not an iteration" in check("12.6", 9).message
    assert "whole number" in check("12.6", 7.64).message


def test_12_7_goal_bias_scene(solution):
    verdict = check("12.7", solution("12.7")["answer"])
    assert verdict and "β = 0.1 goes round" in verdict.message
    off_line = check("12.7", [rapp.Circle((0.0, -1.5), 0.2)])
    assert not off_line and "Block it" in off_line.message
    at_start = check("12.7", [rapp.Circle((1.5, 0.0), 0.2)])
    assert not at_start and "the start collides" in at_start.message
    # Discs on the elbow's circle on both sides: every way from start to goal is blocked.
    walls = [rapp.Circle((np.cos(a), np.sin(a)), 0.3) for a in (1.0, 1.0 - np.pi)]
    sealed = check("12.7", walls)
    assert not sealed and "way round" in sealed.message
    assert "1 to 6 obstacles" in check("12.7", [(1.0, 2.0)]).message
    assert "1 to 6 obstacles" in check("12.7", []).message
