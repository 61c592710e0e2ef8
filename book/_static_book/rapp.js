// rapp: a figure shown smaller than it was drawn (a multi-panel row on a phone) opens full size
// on click, in a new tab. Figures already shown at their own size do nothing.
document.addEventListener("click", (event) => {
  const img = event.target.closest(".cell_output img");
  if (!img || img.closest("a, .animation, .jupyter-widgets")) return;
  if (img.naturalWidth > 1.15 * img.clientWidth) window.open(img.src, "_blank", "noopener");
});

// rapp: pages a phone can read and a screen reader can use (issues 33 and 38). What the theme and
// the saved widgets put on the page is named here, once it is there (widgets render late).
(function () {
  "use strict";
  const MIN_TEXT_PX = 9; // the smallest figure text to show, CSS px (book/_ext/reader_pages.py)

  // The width and smallest text of a PNG (a widget's figure: a blob: or data: URL in the page),
  // from its IHDR and its rapp:text-px chunk, which rapp.plotting writes as for the book's figures.
  function pngTextPx(bytes) {
    if (bytes.length < 24 || bytes[1] !== 0x50) return null;
    const dv = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    const width = dv.getUint32(16);
    for (let i = 8; i + 8 <= bytes.length;) {
      const len = dv.getUint32(i);
      const type = String.fromCharCode(...bytes.subarray(i + 4, i + 8));
      if (type === "IDAT" || type === "IEND") break;
      if (type === "tEXt") {
        const data = bytes.subarray(i + 8, i + 8 + len), zero = data.indexOf(0);
        if (String.fromCharCode(...data.subarray(0, zero)) === "rapp:text-px")
          return { width, px: parseFloat(String.fromCharCode(...data.subarray(zero + 1))) };
      }
      i += 12 + len;
    }
    return null;
  }

  function legibleWidgetFigure(img) {
    const src = img.getAttribute("src") || "";
    if (!/^(blob:|data:image\/png)/.test(src) || img.dataset.rappSized === src.slice(-40)) return;
    img.dataset.rappSized = src.slice(-40);
    fetch(src).then((r) => r.arrayBuffer()).then((buf) => {
      const t = pngTextPx(new Uint8Array(buf));
      if (!t || !(t.px > 0) || !t.width) { img.style.removeProperty("--rapp-min-w"); return; }
      img.style.setProperty("--rapp-min-w", Math.min(t.width, Math.ceil(t.width * MIN_TEXT_PX / t.px)) + "px");
    }).catch(() => {});
  }

  function widgetLabel(box) {
    const label = box && box.querySelector(":scope > .widget-label, .widget-label");
    return label ? label.textContent.trim() : "";
  }

  function nameWidgets(root) {
    // Sliders: the handle (role=slider) and the number box take the slider's description.
    root.querySelectorAll(".widget-slider, .widget-hslider, .widget-vslider, .jupyter-widgets.widget-inline-hbox").forEach((box) => {
      const name = widgetLabel(box);
      if (!name) return;
      box.querySelectorAll('[role="slider"], .noUi-handle, input, select, textarea').forEach((el) => {
        if (!el.getAttribute("aria-label") && !el.getAttribute("aria-labelledby")) el.setAttribute("aria-label", name);
      });
    });
    // Any other input still without a name: its placeholder, else its box's description.
    root.querySelectorAll(".jupyter-widgets input, .jupyter-widgets select, .jupyter-widgets textarea, .jupyter-widgets [role=slider]").forEach((el) => {
      if (el.getAttribute("aria-label") || el.getAttribute("aria-labelledby") || (el.id && document.querySelector(`label[for="${el.id}"]`))) return;
      const name = el.getAttribute("placeholder") || widgetLabel(el.closest(".widget-inline-hbox, .widget-box")) || el.getAttribute("title");
      if (name) el.setAttribute("aria-label", name);
    });
    // Figures a widget draws: a text alternative and, on a phone, a legible width.
    root.querySelectorAll("img.widget-image").forEach((img) => {
      legibleWidgetFigure(img);
      if (img.hasAttribute("alt")) return;
      const view = img.closest(".widget-subarea, .jupyter-widgets-view") || img.parentElement;
      const names = [...(view ? view.querySelectorAll(".widget-label") : [])]
        .map((l) => l.textContent.trim()).filter(Boolean);
      img.setAttribute("alt", "The figure of this explorer, redrawn by its controls"
        + (names.length ? " (" + names.join(", ") + ")" : "") + "; the text around it says what it shows.");
    });
  }

  function nameTheme() {
    // The navigation's fold-out arrows: a <summary> with only an icon in it.
    document.querySelectorAll("nav details > summary").forEach((summary) => {
      if (summary.getAttribute("aria-label") || summary.textContent.trim()) return;
      const link = summary.parentElement.parentElement.querySelector(":scope > a");
      summary.setAttribute("aria-label", "Show the sections of " + (link ? link.textContent.trim() : "this part"));
    });
    // Controls whose visible text is not in their accessible name (the search button shows
    // "Search Ctrl+K" but was named "Search"; a folded code cell shows "Show code cell source"
    // but was named "Toggle hidden content"): the name becomes the visible text.
    document.querySelectorAll("button[aria-label], summary[aria-label], a[aria-label]").forEach((b) => {
      if (b.closest(".theme-switch-button") || b.classList.contains("theme-switch-button")) return;
      const text = b.innerText ? b.innerText.replace(/\s+/g, " ").trim() : "";
      const label = b.getAttribute("aria-label");
      if (text && !label.toLowerCase().includes(text.toLowerCase())) b.setAttribute("aria-label", text);
    });
    document.querySelectorAll(".theme-switch-button").forEach((b) => {
      const shown = [...b.querySelectorAll("[title], [data-mode]")]
        .filter((i) => i.getClientRects().length && getComputedStyle(i).display !== "none");
      const text = b.textContent.replace(/\s+/g, " ").trim();
      const label = shown.length ? (shown[0].getAttribute("title") || shown[0].dataset.mode) : "";
      b.setAttribute("aria-label", [text || label, "colour mode"].filter(Boolean).join(", "));
    });
  }

  // Coloured text in a widget's HTML (a status line in the figures' palette: green #009e73 is
  // 3.4:1 on white) is darkened, keeping its hue, until it reads at 4.5:1 (WCAG 2.1 AA).
  function luminance(rgb) {
    const c = rgb.map((v) => { v /= 255; return v <= 0.03928 ? v / 12.92 : Math.pow((v + 0.055) / 1.055, 2.4); });
    return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
  }
  function readableColours(root) {
    root.querySelectorAll(".widget-html-content [style*='color'], .widget-label [style*='color'], .widget-html-content font[color]").forEach((el) => {
      if (el.dataset.rappContrast) return;
      el.dataset.rappContrast = "1";
      const m = getComputedStyle(el).color.match(/\d+(\.\d+)?/g);
      if (!m) return;
      let rgb = m.slice(0, 3).map(Number);
      const bg = 1.0; // the widgets' white background
      for (let k = 0; k < 20 && (bg + 0.05) / (luminance(rgb) + 0.05) < 4.6; k++) rgb = rgb.map((v) => v * 0.9);
      el.style.color = `rgb(${rgb.map(Math.round).join(",")})`;
    });
  }

  // matplotlib's animation players: the frame slider gets a name.
  function nameAnimations() {
    document.querySelectorAll(".animation input[type=range]").forEach((el) => {
      if (!el.getAttribute("aria-label")) el.setAttribute("aria-label", "Animation frame");
    });
    document.querySelectorAll(".animation button").forEach((b) => {
      if (!b.getAttribute("aria-label") && !b.textContent.trim() && b.title) b.setAttribute("aria-label", b.title);
    });
  }

  // A box that scrolls sideways (a figure on a phone, a long equation, a table) can be reached
  // and scrolled with the keyboard.
  function focusableScrollers() {
    // Inline math wider than its line's box (a long formula on a phone): its own scrolling box.
    document.querySelectorAll('.bd-article mjx-container:not([display="true"])').forEach((el) => {
      const box = el.parentElement && el.parentElement.closest("p, li, td, th, dd, div");
      const limit = box ? box.clientWidth : document.documentElement.clientWidth;
      const wide = el.classList.contains("rapp-wide-inline") ? el.scrollWidth : el.getBoundingClientRect().width;
      el.classList.toggle("rapp-wide-inline", wide > limit + 1);
    });
    document.querySelectorAll('.bd-article .rapp-figure-scroll, .bd-article mjx-container[display="true"], .bd-article mjx-container.rapp-wide-inline, .bd-article table, .bd-article .cell_output')
      .forEach((el) => {
        if (el.scrollWidth > el.clientWidth + 1) {
          if (!el.hasAttribute("tabindex")) { el.setAttribute("tabindex", "0"); el.dataset.rappTab = "1"; }
        } else if (el.dataset.rappTab) {
          el.removeAttribute("tabindex"); delete el.dataset.rappTab;
        }
      });
  }

  // Debounced: explorers and animations change the page many times a second.
  let timer = null;
  function update() {
    if (timer !== null) return;
    timer = setTimeout(() => {
      timer = null;
      nameTheme();
      nameWidgets(document);
      nameAnimations();
      readableColours(document);
      focusableScrollers();
      // The page check (scripts/check_book.py) runs axe-core once the page's names are given.
      document.documentElement.dataset.rappNamed = "1";
    }, 150);
  }
  function start() {
    update();
    new MutationObserver(update).observe(document.body, { childList: true, subtree: true, attributes: true, attributeFilter: ["src", "data-mode"] });
    window.addEventListener("resize", update);
    window.addEventListener("load", update);
  }
  // Math is typeset lazily as it comes into view (MathJax's ui/lazy, _config.yml), so that a
  // page's explorers answer sooner. A few seconds after the page has loaded (its widgets are
  // drawn by then), the rest is typeset a few formulas at a time while the main thread is idle
  // (a reader's key press or drag goes first), so that screen readers and find in page see
  // every formula; printing typesets all at once (MathJax does).
  const TYPESET_BATCH = 20;
  const TYPESET_REST_AFTER_MS = 3000;

  function lazyDocument() {  // MathJax's lazy document once MathJax has started, or null
    const mj = window.MathJax;
    if (!mj || !mj.startup || !mj.startup.promise) return Promise.resolve(null);
    return mj.startup.promise.then(() => {
      const doc = mj.startup.document;
      return doc && typeof doc.lazyTypesetAll === "function" ? doc : null;
    });
  }

  // A formula typeset above the reader grows the page above what they read. Browsers with CSS
  // scroll anchoring keep the text in place; without it (Safari before 26) the text would jump,
  // so its element is put back where it was.
  function anchoredByTheBrowser() {
    return getComputedStyle(document.scrollingElement || document.documentElement).overflowAnchor === "auto";
  }
  function readingAnchor() {
    if (window.scrollY < 1 || anchoredByTheBrowser()) return null;
    // The first element of the article below the theme's sticky bars.
    const bars = [...document.querySelectorAll(".bd-header, .bd-header-article")]
      .map((bar) => bar.getBoundingClientRect().bottom);
    const y = Math.max(0, ...bars) + 8;
    const hit = document.elementsFromPoint(window.innerWidth / 2, y).find((el) => el.closest(".bd-article"));
    if (!hit) return null;
    const el = hit.closest("p, li, pre, table, h1, h2, h3, h4, h5, h6, dt, dd, figure, div.math, .cell") || hit;
    return { el, y: el.getBoundingClientRect().top + window.scrollY };
  }
  function putBack(anchor) {
    if (!anchor || !anchor.el.isConnected) return;
    const drift = anchor.el.getBoundingClientRect().top + window.scrollY - anchor.y;
    if (Math.abs(drift) > 1) window.scrollBy(0, drift);
  }

  function typesetTheRest() {
    lazyDocument().then((doc) => {
      if (!doc) return;
      const idle = window.requestIdleCallback || ((f) => setTimeout(f, 50));
      // MathJax 3.2's lazy document: lazySet holds the ids to typeset next, lazyHandleSet
      // typesets them after lazyPromise; without them (another version), all at once.
      if (!(doc.lazySet instanceof Set) || typeof doc.lazyHandleSet !== "function" || !doc.lazyPromise) {
        idle(() => { const anchor = readingAnchor(); doc.lazyTypesetAll().then(() => putBack(anchor)); });
        return;
      }
      const step = () => {
        const ids = [...document.querySelectorAll("mjx-lazy[data-mjx-lazy]")]
          .slice(0, TYPESET_BATCH).map((el) => el.getAttribute("data-mjx-lazy"));
        if (!ids.length) return;
        const anchor = readingAnchor();
        ids.forEach((id) => doc.lazySet.add(id));
        doc.lazyHandleSet();
        doc.lazyPromise.then(() => { putBack(anchor); idle(step, { timeout: 100 }); });
      };
      idle(step, { timeout: 100 });
    });
  }

  // A jump to a #fragment (an equation's or a section's link) lands before the formulas around
  // it are typeset: everything is typeset at once, then the page jumps again to the target,
  // unless the reader has moved on meanwhile.
  let readerMoved = false;
  ["wheel", "touchmove", "keydown"].forEach((type) =>
    window.addEventListener(type, () => { readerMoved = true; }, { passive: true, capture: true }));
  function settleJump() {
    const id = decodeURIComponent(window.location.hash.slice(1));
    const target = id && document.getElementById(id);
    if (!target) return;
    readerMoved = false;
    lazyDocument()
      .then((doc) => doc && doc.lazyTypesetAll())
      .then(() => { if (!readerMoved && target.isConnected) target.scrollIntoView(); });
  }
  window.addEventListener("hashchange", settleJump);
  window.addEventListener("load", () => {
    settleJump();
    setTimeout(typesetTheRest, TYPESET_REST_AFTER_MS);
  });

  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", start);
  else start();
})();
