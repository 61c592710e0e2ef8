"""Chapter 13's exercises: the model solutions pass, plausible wrong answers fail usefully."""

import math

import numpy as np

from rapp.exercises import check


def _ik2_variant(*, clip=True, atan2=True, strict=False):
    """The model ik2 with one slip: no clipping, atan for atan2, or a strict reachability test."""
    def ik2(L1, L2, x, y):
        r = math.hypot(x, y)
        c = (x * x + y * y - L1 * L1 - L2 * L2) / (2 * L1 * L2)
        if abs(c) > 1 + 1e-9 or (strict and not abs(L1 - L2) <= r <= L1 + L2):
            return np.full((2, 2), np.nan)
        t2 = np.arccos(np.clip(c, -1.0, 1.0) if clip else c)
        rows = []
        for q2 in (t2, -t2):
            if atan2:
                q1 = np.arctan2(y, x) - np.arctan2(L2 * np.sin(q2), L1 + L2 * np.cos(q2))
            else:
                q1 = np.arctan(y / x) - np.arctan(L2 * np.sin(q2) / (L1 + L2 * np.cos(q2)))
            rows.append((q1, q2))
        return np.array(rows)
    return ik2


def test_13_1_elbow_angles(book_exercises):
    t2 = math.acos(-0.9125)
    assert check("13.1", [t2, -t2])
    assert "2.720" in book_exercises["13.1"]["solution"]
    assert "wrong order" in check("13.1", [-t2, t2]).message
    assert "degrees" in check("13.1", np.degrees([t2, -t2])).message
    inner = math.acos(0.9125)
    assert "interior angle" in check("13.1", [inner, -inner]).message
    assert "shoulder angles" in check("13.1", [1.03404615, 2.1075465]).message
    one = check("13.1", t2)
    assert not one and "count the solutions" in one.message


def test_13_2_elbow_on_the_right(book_exercises, solution):
    answer = solution("13.2")["answer"]
    assert check("13.2", answer)
    assert check("13.2", np.asarray(answer) + [2 * np.pi, 0.0])      # modulo 2 pi
    assert "-1.053" in book_exercises["13.2"]["solution"]
    assert "elbow-down ($-$)" in book_exercises["13.2"]["solution"]
    left = check("13.2", [-2.08891992, 1.43285933])                # the other elbow
    assert not left and "on the left" in left.message
    assert "degrees" in check("13.2", np.degrees(answer)).message
    assert "not on the target" in check("13.2", [1.0, 1.0]).message
    assert "two numbers" in check("13.2", -1.43285933).message


def test_13_3_model_ik_passes_and_slips_fail(solution):
    ik2 = solution("13.3")["ik2"]
    assert check("13.3", ik2)
    assert check("13.3", _ik2_variant())
    no_clip = check("13.3", _ik2_variant(clip=False))
    assert not no_clip and "clip" in no_clip.message and "boundary circle" in no_clip.message
    strict = check("13.3", _ik2_variant(strict=True))
    assert not strict and "tolerance" in strict.message
    atan = check("13.3", _ik2_variant(atan2=False))
    assert not atan and "atan2" in atan.message and "x=-1.5" in atan.message
    swapped = check("13.3", lambda *a: ik2(*a)[::-1])
    assert not swapped and "other order" in swapped.message

    def mispaired(*a):                     # theta_2 of one elbow with theta_1 of the other
        q = ik2(*a)
        q[:, 1] *= -1
        return q
    wrong = check("13.3", mispaired)
    assert not wrong and "not on the target" in wrong.message
    numbers = check("13.3", lambda *a: np.nan_to_num(ik2(*a)))
    assert not numbers and "outside the annulus" in numbers.message
    assert "missing return" in check("13.3", lambda *a: None).message
    assert "(2, 2)" in check("13.3", lambda *a: ik2(*a)[0]).message


def test_13_4_count_solutions(solution):
    count = solution("13.4")["count_solutions"]
    assert check("13.4", count)

    def seed_count(L1, L2, x, y):          # the seed's list: 2 whenever reachable
        r = math.hypot(x, y)
        return 2 if abs(L1 - L2) - 1e-9 <= r <= L1 + L2 + 1e-9 else 0
    wrong = check("13.4", seed_count)
    assert not wrong and "boundary circle" in wrong.message and "one configuration" in wrong.message
    no_inf = check("13.4", lambda *a: 1 if count(*a) == math.inf else count(*a))
    assert not no_inf and "undercounts the base" in no_inf.message

    def strict(L1, L2, x, y):
        r = math.hypot(x, y)
        if L1 == L2 and r == 0:
            return math.inf
        if r < abs(L1 - L2) or r > L1 + L2:
            return 0
        return 1 if r in (L1 + L2, abs(L1 - L2)) else 2
    wrong = check("13.4", strict)
    assert not wrong and "small tolerance" in wrong.message
    any_base = check("13.4", lambda L1, L2, x, y: math.inf if x == y == 0 else count(L1, L2, x, y))
    assert not any_base and "L1 ≠ L2" in any_base.message
    assert "0, 1, 2 or math.inf" in check("13.4", lambda *a: True).message
    assert "0, 1, 2 or math.inf" in check("13.4", lambda *a: 3).message
