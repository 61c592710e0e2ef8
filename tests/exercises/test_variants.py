"""Per-student numbers: a key and a student id give a sheet, and grade judges each on their own numbers."""

import csv
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from rapp.exercises import catalog, check, variants
from rapp.exercises.core import TOLERANCE_COUNT

ROOT = Path(__file__).resolve().parents[2]
IDS = sorted(variants.VARIANTS, key=lambda i: tuple(map(int, i.split("."))))


def test_chapters_1_to_8_have_variants_for_their_numeric_exercises():
    numeric = {ex.id for ex in catalog() if ex.kind == "numeric" and ex.chapter <= 8}
    # Chapter 7's numbers come from planning runs on its scenarios or are an exit code; 1.1 has one answer.
    # 4.4: the benchmark grid; 4.6, 5.6: read off the live explorer, which shows the book's scenario.
    assert numeric - set(IDS) == {"1.1", "4.4", "4.6", "5.6", "7.1", "7.3", "7.5"}
    assert {int(i.split(".")[0]) for i in IDS} == {1, 2, 3, 4, 5, 6, 8}


@pytest.mark.parametrize("ex_id", IDS)
def test_each_student_is_judged_on_their_own_numbers(ex_id):
    codes = [variants.code("a long instructor secret", f"student{i}") for i in range(12)]
    answers = [np.asarray(variants.VARIANTS[ex_id].expected(variants.params(ex_id, c)), float) for c in codes]
    for c, a in zip(codes, answers):
        assert check(ex_id, a, variant=c), (ex_id, c)
        rounded = a if variants.VARIANTS[ex_id].exact_integer else np.round(a, 4)
        assert check(ex_id, rounded, variant=c)
    distinct = {tuple(np.round(np.ravel(a), 6)) for a in answers}
    assert len(distinct) >= 6, ex_id  # a neighbour's answer is (nearly always) not yours
    copied = sum(bool(check(ex_id, answers[0], variant=c)) for c in codes[1:])
    assert copied <= 4, ex_id
    # Without a code: the book's numbers, as before.
    book = next(ex for ex in catalog() if ex.id == ex_id)
    assert check(ex_id, book.judge.expected())


def test_codes_come_from_the_key_and_the_student():
    assert variants.code("k1" * 8, "ann") != variants.code("k2" * 8, "ann")
    assert variants.code("k1" * 8, "ann") == variants.code("k1" * 8, " ann ")
    assert "no per-student numbers" in check("5.2", None, variant="abc").message


@pytest.mark.slow
def test_assign_writes_sheets_and_grade_uses_the_same_key(tmp_path):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    roster = tmp_path / "roster.txt"
    roster.write_text("ann\nben\n")
    key = tmp_path / "key.txt"
    run = lambda *a: subprocess.run([sys.executable, "-m", "rapp", *a], capture_output=True, text=True,  # noqa: E731
                                    env=env, cwd=tmp_path, timeout=300)
    out = run("assign", "--key", str(key), "--roster", str(roster), "--exercises", "1.3,5.1,5.2", "--out", "sheets")
    assert out.returncode == 0, out.stderr
    assert key.exists() and oct(key.stat().st_mode & 0o777) == "0o600"
    secret = key.read_text().strip()
    sheet = (tmp_path / "sheets" / "ann.md").read_text()
    c = variants.code(secret, "ann")
    assert c in sheet and variants.statement("1.3", c) in sheet and "As in the book" in sheet
    # ann answers with her numbers; ben copies ann's answers.
    mine = {i: variants.VARIANTS[i].expected(variants.params(i, c)) for i in ("1.3", "5.1")}
    subs = tmp_path / "subs"
    subs.mkdir()
    text = f"answers = {{'1.3': {float(mine['1.3'])!r}, '5.1': {int(mine['5.1'])}}}\n"
    (subs / "ann.py").write_text(text)
    (subs / "ben.py").write_text(text)
    out = run("grade", str(subs), "--exercises", "1.3,5.1", "--key", str(key), "--out", "g.csv")
    assert out.returncode == 0, out.stderr
    rows = {(r["student"], r["exercise"]): r["verdict"] for r in csv.DictReader((tmp_path / "g.csv").open())}
    assert rows[("ann", "1.3")] == rows[("ann", "5.1")] == "correct"
    assert [rows[("ben", "1.3")], rows[("ben", "5.1")]].count("wrong") >= 1
    bad = run("assign", "--key", str(tmp_path / "short.txt"), "--roster", str(roster), "--exercises", "9.9")
    assert bad.returncode == 2 and len(bad.stderr.strip().splitlines()) == 1
