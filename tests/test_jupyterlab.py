"""JupyterLab as a student uses it: open a chapter, read it as the book numbers it, Run All.

One JupyterLab server for the module (on a free local port, serving a copy of the notebooks and
book pages, so nothing in the checkout changes), driven by playwright through the system
Chromium. The checks:

- chapters 5, 6 and 14, opened without running a cell, read as the HTML book does: exercises,
  pseudocode, figure captions and equations carry the book's numbers N.1, N.2, … (the front
  matter of scripts/number_notebooks.py); every cross-reference resolves to something on the
  page, no raw ``{role}`` or ``:::{directive}`` is left, every link to another chapter names a
  file that exists, solutions stay folded, and the book's MyST logs no error to the console;
- chapter 1 after Run All: no error output, the reader's check cells answered, and its explorer
  shows its figure, every time (it once came back blank in 6 runs of 11); a slider moved with the
  keyboard changes that figure. One chapter is run: Run All is what costs time here, and the
  numbering above needs no kernel.

The expected numbers come from the notebooks themselves (directive order, figure metadata) and
from ``rapp.exercises.catalog()``, not from the script under test.
Skipped, with the reason, where Chromium or playwright is missing; CI installs Chromium.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import socket
import subprocess
import sys
import time
from pathlib import Path
from urllib.parse import unquote

import nbformat
import pytest
import yaml

import rapp

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = ROOT / "notebooks"
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")

playwright = pytest.importorskip("playwright.sync_api", reason="playwright is not installed")
pytestmark = [pytest.mark.slow,
              pytest.mark.skipif(CHROMIUM is None, reason="no chromium on PATH (apt-get install chromium)")]

TOKEN = "rapp-test"
ERRORS = '[data-mime-type="application/vnd.jupyter.error"]'
PANEL = ".jp-NotebookPanel:not(.lm-mod-hidden)"


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _settings(folder: Path) -> None:
    """Lab settings for a test: every cell rendered (no windowing), no news pop-up."""
    for plugin, values in {
        "notebook-extension/tracker": {"windowingMode": "none"},
        "apputils-extension/notification": {"fetchNews": "false"},
    }.items():
        path = folder / "@jupyterlab" / f"{plugin}.jupyterlab-settings"
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(values))


@pytest.fixture(scope="module")
def lab(tmp_path_factory):
    """A page of one JupyterLab server serving a copy of notebooks/ and book/ (for their links)."""
    root = tmp_path_factory.mktemp("lab")
    shutil.copytree(NOTEBOOKS, root / "notebooks", ignore=shutil.ignore_patterns(".ipynb_checkpoints"))
    shutil.copytree(ROOT / "book", root / "book", ignore=shutil.ignore_patterns("_static*", "_ext"))
    _settings(root / ".settings")
    env = dict(os.environ, JUPYTERLAB_SETTINGS_DIR=str(root / ".settings"),
               JUPYTERLAB_WORKSPACES_DIR=str(root / ".workspaces"))
    port = _free_port()
    jupyter = Path(sys.executable).with_name("jupyter")
    server = subprocess.Popen(
        [str(jupyter), "lab", "--no-browser", "--allow-root", f"--port={port}",
         "--ServerApp.ip=127.0.0.1", f"--ServerApp.root_dir={root}",
         f"--IdentityProvider.token={TOKEN}"],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    try:
        with playwright.sync_playwright() as pw:
            browser = pw.chromium.launch(executable_path=CHROMIUM,
                                         args=["--no-sandbox", "--disable-gpu"])
            page = browser.new_page(viewport={"width": 1300, "height": 900})
            page.set_default_timeout(120_000)
            console: list[str] = []
            page.on("console", lambda m: console.append(m.text) if m.type == "error" else None)
            deadline = time.monotonic() + 60
            while True:
                try:
                    page.goto(f"http://127.0.0.1:{port}/lab?token={TOKEN}")
                    break
                except playwright.Error:
                    if time.monotonic() > deadline or server.poll() is not None:
                        raise
                    time.sleep(0.5)
            yield page, port, root, console
            browser.close()
    finally:
        server.terminate()
        server.wait(30)


def _open(page, port, name: str) -> None:
    # reset: a fresh workspace, so no tab of an earlier test is restored beside this one.
    page.goto(f"http://127.0.0.1:{port}/lab/tree/notebooks/{name}?token={TOKEN}&reset")
    page.wait_for_selector(f"{PANEL} .jp-Notebook .jp-MarkdownCell .myst")


def _kernel_idle(page) -> None:
    page.wait_for_function("""() => [...document.querySelectorAll('.jp-StatusBar-TextItem')]
        .some(e => /\\|\\s*Idle/.test(e.textContent))""")


def _open_and_run_all(page, port, name: str) -> None:
    _open(page, port, name)
    _kernel_idle(page)
    _run_all(page)


def _run_all(page) -> None:
    for attempt in range(3):
        page.click('.lm-MenuBar-itemLabel:text-is("Run")')
        page.click('.lm-Menu-itemLabel:text-is("Run All Cells")')
        try:  # started: the first code cell is queued, running or done
            page.wait_for_function("""() => { const p = document.querySelector('.jp-CodeCell .jp-InputPrompt');
                return p && !/^\\[ \\]/.test(p.textContent.trim()); }""", timeout=15_000)
            break
        except playwright.Error:  # a Run All sent before the kernel listened: send it again
            continue
    # Done when every code cell shows an execution count (none queued "[*]" or unrun "[ ]").
    try:
        page.wait_for_function("""() => {
            const p = [...document.querySelectorAll('.jp-CodeCell .jp-InputPrompt')]
                .map(e => e.textContent.trim());
            return p.length > 0 && p.every(t => /^\\[\\d+\\]:?$/.test(t));
        }""", timeout=90_000)
    except playwright.Error:
        prompts = page.evaluate("[...document.querySelectorAll('.jp-CodeCell .jp-InputPrompt')]"
                                ".map(e => e.textContent.trim())")
        errors = page.locator(ERRORS).all_inner_texts()
        raise AssertionError(f"Run All did not finish: prompts {prompts}; errors {errors}") from None
    _kernel_idle(page)


# --- what the book shows for a chapter, read from the notebook itself -----------------------------

def chapter_pages(name: str) -> tuple[int, list[str]]:
    """The chapter a notebook belongs to and its pages in reading order (a chapter's
    ``sections`` in the toc are its later pages)."""
    toc = yaml.safe_load((ROOT / "_toc.yml").read_text(encoding="utf-8"))
    chapters = [c for p in toc["parts"] if p.get("numbered") for c in p["chapters"]]

    def pages(entry):
        return [entry["file"]] + [f for s in entry.get("sections", []) for f in pages(s)]

    for number, chapter in enumerate(chapters, 1):
        files = pages(chapter)
        if f"notebooks/{Path(name).stem}" in files:
            return number, [Path(f).name + ".ipynb" for f in files]
    raise ValueError(f"{name} is not a chapter page of the toc")


def _page(name: str) -> dict:
    """What one page holds, read from its notebook: exercise and algorithm titles, figure
    captions, labelled equations and labels, in order."""
    nb = nbformat.read(NOTEBOOKS / name, as_version=4)
    cells = [c for c in nb.cells if not c.metadata.get("rapp", {}).get("frontmatter")]
    text = "\n\n".join(c.source for c in cells if c.cell_type == "markdown")
    return {
        "exercise_titles": re.findall(r"^(?:`{3,}|:{3,})\{exercise\}[ \t]*(.+)$", text, re.M),
        "algorithms": re.findall(r"^(?:`{3,}|:{3,})\{prf:algorithm\}[ \t]*(.+)$", text, re.M),
        "figures": [c.metadata["mystnb"]["figure"]["caption"] for c in cells
                    if c.cell_type == "code" and "figure" in c.metadata.get("mystnb", {})],
        "equations": len(re.findall(r"\$\$[ \t]*\([\w.:-]+\)", text)),
        "labels": set(re.findall(r"^\(([\w.:-]+)\)=", text, re.M))
        | set(re.findall(r"^\s*:label:\s*(\S+)", text, re.M))
        | set(re.findall(r"\$\$[ \t]*\(([\w.:-]+)\)", text))
        | {c.metadata["mystnb"]["figure"].get("name") for c in cells
           if c.cell_type == "code" and "figure" in c.metadata.get("mystnb", {})},
    }


def expected(name: str) -> dict:
    """The page's exercises, algorithms, figures and equations with the numbers the book gives
    them: counted per chapter, so a later page continues from the pages before it."""
    n, pages = chapter_pages(name)
    here = _page(name)
    before = [_page(p) for p in pages[:pages.index(name)]]
    skip = {k: sum(len(b[k]) for b in before) for k in ("exercise_titles", "algorithms", "figures")}
    skip["equations"] = sum(b["equations"] for b in before)
    exercises = [f"Exercise {n}.{skip['exercise_titles'] + k}"
                 for k in range(1, len(here["exercise_titles"]) + 1)]
    catalog = {f"Exercise {e.id}" for e in rapp.exercises.catalog() if e.chapter == n}
    assert set(exercises) <= catalog, (exercises, catalog)
    return dict(here, n=n, exercises=exercises, skip=skip)


READ_PAGE = """() => {
    const nb = document.querySelector('%s .jp-Notebook');
    const texts = s => [...nb.querySelectorAll(s)].map(e => e.textContent.replace(/\\s+/g, ' ').trim());
    const ids = new Set([...nb.querySelectorAll('[id]')].map(e => e.id));
    return {
        exercises: texts('aside.myst-exercise .myst-exercise-title'),
        equations: texts('a[title="Link to this Equation"]'),
        algorithms: texts('.myst-proof > div:first-child'),
        captions: texts('figcaption'),
        unresolved: texts('.text-yellow-600'),
        dangling: [...nb.querySelectorAll('a[href^="#"]')].map(a => decodeURIComponent(a.getAttribute('href').slice(1)))
            .filter(id => id && !ids.has(id)),
        files: [...nb.querySelectorAll('.jp-MarkdownCell a[href*="/files/"]')].map(a => a.getAttribute('href')),
        open: [...nb.querySelectorAll('details.myst-exercise')].filter(d => d.open).length,
        solutions: nb.querySelectorAll('details.myst-exercise').length,
        text: nb.innerText,
    };
}""" % PANEL


@pytest.mark.parametrize("name", ["05_astar.ipynb", "05_astar_variants.ipynb", "06_inverse_kinematics.ipynb",
                                  "14_completeness.ipynb"])
def test_chapter_reads_as_the_book_numbers_it_without_running(lab, name):
    page, port, root, console = lab
    want = expected(name)
    n = want["n"]
    console.clear()
    _open(page, port, name)
    # Cells render one by one, and jupyterlab-myst numbers the notebook again after each: wait
    # until every exercise box and figure caption is there, then read.
    try:
        # ... and the page's last algorithm: a page without exercises is otherwise read too soon.
        skip = want["skip"]["algorithms"] + len(want["algorithms"])
        last_alg = f"Algorithm {n}.{skip} " if want["algorithms"] else ""
        page.wait_for_function("""([n, ex, fig, lastAlg]) => {
            const nb = document.querySelector('%s .jp-Notebook');
            const titles = [...nb.querySelectorAll('aside.myst-exercise .myst-exercise-title')];
            const algs = [...nb.querySelectorAll('.myst-proof > div:first-child')]
                .map(e => e.textContent.replace(/\\s+/g, ' ').trim());
            return titles.length === ex && titles.every(t => t.textContent.startsWith(`Exercise ${n}.`))
                && nb.querySelectorAll('figcaption').length >= fig
                && (!lastAlg || algs.some(a => a.startsWith(lastAlg)));
        }""" % PANEL, arg=[n, len(want["exercises"]), len(want["figures"]), last_alg], timeout=60_000)
    except playwright.Error:
        pass  # read what is there: the assertions below say what is missing
    page.wait_for_timeout(300)
    seen = page.evaluate(READ_PAGE)

    # Exercises: "Exercise 5.2 (Implement GD1)" is rapp.exercises.check("5.2", ...).
    assert [e.split(" (")[0] for e in seen["exercises"]] == want["exercises"]
    for shown, title in zip(seen["exercises"], want["exercise_titles"], strict=True):
        assert re.split(r"[$`]", title)[0].strip() in shown
    # Pseudocode: this chapter's in order, numbered N.1, N.2, ...; others keep their own chapter.
    # (The folded index also shows the chapter's targets on its other pages, numbered as there.)
    own = range(want["skip"]["algorithms"] + 1, want["skip"]["algorithms"] + len(want["algorithms"]) + 1)
    mine = [a for a in seen["algorithms"]
            if any(a.startswith(f"Algorithm {n}.{k} ") for k in own)]
    assert mine == [f"Algorithm {n}.{k} ({t})"
                    for k, t in enumerate(want["algorithms"], want["skip"]["algorithms"] + 1)]
    assert all(re.match(r"Algorithm \d+\.\d+ \(", a) for a in seen["algorithms"])
    # Figures made by code cells: a numbered caption each, the caption of the book.
    own = range(want["skip"]["figures"] + 1, want["skip"]["figures"] + len(want["figures"]) + 1)
    mine = [c for c in seen["captions"] if any(c.startswith(f"Figure {n}.{k}:") for k in own)]
    assert len(mine) == len(want["figures"])
    for k, (shown, caption) in enumerate(zip(mine, want["figures"]), want["skip"]["figures"] + 1):
        assert shown.startswith(f"Figure {n}.{k}:")
        first_words = re.split(r"[$(]", caption)[0].strip().replace("'", "’")
        assert first_words and first_words in shown.replace("'", "’")
    # Labelled equations: (N.1) ... (N.k), in order, as in the book.
    # (Lab also numbers the unlabelled ones; test_lab_numbering.py keeps them after the last
    # labelled one, so the numbers the text refers to agree.)
    mine = [e for e in seen["equations"] if e.startswith(f"({n}.")]
    first = want["skip"]["equations"] + 1
    assert mine[:want["equations"]] == [f"({n}.{k})" for k in range(first, first + want["equations"])]

    # Every reference resolves; nothing is left raw; links to other files name files that exist.
    # A link to a target of this chapter lands on it. (A target in another chapter or page is a
    # box in the chapter's folded index, with a link to that file; Lab's renderer gives such
    # boxes no anchor, so only the text of its reference is checked, by "unresolved".)
    assert seen["unresolved"] == []
    assert [d for d in seen["dangling"] if d in want["labels"]] == []
    text = seen["text"]
    for raw in ("{numref}", "{prf:ref}", "{ref}", "{eq}", "{doc}", "{term}", ":::{", "```{"):
        assert raw not in text
    assert not re.search(r"\b(?:fig|alg|ex|sol)-ch?\d", text), "a raw label is shown"
    for href in seen["files"]:
        path = unquote(href.split("/files/", 1)[1].split("?")[0])
        assert (root / path).is_file(), f"a link to {path}, which does not exist"
    assert not [m for m in console if "not found" in m.lower() or "myst" in m.lower()]
    # Solutions stay folded until the reader opens one.
    assert seen["solutions"] >= len(want["exercises"]) and seen["open"] == 0


def _explorer_figure(page) -> dict:
    """The chapter-1 explorer's figure: is its image decoded, and which overlay is shown."""
    return page.evaluate("""() => {
        const panel = document.querySelector('.jp-NotebookPanel:not(.lm-mod-hidden)');
        const img = panel && panel.querySelector('.widget-image');
        const shown = [...(panel ? panel.querySelectorAll('.widget-gridbox svg') : [])]
            .filter(e => e.getClientRects().length > 0);
        return {drawn: !!img && img.complete && img.naturalWidth > 0 && shown.length === 1,
                overlay: shown.length ? shown[0].outerHTML : ''};
    }""")


def test_chapter_1_runs_without_errors_and_its_figure_is_never_blank(lab):
    page, port, _, _ = lab
    _open_and_run_all(page, port, "01_introduction.ipynb")
    assert page.locator(ERRORS).count() == 0
    assert page.get_by_text("Exercise 1.1: not yet. no answer yet").count() == 1
    for _ in range(2):  # views switch in the browser: no kernel redraw can race a second run
        page.wait_for_function("""() => { const i = document.querySelector(
                                              '.jp-NotebookPanel:not(.lm-mod-hidden) .widget-image');
                                          return i && i.complete && i.naturalWidth > 0; }""",
                               timeout=30_000)
        assert _explorer_figure(page)["drawn"]
        page.wait_for_timeout(1000)  # a late second redraw would blank it now
        assert _explorer_figure(page)["drawn"]
        _run_all(page)
    before = _explorer_figure(page)["overlay"]
    handle = page.locator(".jp-NotebookPanel:not(.lm-mod-hidden) .widget-slider .noUi-handle").first
    handle.focus()
    for _ in range(3):
        page.keyboard.press("ArrowRight")
    page.wait_for_timeout(300)
    after = _explorer_figure(page)
    assert after["drawn"] and after["overlay"] != before
