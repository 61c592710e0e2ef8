# The two commands of the README:
#   make book   set up .venv and node_modules, build the book into _build/html, check it in Chromium
#   make test   set up .venv, run every test (unit, property, doctests, notebooks via nbval)
#   make check  the fast tier while working: every test not marked slow (no notebooks, no browser)
# Other targets: make setup, make notebooks (re-execute notebooks/*.ipynb in place), make clean,
#   make student-book (the book without solutions, into _build/student/_build/html).

SHELL := /bin/bash
.SHELLFLAGS := -eu -o pipefail -c
.DELETE_ON_ERROR:
.SUFFIXES:
MAKEFLAGS += --no-print-directory

PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
PY_STAMP := $(VENV)/.environment.stamp
NODE_STAMP := node_modules/.package-lock.json
VENDOR_STAMP := book/_static_vendor/offline/.stamp
export PIP_DISABLE_PIP_VERSION_CHECK := 1
# Byte-code caches on: pytest then keeps each test module's rewritten assertions in
# __pycache__ instead of rewriting ~200 modules in every worker of every run (~5 CPU-s each).
unexport PYTHONDONTWRITEBYTECODE
# Loaded before nbval: spares every test process jsonschema's IRI parser (tests/pytest_fast_start.py).
PYTEST_START := -p tests.pytest_fast_start
export NO_COLOR := 1

.PHONY: setup setup-python setup-js book test check notebooks clean student-book

setup: setup-python setup-js
setup-python: $(PY_STAMP)
setup-js: $(VENDOR_STAMP)

# Re-installed whenever environment.txt (pinned, ends with `-e .`) or pyproject.toml changes.
$(PY_STAMP): environment.txt pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --progress-bar off -r environment.txt
	touch $@

# MathJax 3, RequireJS and the ipywidgets HTML manager, pinned in package-lock.json.
$(NODE_STAMP): package.json package-lock.json
	npm ci --ignore-scripts --no-audit --no-fund --loglevel=error
	touch $@

# Copied into book/_static_vendor/offline/, which _config.yml serves as static files.
$(VENDOR_STAMP): $(NODE_STAMP) $(PY_STAMP) scripts/vendor_js.py
	$(PY) scripts/vendor_js.py
	touch $@

book: setup
	$(VENV)/bin/jupyter-book build . --all --quiet --warningiserror --nitpick --keep-going
	$(PY) scripts/check_book.py _build/html

# The student edition: the same book with sphinx-exercise's hide_solutions on (the exercises stay,
# numbered the same), then a check that no page holds a solution's text.
student-book: setup
	$(PY) scripts/student_book_config.py _build/student_config.yml
	$(VENV)/bin/jupyter-book build . --all --quiet --config _build/student_config.yml --path-output _build/student
	$(PY) scripts/check_student_book.py _build/student/_build/html

test: setup-python
	$(PY) -m pytest $(PYTEST_START)

check: setup-python
	$(PY) -m pytest $(PYTEST_START) -m "not slow"

notebooks: setup-python
	$(PY) scripts/execute_notebooks.py

clean:
	rm -rf _build book/_static_vendor
