"""The page check's count of typeset math (scripts/check_book.py), with math typeset lazily."""

from __future__ import annotations

import yaml
from bs4 import BeautifulSoup

from tests.helpers import ROOT, load_script

check_book = load_script("scripts/check_book.py")

TYPESET = '<span class="math"><mjx-container jax="CHTML"><mjx-math></mjx-math></mjx-container></span>'
# What MathJax's lazy extension leaves until the formula comes into view (or rapp.js's idle pass).
WAITING = ('<span class="math"><mjx-container><mjx-lazy data-mjx-lazy="3"></mjx-lazy>'
           '<mjx-assistive-mml><math></math></mjx-assistive-mml></mjx-container></span>')
RAW = '<div class="math notranslate">\\[x^2\\]</div>'


def test_a_formula_waiting_in_a_lazy_placeholder_counts_as_not_typeset():
    assert check_book.count_math(BeautifulSoup(TYPESET, "html.parser")) == (1, 0)
    assert check_book.count_math(BeautifulSoup(WAITING, "html.parser")) == (1, 1)
    assert check_book.count_math(BeautifulSoup(TYPESET + WAITING + RAW, "html.parser")) == (3, 2)


def test_the_book_typesets_math_as_it_comes_into_view():
    config = yaml.safe_load((ROOT / "_config.yml").read_text())["sphinx"]["config"]
    assert config["mathjax3_config"]["loader"]["load"] == ["ui/lazy"]
    assert config["mathjax_path"] == "offline/mathjax/tex-chtml.js"
