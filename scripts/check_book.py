"""Open every page of the built book in headless Chromium and check what a reader sees.

Usage: python scripts/check_book.py [_build/html] [--chromium /usr/bin/chromium] [--budget MS]

The book is served from a local HTTP server on 127.0.0.1; Chromium may resolve no other host, so
anything that needs the network fails here as it would for an offline reader. For each page the
DOM is dumped after the scripts ran (MathJax, the ipywidgets HTML manager, animations), and the
page fails when:

- it loads a script or stylesheet from an http(s) URL (the book must work offline);
- a request the page made was not served (missing image, font, script: HTTP status >= 400);
- an <img> has no src, or a src that is neither a data: URI nor a file of the build;
- it has math and MathJax did not typeset it (a math element without an mjx-container);
- a matplotlib animation (to_jshtml) has no controls or no frame shown;
- a saved widget view rendered nothing (no widget DOM next to its view script).

Then every page is opened in Chromium driven by playwright (offline: requests to any host but
the local server are refused), at 1280 px and at 390 px, as a reader on a laptop and on a phone
would see it. Each slider, of a widget or of an animation player, is pressed with the arrow keys:
the page fails when the figure the slider belongs to does not change. Every live explorer (rapp.live,
`data-rapp-live`) is dragged by a handle and must recompute and redraw. Measured and reported per
page: the seconds until the first slider responds and until every widget view rendered, the
HTML weight, the height at both widths, the CPU seconds the main thread used until the first
slider responded (the work, which a loaded machine inflates far less than the wait), and the smallest figure text as displayed (the PNG's
recorded ``rapp:text-px`` times its displayed over its natural width). The page fails when

- an element of the article reaches past the screen's right edge at 390 px (a box that scrolls
  sideways inside the column is fine), the page itself is wider than 390 px, or a displayed
  equation, table, code block or image is cut off by a box that clips it;
- axe-core (vendored, scripts/vendor_js.py) finds a critical or serious violation of the WCAG 2.1
  A/AA rules at 1280 px (issue 38);
- the page logs an error to the console, or throws one;
- a chapter page is taller than 22,000 px at 1280 px, or weighs over 2.5 MB of HTML;
- the main thread used over 4 CPU seconds before the page's first slider responded;
- a formula is still waiting to be typeset 30 s after the page opened (MathJax typesets it lazily);
- on the pages of PLACE_PAGES, typesetting the math after a jump to an equation, or above a reader
  in the middle of the page, moves what they read (with CSS scroll anchoring and without it);
- any page weighs over 8 MB; the book fails over 80 MB, and when fewer than 90 % of the figures
  that carry a text size show it at 9 CSS px or more, at 1280 px or at 390 px (a phone).

Prints one line per page and a summary line; exit status 1 when any page fails.
"""

from __future__ import annotations

import argparse
import concurrent.futures
import functools
import http.server
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from urllib.parse import unquote, urljoin, urlparse

from bs4 import BeautifulSoup

WIDGET_VIEW = "application/vnd.jupyter.widget-view+json"
SKIP_DIRS = {"_static", "_sources", "_images", "_sphinx_design_static", "_panels_static"}


class Recorder(http.server.SimpleHTTPRequestHandler):
    """Serve the build and remember every request with its status."""

    log: list[tuple[str, int]]

    def log_request(self, code="-", size="-"):
        self.log.append((unquote(urlparse(self.path).path), int(code) if str(code).isdigit() else 0))

    def log_message(self, format, *args):  # keep the report readable
        pass


class QuietServer(http.server.ThreadingHTTPServer):
    """Chromium drops connections it no longer needs (a favicon, say); that is no error."""

    def handle_error(self, request, client_address):
        if not isinstance(sys.exc_info()[1], ConnectionError):
            super().handle_error(request, client_address)


def serve(root: Path) -> tuple[http.server.ThreadingHTTPServer, list[tuple[str, int]]]:
    log: list[tuple[str, int]] = []
    handler = type("Handler", (Recorder,), {"log": log})
    server = QuietServer(
        ("127.0.0.1", 0), functools.partial(handler, directory=str(root))
    )
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server, log


def dump_dom(chromium: str, url: str, budget_ms: int) -> str:
    with tempfile.TemporaryDirectory(prefix="check_book_") as profile:
        cmd = [
            chromium,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-dev-shm-usage",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--disable-extensions",
            "--no-first-run",
            "--no-default-browser-check",
            "--mute-audio",
            f"--user-data-dir={profile}",
            # Only the local server resolves: a page that needs the network breaks here.
            "--host-resolver-rules=MAP * ~NOTFOUND, EXCLUDE 127.0.0.1",
            f"--virtual-time-budget={budget_ms}",
            "--run-all-compositor-stages-before-draw",
            "--dump-dom",
            url,
        ]
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=180, stdin=subprocess.DEVNULL)
    if proc.returncode != 0 or "<html" not in proc.stdout:
        raise RuntimeError(f"chromium failed ({proc.returncode}): {proc.stderr.strip()[-500:]}")
    return proc.stdout


def is_remote(url: str | None) -> bool:
    return bool(url) and (url.startswith("//") or urlparse(url).scheme in ("http", "https"))


def check_static(html: str) -> list[str]:
    """Problems visible in the page as built: resources loaded from the network."""
    soup = BeautifulSoup(html, "html.parser")
    problems = []
    for tag in soup.find_all("script", src=True):
        if is_remote(tag["src"]):
            problems.append(f"remote script {tag['src']}")
    for tag in soup.find_all("link", href=True):
        rel = " ".join(tag.get("rel", []))
        if is_remote(tag["href"]) and any(r in rel for r in ("stylesheet", "preload", "modulepreload")):
            problems.append(f"remote {rel} {tag['href']}")
    for tag in soup.find_all("style"):
        if "@import" in tag.text and ("http://" in tag.text or "https://" in tag.text):
            problems.append("remote @import in <style>")
    return problems


def count_math(soup: BeautifulSoup) -> tuple[int, int]:
    """(math elements, math elements MathJax did not typeset)."""
    maths = [el for el in soup.find_all(class_="math") if el.name in ("span", "div")]
    # MathJax's lazy extension holds a formula not typeset yet in an <mjx-lazy> placeholder.
    raw = [el for el in maths if el.find("mjx-container") is None or el.find("mjx-lazy") is not None]
    return len(maths), len(raw)


def check_dom(dom: str, page_url: str, root: Path, base_url: str) -> tuple[list[str], dict[str, int]]:
    soup = BeautifulSoup(dom, "html.parser")
    problems: list[str] = []
    stats = {"math": 0, "img": 0, "anim": 0, "widget": 0}

    n_math, n_raw = count_math(soup)
    stats["math"] = n_math
    if n_raw:
        problems.append(f"{n_raw} of {n_math} math elements not typeset by MathJax")
    # MathJax leaves delimiters in text only when it did not run over that text.
    body = soup.find("article") or soup.body
    if n_math and body is not None:
        text = body.get_text(" ")
        if "\\(" in text or "\\[" in text:
            problems.append("raw TeX delimiters \\( or \\[ left in the page text")

    for img in soup.find_all("img"):
        if img.find_parent(class_="animation") is not None:
            continue  # checked with its animation below
        stats["img"] += 1
        src = img.get("src", "")
        if not src:
            problems.append(f"<img> without src (alt={img.get('alt', '')!r})")
        elif src.startswith(("data:", "blob:")):
            continue  # inline, or made in the page (an ipywidgets Image)
        elif is_remote(src) and not src.startswith(base_url):
            problems.append(f"<img> from the network: {src}")
        else:
            path = unquote(urlparse(urljoin(page_url, src)).path).lstrip("/")
            if not (root / path).is_file():
                problems.append(f"<img> file missing: {path}")

    for anim in soup.find_all("div", class_="animation"):
        stats["anim"] += 1
        controls = anim.find(class_="anim-buttons") or anim.find(class_="anim-controls")
        buttons = anim.find_all("button")
        frame = anim.find("img")
        if controls is None or len(buttons) < 3:
            problems.append("animation without controls")
        if frame is None or not frame.get("src", "").startswith("data:image"):
            problems.append("animation shows no frame")

    for script in soup.find_all("script", type=WIDGET_VIEW):
        stats["widget"] += 1
        holder = script.parent
        rendered = holder.find_all(class_="widget-subarea") if holder is not None else []
        nodes = [el for area in rendered for el in area.find_all(True)]
        if not nodes:
            problems.append("widget view rendered blank")
    return problems, stats


PAGE_BUDGET_MB = 8.0
BOOK_BUDGET_MB = 80.0
# What a reader can take in at one sitting, on a laptop and on a phone (issue 22).
CHAPTER_HTML_MB = 2.5          # a chapter page's HTML, saved widget views included
CHAPTER_HEIGHT_PX = 22_000     # a chapter page's height at 1280 px: one sitting (issue 33.6)
# The main thread's CPU seconds until a page's first slider responds (issue 33): measured 0.8 to
# 1.5 s per widget page since math is typeset as it comes into view (1.4 to 3.4 s when MathJax
# typeset every formula first; 2026-12-05); the bound leaves room for a slower CI machine and
# catches a page that typesets everything before its widgets again.
FIRST_SLIDER_CPU_S = 4.0
MIN_TEXT_PX = 9.0              # the smallest figure text as displayed at 1280 px ...
MIN_TEXT_SHARE = 0.90          # ... in at least this share of the measured figures
WIDE, NARROW = 1280, 390       # viewport widths, CSS px
# axe-core (vendored by scripts/vendor_js.py) runs these rule sets on every page at 1280 px; a
# violation of impact "critical" or "serious" fails the page (issue 38).
AXE_PATH = "_static/offline/axe-core/axe.min.js"
AXE_TAGS = ["wcag2a", "wcag2aa", "wcag21a", "wcag21aa"]
AXE_FAIL = ("critical", "serious")


def is_chapter(rel: str) -> bool:
    """Chapter pages (the notebooks) carry the per-page limits; reference pages are reported."""
    return rel.startswith("notebooks/")


# The figure a slider drives: for a widget, the visible images and SVGs of its explorer; for an
# animation player, its frame. A signature of what is shown, to compare before and after a key.
_SHOWN = """(el) => {
    const root = el.closest('.animation') || el.closest('.widget-subarea') || document.body;
    const shown = [...root.querySelectorAll('img, svg')].filter(e => e.getClientRects().length > 0
        && getComputedStyle(e).visibility !== 'hidden');
    let h = 0;
    for (const e of shown) {
        const s = e.tagName === 'IMG' ? e.src : e.outerHTML;
        for (let i = 0; i < s.length; i += 7) { h = (h * 31 + s.charCodeAt(i)) | 0; }
        h = (h * 31 + s.length) | 0;
    }
    return shown.length + ':' + h;
}"""

# Elements of the article whose right edge is past the screen and that no scrolling box inside
# the screen holds (a box that scrolls sideways inside its column is what we want on a phone).
_OVERFLOW = """() => {
    const vw = document.documentElement.clientWidth;
    const article = document.querySelector('.bd-article') || document.body || document.documentElement;
    const found = [];
    const sel = 'img, svg, canvas, table, pre, iframe, video, mjx-container, .widget-subarea, '
        + '.jupyter-widgets, .animation, .cell_output > *, .widget-slider, .widget-box';
    for (const el of article.querySelectorAll(sel)) {
        const r = el.getBoundingClientRect();
        if (r.width === 0 || r.height === 0 || r.right <= vw + 1) continue;
        let held = false;
        for (let a = el.parentElement; a && a !== document.documentElement; a = a.parentElement) {
            const ox = getComputedStyle(a).overflowX;
            if (['auto', 'scroll', 'hidden', 'clip'].includes(ox) && a.getBoundingClientRect().right <= vw + 1) {
                held = true; break;
            }
        }
        if (!held) {
            const cls = (el.className && el.className.baseVal !== undefined) ? el.className.baseVal : el.className;
            found.push(`${el.tagName.toLowerCase()}${cls ? '.' + String(cls).trim().split(/\\s+/)[0] : ''}`
                       + ` to ${Math.round(r.right)} px`);
        }
    }
    return found;
}"""

# Every visible figure image of the article: its natural and displayed width and the smallest
# text it carries (the PNG text chunk rapp:text-px that rapp.plotting.book_png and the widget
# view stack write), read from the image's own bytes.
_FIGURES = """async () => {
    function chunks(bytes) {
        const out = {};
        const dv = new DataView(bytes.buffer);
        if (bytes.length < 8 || bytes[1] !== 0x50) return out;
        for (let i = 8; i + 8 <= bytes.length;) {
            const len = dv.getUint32(i);
            const type = String.fromCharCode(...bytes.slice(i + 4, i + 8));
            if (type === 'IDAT' || type === 'IEND') break;
            if (type === 'tEXt') {
                const data = bytes.slice(i + 8, i + 8 + len);
                const zero = data.indexOf(0);
                out[String.fromCharCode(...data.slice(0, zero))] = String.fromCharCode(...data.slice(zero + 1));
            }
            i += 12 + len;
        }
        return out;
    }
    const article = document.querySelector('.bd-article') || document.body || document.documentElement;
    const res = [];
    for (const img of article.querySelectorAll('img')) {
        const shown = img.getBoundingClientRect().width;
        if (!img.naturalWidth || !shown || img.closest('.animation')) continue;
        let text = null;
        try {
            const meta = chunks(new Uint8Array(await (await fetch(img.src)).arrayBuffer()));
            if (meta['rapp:text-px']) text = parseFloat(meta['rapp:text-px']);
        } catch (e) {}
        res.push({natural: img.naturalWidth, shown: shown, text_px: text,
                  seen_px: text === null ? null : text * shown / img.naturalWidth});
    }
    return res;
}"""

_HANDLES = ".widget-slider .noUi-handle, .animation input[type=range]"

# Displayed equations whose content is wider than a box that clips it (overflow hidden/clip on
# the way up, no scrolling box in between): a reader would never see its end.
_CLIPPED = """() => {
    const article = document.querySelector('.bd-article') || document.body;
    const out = [];
    for (const el of article.querySelectorAll('mjx-container[display="true"], pre, table, img')) {
        const r = el.getBoundingClientRect();
        if (!r.width || ['auto', 'scroll'].includes(getComputedStyle(el).overflowX)) continue;
        const right = r.left + Math.max(r.width, el.scrollWidth || 0);
        for (let a = el.parentElement; a && a !== document.body; a = a.parentElement) {
            const ox = getComputedStyle(a).overflowX;
            if (['auto', 'scroll'].includes(ox)) break;
            if (['hidden', 'clip'].includes(ox) && right > a.getBoundingClientRect().right + 2) {
                out.push(`${el.tagName.toLowerCase()} "${(el.textContent || '').replace(/\\s+/g, ' ').trim().slice(0, 30)}"`
                         + ` cut at ${Math.round(a.getBoundingClientRect().right)} px of ${Math.round(right)}`);
                break;
            }
        }
    }
    return out;
}"""

# axe-core's verdict on the page: the violations of impact critical or serious, each with its
# rule, impact, number of elements and the first few elements' selectors.
_AXE = """async (tags) => {
    const r = await axe.run(document, {runOnly: {type: 'tag', values: tags}, resultTypes: ['violations']});
    return r.violations.map(v => ({id: v.id, impact: v.impact, n: v.nodes.length,
                                   where: v.nodes.slice(0, 3).map(n => n.target.join(' '))}));
}"""


def run_axe(page, axe_source: str) -> list[dict]:
    """axe-core's violations on ``page`` (WCAG 2.1 A and AA rules), all impacts, once the book's
    script (rapp.js) has named what the theme leaves unnamed (its first pass, 150 ms after
    the page is read; a slow page, as the search page with its index, may take longer)."""
    try:
        page.wait_for_function("() => document.documentElement.dataset.rappNamed === '1'",
                               timeout=10_000)
    except Exception:  # playwright's TimeoutError: axe then reports what is unnamed
        pass
    page.add_script_tag(content=axe_source)
    return page.evaluate(_AXE, AXE_TAGS)


def _press_changes(page, handle) -> bool:
    """Press the arrow keys on a slider until what it drives changes (False: it never did)."""
    before = handle.evaluate(_SHOWN)
    for key in ("ArrowRight", "ArrowLeft", "ArrowLeft"):
        handle.focus()
        page.keyboard.press(key)
        page.wait_for_timeout(120)
        if handle.evaluate(_SHOWN) != before:
            return True
    return False


def _launch(pw):
    """Headless Chromium from Debian's package, as every browser check here starts it."""
    return pw.chromium.launch(executable_path=shutil.which("chromium") or "/usr/bin/chromium",
                              args=["--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage"])


def _local_only(host: str):
    """A route handler that serves the book's own server (and data:/blob: URLs) and aborts the rest."""
    return lambda route: (route.continue_() if urlparse(route.request.url).netloc == host
                          or route.request.url.startswith(("data:", "blob:")) else route.abort())


# True once no formula waits in MathJax's lazy placeholder (rapp.js typesets the rest when idle).
_ALL_TYPESET = "() => !document.querySelector('mjx-lazy')"


def main_thread_busy(cdp) -> tuple[float | None, float | None]:
    """Seconds the page's main thread has spent running tasks (Chrome's ``TaskDuration``: wall
    time, which a loaded machine stretches) and the CPU seconds it used (``ThreadTime``: the work
    itself, which a loaded machine inflates far less)."""
    try:
        metrics = {m["name"]: m["value"] for m in cdp.send("Performance.getMetrics")["metrics"]}
    except Exception:  # a browser without the metrics: nothing to report
        return None, None
    return metrics.get("TaskDuration"), metrics.get("ThreadTime")


def check_in_browser(base_url: str, pages: list[tuple[str, int]],
                     live_only: frozenset = frozenset(),
                     axe_source: str | None = None) -> dict[str, tuple[list[str], dict]]:
    """Open every page as a reader would, at 1280 px and at 390 px, and measure it.

    ``pages`` are (relative URL, number of saved widget views). At 1280 px: the seconds until the
    first slider responds and until every widget view rendered, every slider pressed with the
    arrow keys (the figure it drives must change), the page's height, and the smallest figure
    text as displayed, axe-core's accessibility violations (with ``axe_source``) and the errors
    the page logged to the console. At 390 px: the page's width, the elements that reach past the
    screen's right edge or are cut by a box that clips, and the figure text as displayed.
    Returns, per page, the problems and the numbers measured.
    """
    from playwright.sync_api import sync_playwright

    host = urlparse(base_url).netloc
    results: dict[str, tuple[list[str], dict]] = {}
    with sync_playwright() as pw:
        browser = _launch(pw)
        for rel, views in pages:
            page = browser.new_page(viewport={"width": WIDE, "height": 900})
            page.route("**/*", _local_only(host))
            problems: list[str] = []
            measured: dict = {}
            errors: list[str] = []
            page.on("pageerror", lambda err, errors=errors: errors.append(f"uncaught: {str(err).splitlines()[0]}"))
            page.on("console", lambda msg, errors=errors: errors.append(
                f"console error: {msg.text.splitlines()[0][:160]}") if msg.type == "error"
                and not msg.location.get("url", "").endswith("favicon.ico") else None)
            # The main thread's CPU seconds (Chrome's ThreadTime) until the first slider answered
            # is the work a reader's machine must do before the page is usable; a loaded machine
            # stretches the wall time (and TaskDuration, also reported) but hardly the work.
            # Bounded by FIRST_SLIDER_CPU_S (issue 33: usable within 3 s on an idle machine).
            cdp = page.context.new_cdp_session(page)
            cdp.send("Performance.enable")
            t0 = time.monotonic()
            page.goto(base_url + rel, wait_until="domcontentloaded")
            try:  # a redirect stub (the root index.html) has nothing to measure
                stub = page.evaluate("!!document.querySelector('meta[http-equiv=\"refresh\" i]')")
            except Exception:  # it has navigated away already: a redirect too
                stub = True
            if stub:
                results[rel] = ([], {"slider": 0})
                page.close()
                continue
            # Live explorers (rapp.live) are dragged, not pressed: check_live times and checks them.
            has_slider = (views and rel not in live_only) or page.locator(".animation").count()
            # The first slider that moves its figure: how long a reader waits to use the page.
            while has_slider and time.monotonic() - t0 < 30:
                first = page.locator(_HANDLES)
                if first.count() and first.first.is_visible():
                    first.first.scroll_into_view_if_needed()
                    if _press_changes(page, first.first):
                        measured["first_slider_s"] = time.monotonic() - t0
                        measured["first_slider_busy_s"], measured["first_slider_cpu_s"] = main_thread_busy(cdp)
                        break
                page.wait_for_timeout(150)
            page.wait_for_load_state("load")
            if views:
                try:
                    page.wait_for_function(
                        "(n) => document.querySelectorAll('.widget-subarea').length >= n "
                        "&& [...document.querySelectorAll('.widget-subarea')].every(a => a.children.length)",
                        arg=views, timeout=30_000)
                except Exception:
                    problems.append("widgets did not render within 30 s")
                measured["ready_s"] = time.monotonic() - t0
            if has_slider and "first_slider_s" not in measured:
                problems.append("no slider responded within 30 s")
            handles = page.locator(_HANDLES)
            pressed = 0
            for i in range(handles.count()):
                handle = handles.nth(i)
                if not handle.is_visible():
                    continue
                handle.scroll_into_view_if_needed()
                name = page.evaluate("(el) => { const w = el.closest('.widget-slider');"
                                     " const l = w && w.querySelector('.widget-label');"
                                     " return l ? l.textContent : 'animation frame'; }",
                                     handle.element_handle())
                pressed += 1
                if not _press_changes(page, handle):
                    problems.append(f"slider {name!r}: the arrow keys move it, the figure stays")
            measured["slider"] = pressed
            measured["console"] = errors
            # Math comes into view typeset, and rapp.js typesets the rest once the page is idle:
            # every formula is measured below, at both widths, as a reader would see it.
            try:
                page.wait_for_function(_ALL_TYPESET, timeout=30_000)
            except Exception:
                problems.append("math still waiting to be typeset 30 s after the page opened")
            try:
                measured["height_px"] = page.evaluate("document.documentElement.scrollHeight")
                measured["figures"] = page.evaluate(_FIGURES)
                if axe_source:
                    measured["axe"] = run_axe(page, axe_source)
                page.set_viewport_size({"width": NARROW, "height": 844})
                page.wait_for_timeout(400)
                measured["overflow"] = page.evaluate(_OVERFLOW)
                measured["clipped"] = page.evaluate(_CLIPPED)
                measured["width_390_px"] = page.evaluate("document.documentElement.scrollWidth")
                measured["figures_390"] = page.evaluate(_FIGURES)
                measured["height_390_px"] = page.evaluate("document.documentElement.scrollHeight")
            except Exception as err:  # a page the browser could not measure is a failure, not a crash
                problems.append(f"could not measure the page: {str(err).splitlines()[0]}")
            problems += sorted(set(errors))
            for v in measured.get("axe", []):
                if v["impact"] in AXE_FAIL:
                    problems.append(f"axe {v['impact']} {v['id']}: {v['n']} elements, e.g. " + "; ".join(v["where"]))
            if measured.get("width_390_px", 0) > NARROW:
                problems.append(f"at {NARROW} px the page is {measured['width_390_px']} px wide: it scrolls sideways")
            for where in measured.get("clipped", []):
                problems.append(f"at {NARROW} px cut off: {where}")
            results[rel] = (problems, measured)
            page.close()
        browser.close()
    return results


# Moving a slider (its value set as a reader's drag sets it, then an `input` event) must redraw
# the explorer at once: the C-space picture changes, and the status line with it. The speed
# slider only paces the animation.
_MOVE_SLIDER = """(input) => {
    const v = +input.value, lo = +input.min, hi = +input.max, step = +input.step || 1;
    input.value = String(v + step <= hi ? v + step : v - step);
    input.dispatchEvent(new Event("input", {bubbles: true}));
    return input.parentElement.textContent.trim().split(" ")[0];
}"""
_SWITCH_MENU = """(select) => {
    select.selectedIndex = (select.selectedIndex + 1) % select.options.length;
    select.dispatchEvent(new Event("change", {bubbles: true}));
    return select.value;
}"""


def _controls_redraw(page, root, canvas: str) -> list[str]:
    """Move each slider of an explorer and switch its menu; each must change the C-space picture."""
    problems = []
    status = "(root) => root.querySelector('.rl-status').textContent"
    controls = [(s, _MOVE_SLIDER) for s in root.locator("input[type=range]").all()]
    controls += [(s, _SWITCH_MENU) for s in root.locator("select").all()]
    for control, action in controls:
        if not control.is_visible():
            continue
        before = (root.evaluate(canvas), root.evaluate(status))
        label = control.evaluate(action)
        if label == "speed":
            continue
        # A control may need a second step to show (a heuristic weight one step from 1 can
        # leave a short search's path and count as they were): up to three steps, each given
        # time to redraw.
        for attempt in range(3):
            page.wait_for_timeout(400)
            if (root.evaluate(canvas), root.evaluate(status)) != before:
                break
            if attempt < 2:
                control.evaluate(action)
        else:
            problems.append(f"control {label!r} changed, but the picture and the status line stayed")
    return problems


# Math is typeset as it comes into view and the rest later (rapp.js): what a reader reads must not
# move meanwhile. On these pages an equation link far from its target is followed 1 s after the
# page opened, with CSS scroll anchoring and without it (Safari before 26, emulated with
# overflow-anchor: none), and a reader who jumped to the middle of the page stays where they are.
PLACE_PAGES = ("notebooks/06_inverse_kinematics.html", "notebooks/15_motion.html")
PLACE_TOLERANCE_PX = 16  # what rapp.js fixed moved 26 to 1,709 px; it now moves under 6
_NO_ANCHORING = """document.addEventListener('DOMContentLoaded', () => {
  const s = document.createElement('style');
  s.textContent = '* { overflow-anchor: none !important; }';
  document.head.appendChild(s);
});"""
# The first equation link whose target is more than two screens away, marked for the click.
_FAR_LINK = """() => {
  const y = (el) => el.getBoundingClientRect().top + scrollY;
  for (const a of document.querySelectorAll('.bd-article a.reference.internal[href^="#equation-"]')) {
    if (a.closest('.eqno') || !a.getClientRects().length) continue;
    const t = document.getElementById(decodeURIComponent(a.getAttribute('href').slice(1)));
    if (t && Math.abs(y(t) - y(a)) > 2 * innerHeight) { a.dataset.rappCheck = '1'; return t.id; }
  }
  return null;
}"""
# The block of the article at 40 % of the screen's height, marked: what the reader is reading.
_READING = """() => {
  const hit = document.elementsFromPoint(innerWidth / 2, innerHeight * 0.4).find((el) => el.closest('.bd-article'));
  const el = hit && (hit.closest('p, li, pre, table, h1, h2, h3, h4, h5, h6, dd, figure, div.math') || hit);
  if (!el) return false;
  el.dataset.rappReading = '1';
  return true;
}"""
_TOP = "(sel) => document.querySelector(sel).getBoundingClientRect().top"

def _follow(page, url: str, action: str) -> tuple[float | None, str]:
    """Open ``url``, jump (``"jump"``: an equation link; ``"middle"``: the middle of the page) 1 s
    later, and return how far what the reader then sees moved once every formula was typeset
    (None: the math never finished), with what was watched. LookupError: nothing to watch."""
    page.goto(url, wait_until="domcontentloaded")
    page.wait_for_timeout(1000)
    if action == "jump":
        target = page.evaluate(_FAR_LINK)
        if not target:
            raise LookupError("no equation link two screens from its target to follow")
        page.locator("[data-rapp-check]").first.click()
        sel, what = f"[id='{target}']", f"the jump to #{target}"
    else:
        page.evaluate("window.scrollTo(0, document.documentElement.scrollHeight * 0.45)")
        sel, what = "[data-rapp-reading]", "the text read in the middle of the page"
    page.wait_for_timeout(300)
    if action == "middle" and not page.evaluate(_READING):
        raise LookupError("nothing of the article in the middle of the screen")
    before = page.evaluate(_TOP, sel)
    try:
        page.wait_for_function(_ALL_TYPESET, timeout=30_000)
    except Exception:
        return None, what
    page.wait_for_timeout(1000)
    return page.evaluate(_TOP, sel) - before, what


def check_place_kept(base_url: str, pages: tuple[str, ...] = PLACE_PAGES) -> dict[str, tuple[list[str], dict]]:
    """Follow an equation link, and jump to the middle of the page, before the math is typeset.

    At 390 x 844 px, with and without CSS scroll anchoring: the link's target (and, without
    anchoring, the block being read after a jump to the middle) must stay within
    ``PLACE_TOLERANCE_PX`` of where it was once every formula is typeset. Returns, per page, the
    problems and the largest movement measured.
    """
    from playwright.sync_api import sync_playwright

    host = urlparse(base_url).netloc
    results: dict[str, tuple[list[str], dict]] = {}
    with sync_playwright() as pw:
        browser = _launch(pw)
        for rel in pages:
            problems: list[str] = []
            moved: list[float] = []
            for anchoring, action in ((True, "jump"), (False, "jump"), (False, "middle")):
                context = browser.new_context(viewport={"width": NARROW, "height": 844}, is_mobile=True,
                                              has_touch=True, device_scale_factor=3)
                context.route("**/*", _local_only(host))
                if not anchoring:
                    context.add_init_script(_NO_ANCHORING)
                try:
                    shift, what = _follow(context.new_page(), base_url + rel, action)
                except LookupError as missing:
                    problems.append(str(missing))
                    continue
                finally:
                    context.close()
                if shift is None:
                    problems.append("math still waiting to be typeset 30 s after the page opened")
                    continue
                moved.append(abs(shift))
                if abs(shift) > PLACE_TOLERANCE_PX:
                    problems.append(f"{what} moved {shift:+.0f} px while the math was typeset "
                                    f"({'with' if anchoring else 'without'} CSS scroll anchoring)")
            results[rel] = (problems, {"moved_px": max(moved, default=0.0)})
        browser.close()
    return results


def check_live(base_url: str, pages: list[str], shots: Path | None = None) -> dict[str, tuple[list[str], dict]]:
    """Drag every live explorer (``data-rapp-live``) and check that it redraws.

    For each explorer root the first obstacle handle (``data-rapp-drag="obstacle-…"``), or the
    goal handle where no workspace is shown, is dragged with the mouse; the explorer must
    recompute (its ``data-rapp-frame`` counter grows) and its C-space canvas must change. With
    ``shots`` a screenshot of each explorer is saved before and after the drag. Returns, per page,
    the problems and the number of explorers dragged.
    """
    from playwright.sync_api import sync_playwright

    host = urlparse(base_url).netloc
    results: dict[str, tuple[list[str], dict]] = {}
    canvas = "(root) => root.querySelector('canvas[data-rapp-drag=cspace]').toDataURL()"
    with sync_playwright() as pw:
        browser = _launch(pw)
        for rel in pages:
            page = browser.new_page(viewport={"width": 1280, "height": 900})
            page.route("**/*", lambda route: route.continue_() if urlparse(route.request.url).netloc
                       == host or route.request.url.startswith("data:") else route.abort())
            problems: list[str] = []
            page.goto(base_url + rel, wait_until="load")
            try:
                page.wait_for_selector("[data-rapp-live]", timeout=30_000)
            except Exception:
                results[rel] = (["a live explorer did not render within 30 s"], {"live": 0})
                page.close()
                continue
            roots = page.locator("[data-rapp-live]")
            for i in range(roots.count()):
                root = roots.nth(i)
                root.scroll_into_view_if_needed()
                page.wait_for_timeout(200)
                handle = root.locator('[data-rapp-drag^="obstacle-"]').first
                if not handle.is_visible():
                    handle = root.locator('[data-rapp-drag="goal"]')
                name = f"explorer {i + 1} ({root.get_attribute('data-rapp-live')})"
                if shots:
                    root.screenshot(path=str(shots / f"{Path(rel).stem}-{i + 1}-before.png"))
                frame, image = root.get_attribute("data-rapp-frame"), root.evaluate(canvas)
                box = handle.bounding_box()
                if box is None:
                    problems.append(f"{name}: no handle to drag")
                    continue
                x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
                page.mouse.move(x, y)
                page.mouse.down()
                page.mouse.move(x - 45, y + 35, steps=12)
                page.mouse.up()
                page.wait_for_timeout(300)
                if shots:
                    root.screenshot(path=str(shots / f"{Path(rel).stem}-{i + 1}-after.png"))
                if root.get_attribute("data-rapp-frame") == frame:
                    problems.append(f"{name}: dragged, but it did not recompute")
                elif root.evaluate(canvas) == image:
                    problems.append(f"{name}: dragged and recomputed, but the C-space picture stayed")
                problems += [f"{name}: {p}" for p in _controls_redraw(page, root, canvas)]
            results[rel] = (problems, {"live": roots.count()})
            page.close()
        browser.close()
    return results


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build", nargs="?", default="_build/html", type=Path)
    parser.add_argument("--chromium", default=shutil.which("chromium") or "/usr/bin/chromium")
    parser.add_argument("--budget", type=int, default=20000, help="virtual time per page, ms")
    parser.add_argument("--jobs", type=int, default=2, help="pages opened at once (default 2)")
    parser.add_argument("--shots", type=Path, help="save screenshots of each live explorer before and after its drag here")
    args = parser.parse_args(argv)

    root = args.build.resolve()
    pages = sorted(
        p for p in root.rglob("*.html") if not (set(p.relative_to(root).parts[:-1]) & SKIP_DIRS)
    )
    if not pages:
        print(f"check_book: no HTML pages under {root}")
        return 1
    if not Path(args.chromium).exists():
        print(f"check_book: chromium not found at {args.chromium}")
        return 1

    server, log = serve(root)
    base_url = f"http://127.0.0.1:{server.server_address[1]}/"
    totals = {"math": 0, "img": 0, "anim": 0, "widget": 0}

    def visit(page: Path) -> tuple[list[str], dict[str, int]]:
        url = base_url + page.relative_to(root).as_posix()
        problems = check_static(page.read_text(encoding="utf-8"))
        stats = {k: 0 for k in totals}
        try:
            dom = dump_dom(args.chromium, url, args.budget)
        except (RuntimeError, subprocess.TimeoutExpired) as err:
            return problems + [str(err)], stats
        found, stats = check_dom(dom, url, root, base_url)
        return problems + found, stats

    failed = 0
    try:
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            results = list(pool.map(visit, pages))
        with_widgets = [(p.relative_to(root).as_posix(), p.read_text(encoding="utf-8").count(WIDGET_VIEW))
                        for p in pages]
        # Pages whose widgets are all live explorers (no ipywidgets slider among them).
        live_only = frozenset(rel for rel, n in with_widgets if n and "rapp.live.Explorer" in (
            html := (root / rel).read_text(encoding="utf-8")) and "SliderModel" not in html)
        axe_file = root / AXE_PATH
        if not axe_file.is_file():
            print(f"check_book: {AXE_PATH} is missing from the build (scripts/vendor_js.py copies it)")
            return 1
        browsed = check_in_browser(base_url, with_widgets, live_only, axe_file.read_text(encoding="utf-8"))
        if args.shots:
            args.shots.mkdir(parents=True, exist_ok=True)
        live = check_live(base_url, [p.relative_to(root).as_posix() for p in pages
                                     if "rapp.live.Explorer" in p.read_text(encoding="utf-8")], args.shots)
        place = check_place_kept(base_url, tuple(rel for rel in PLACE_PAGES if (root / rel).is_file()))
    finally:
        server.shutdown()
    book_mb = sum(f.stat().st_size for f in root.rglob("*") if f.is_file()) / 1e6
    totals["slider"] = 0
    # Pages are opened in parallel, so a failed request is reported under every page whose HTML
    # names the file; one nothing names (e.g. a font a stylesheet asked for) fails on its own line.
    missing = sorted({path for path, code in log if code >= 400 and path != "/favicon.ico"})
    figures_all: list[dict] = []
    figures_narrow: list[dict] = []
    axe_total = 0
    for page, (problems, stats) in zip(pages, results):
        rel = page.relative_to(root).as_posix()
        html = page.read_text(encoding="utf-8")
        problems += [f"not served: {path}" for path in missing if Path(path).name in html]
        browser_problems, measured = browsed.get(rel, ([], {"slider": 0}))
        problems += browser_problems + live.get(rel, ([], {}))[0] + place.get(rel, ([], {}))[0]
        stats = dict(stats, slider=measured.get("slider", 0))
        mb = page.stat().st_size / 1e6
        if mb > PAGE_BUDGET_MB:
            problems.append(f"page weighs {mb:.1f} MB, over the {PAGE_BUDGET_MB:g} MB budget")
        height = measured.get("height_px", 0)
        if is_chapter(rel):
            if mb > CHAPTER_HTML_MB:
                problems.append(f"chapter page weighs {mb:.2f} MB of HTML, over {CHAPTER_HTML_MB:g} MB")
            if height > CHAPTER_HEIGHT_PX:
                problems.append(f"chapter page is {height} px tall at {WIDE} px, over {CHAPTER_HEIGHT_PX}")
        for where in measured.get("overflow", []):
            problems.append(f"at {NARROW} px past the screen's edge: {where}")
        figures = measured.get("figures", [])
        figures_all += [dict(f, page=rel) for f in figures]
        figures_narrow += [dict(f, page=rel) for f in measured.get("figures_390", [])]
        axe_serious = sum(v["n"] for v in measured.get("axe", []) if v["impact"] in AXE_FAIL)
        axe_total += axe_serious
        seen = [f["seen_px"] for f in figures if f["seen_px"] is not None]
        for key in totals:
            totals[key] += stats[key]
        summary = ", ".join(f"{v} {k}" for k, v in stats.items()) + f"; {mb:.2f} MB"
        summary += f", {height} px tall ({measured.get('height_390_px', 0)} at {NARROW})"
        if figures:
            summary += (f", figure text {min(seen):.1f} px min over {len(seen)} of {len(figures)} figures"
                        if seen else f", {len(figures)} figures without a recorded text size")
        narrow = [f["seen_px"] for f in measured.get("figures_390", []) if f["seen_px"] is not None]
        if narrow:
            summary += f" ({min(narrow):.1f} px min at {NARROW})"
        if "axe" in measured:
            summary += f", {axe_serious} critical/serious axe findings"
        if "first_slider_s" in measured:
            summary += f", first slider responds in {measured['first_slider_s']:.1f} s"
            if measured.get("first_slider_cpu_s") is not None:
                summary += (f" (main thread CPU {measured['first_slider_cpu_s']:.1f} s, busy "
                            f"{measured.get('first_slider_busy_s') or 0:.1f} s)")
                if measured["first_slider_cpu_s"] > FIRST_SLIDER_CPU_S:
                    problems.append(f"the main thread worked {measured['first_slider_cpu_s']:.1f} CPU s before the "
                                    f"first slider responded, over {FIRST_SLIDER_CPU_S:g} s")
        if rel in live:
            summary += f", {live[rel][1]['live']} live explorers dragged"
        if "ready_s" in measured:
            summary += f", interactive in {measured['ready_s']:.1f} s"
        if rel in place:
            summary += f", read text moved {place[rel][1]['moved_px']:.0f} px at most while math was typeset"
        if problems:
            failed += 1
            print(f"FAIL {rel} ({summary})")
            for problem in problems:
                print(f"     - {problem}")
        else:
            print(f"ok   {rel} ({summary})")
    # Figure text: a book-wide share, since a few dense figures (a legend of a 3-panel row) may
    # stay just under; figures drawn without the book style carry no size and are listed.
    seen_all = [f for f in figures_all if f["seen_px"] is not None]
    legible = [f for f in seen_all if f["seen_px"] >= MIN_TEXT_PX]
    unmeasured = len(figures_all) - len(seen_all)
    share = len(legible) / len(seen_all) if seen_all else 1.0
    small = sorted(seen_all, key=lambda f: f["seen_px"])[:5]
    print(f"figure text at {WIDE} px: {len(legible)} of {len(seen_all)} measured figures "
          f"show their smallest text at >= {MIN_TEXT_PX:g} px ({share:.0%}); {unmeasured} figures "
          "carry no text size (drawn without rapp.plotting.book_style)"
          + ("; smallest: " + ", ".join(f"{f['page']} {f['seen_px']:.1f} px" for f in small) if small else ""))
    if share < MIN_TEXT_SHARE:
        failed += 1
        print(f"FAIL figure text: {share:.0%} of figures legible, under {MIN_TEXT_SHARE:.0%}")
    # The same on a phone: the figures keep a width at which their text reads (reader_pages.py).
    seen_narrow = [f for f in figures_narrow if f["seen_px"] is not None]
    legible_narrow = [f for f in seen_narrow if f["seen_px"] >= MIN_TEXT_PX]
    share_narrow = len(legible_narrow) / len(seen_narrow) if seen_narrow else 1.0
    small = sorted(seen_narrow, key=lambda f: f["seen_px"])[:5]
    print(f"figure text at {NARROW} px: {len(legible_narrow)} of {len(seen_narrow)} measured figures "
          f"show their smallest text at >= {MIN_TEXT_PX:g} px ({share_narrow:.0%})"
          + ("; smallest: " + ", ".join(f"{f['page']} {f['seen_px']:.1f} px" for f in small) if small else ""))
    if share_narrow < MIN_TEXT_SHARE:
        failed += 1
        print(f"FAIL figure text on a phone: {share_narrow:.0%} of figures legible, under {MIN_TEXT_SHARE:.0%}")
    print(f"accessibility (axe-core, WCAG 2.1 A/AA, at {WIDE} px): {axe_total} critical or serious findings")
    unattributed = [p for p in missing if not any(Path(p).name in pg.read_text(encoding="utf-8") for pg in pages)]
    if unattributed:
        failed += 1
        print("FAIL requests not served: " + ", ".join(unattributed))
    if book_mb > BOOK_BUDGET_MB:
        failed += 1
        print(f"FAIL the book weighs {book_mb:.1f} MB, over the {BOOK_BUDGET_MB:g} MB budget")
    checked = ", ".join(f"{v} {k}" for k, v in totals.items()) + f"; book {book_mb:.1f} MB"
    print(
        f"check_book: {len(pages) - failed} of {len(pages)} pages ok; "
        f"checked {checked}; {len(log)} requests served locally"
    )
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
