"""Chapter 6's exercises: the model solutions pass, plausible wrong answers fail usefully."""

import numpy as np

import rapp
from rapp.exercises import check
from rapp.exercises.ch06 import _dls_ref, _n_link_cases, _singular_ref, _two_link_cases


def test_6_1_both_solutions(book_exercises, solution):
    right = [[0.0, np.pi / 2], [np.pi / 2, -np.pi / 2]]
    assert check("6.1", right) and check("6.1", solution("6.1")["answer"])
    assert "1.5708" in book_exercises["6.1"]["solution"]
    assert "swapped" in check("6.1", right[::-1]).message
    assert "degrees" in check("6.1", np.degrees(right)).message
    assert "wrong sign" in check("6.1", [[np.pi / 2, np.pi / 2], [0.0, -np.pi / 2]]).message
    assert "shape" in check("6.1", [0.0, np.pi / 2]).message


def test_6_2_det_j(book_exercises, solution):
    want = 0.8 * np.sin(2.0)
    assert check("6.2", want) and check("6.2", solution("6.2")["answer"])
    assert "0.7274" in book_exercises["6.2"]["solution"]
    assert "sign" in check("6.2", -want).message
    assert "degrees" in check("6.2", 0.8 * np.sin(np.radians(2.0))).message
    assert "absolute angle" in check("6.2", 0.8 * np.sin(2.4)).message
    assert "det(J Jᵀ)" in check("6.2", want**2).message
    assert "cosine" in check("6.2", 0.8 * np.cos(2.0)).message


def test_6_3_the_reference_is_the_sine_rule_and_the_package_rank():
    for L1, L2, q in _two_link_cases(np.random.default_rng(63)):
        sigma_min = np.linalg.svd(rapp.jacobian(rapp.Arm([L1, L2]), q), compute_uv=False)[-1]
        assert _singular_ref([L1, L2], q) == (abs(np.sin(q[1])) <= 1e-9)
        assert sigma_min < 1e-14 or sigma_min > 1e-6  # no case in the band a tolerance could disagree on


def test_6_3_two_link_singular(solution):
    assert check("6.3", solution("6.3")["singular"])
    exact_zero = check("6.3", lambda L1, L2, q: bool(np.sin(q[1]) == 0))
    assert not exact_zero and "folded arm" in exact_zero.message and "tolerance" in exact_zero.message
    stretched_only = check("6.3", lambda L1, L2, q: bool(abs(q[1]) < 1e-9))
    assert not stretched_only and "folded arm" in stretched_only.message
    no_wrap = check("6.3", lambda L1, L2, q: bool(min(abs(q[1]), abs(abs(q[1]) - np.pi)) < 1e-9))
    assert not no_wrap and "2 pi" in no_wrap.message
    wrong_joint = check("6.3", lambda L1, L2, q: bool(abs(np.sin(q[0])) < 1e-9))
    assert not wrong_joint and "regular configuration" in wrong_joint.message
    loose = check("6.3", lambda L1, L2, q: bool(abs(np.sin(q[1])) < 1e-2))
    assert not loose and "close to a singular one" in loose.message
    assert "True or False" in check("6.3", lambda L1, L2, q: "yes").message


def test_6_4_the_reference_is_all_links_in_line():
    for lengths, q in _n_link_cases(np.random.default_rng(64)):
        assert _singular_ref(lengths, q) == bool(np.all(np.abs(np.sin(q[1:])) <= 1e-9))


def test_6_4_n_link_singular(solution):
    assert check("6.4", solution("6.4")["singular"])
    any_joint = check("6.4", lambda L, q: bool(np.any(np.abs(np.sin(q[1:])) <= 1e-9)))
    assert not any_joint and "not all of them" in any_joint.message
    two_link_rule = check("6.4", lambda L, q: bool(abs(np.sin(q[1])) <= 1e-9))
    assert not two_link_rule and "not all of them" in two_link_rule.message
    stretched_only = check("6.4", lambda L, q: bool(np.all(np.abs(q[1:]) <= 1e-9)))
    assert not stretched_only and "one line" in stretched_only.message
    loose = check("6.4", lambda L, q: bool(np.all(np.abs(np.sin(q[1:])) <= 1e-2)))
    assert not loose and "close to a singular one" in loose.message
    two_only = check("6.4", solution("6.3")["singular"])
    assert not two_only and "takes" in two_only.message  # a 3-argument function is told its signature


def test_6_5_reference_agrees_with_the_package():
    from rapp.ik import _dls_step

    rng = np.random.default_rng(5)
    for n in range(2, 6):
        J = rapp.jacobian(rapp.Arm(rng.uniform(0.2, 1.0, n)), rng.uniform(-np.pi, np.pi, n))
        e = rng.normal(0.0, 0.3, 2)
        lam = 0.1  # the package's step with the damping always on and lambda_max = lam (|e| >= lam^2)
        pkg = _dls_step(J[0][:, None], J[1][:, None], e[:1], e[1:], 1e100, lam)[:, 0]
        assert np.allclose(_dls_ref(J, e, lam), pkg, rtol=1e-10, atol=1e-14)
        assert np.allclose(_dls_ref(J, e, 0.0), np.linalg.pinv(J) @ e, rtol=1e-10, atol=1e-14)


def test_6_5_dls_step(solution):
    assert check("6.5", solution("6.5")["dls_step"])
    lam_not_squared = check("6.5", lambda J, e, lam: J.T @ np.linalg.solve(J @ J.T + lam * np.eye(2), e))
    assert not lam_not_squared and "λ instead of λ²" in lam_not_squared.message
    undamped = check("6.5", lambda J, e, lam: np.linalg.pinv(J) @ e)
    assert not undamped and "undamped" in undamped.message
    no_transpose = check("6.5", lambda J, e, lam: J @ np.linalg.solve(J @ J.T + lam**2 * np.eye(2), e))
    assert not no_transpose and "Jᵀ in front" in no_transpose.message
    column = check("6.5", lambda J, e, lam: (J.T @ np.linalg.solve(J @ J.T + lam**2 * np.eye(2), e))[:, None])
    assert not column and "shape" in column.message
    inverse = check("6.5", lambda J, e, lam: J.T @ np.linalg.inv(J @ J.T) @ e)
    assert not inverse and "undamped" in inverse.message


def test_6_6_longest_step(book_exercises, solution):
    assert check("6.6", 1.0) and check("6.6", solution("6.6")["answer"])
    assert "0.1/0.1 = 1$ rad" in " ".join(book_exercises["6.6"]["solution"].split())
    assert "1 / (2λ)" in check("6.6", 2.0).message          # |e| / lambda
    assert "divides by λ²" in check("6.6", 40.0).message     # |e| / lambda^2
    assert "2λ²" in check("6.6", 20.0).message
    assert "not it" in check("6.6", 0.5).message
