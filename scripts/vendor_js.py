"""Copy the book's JavaScript and CSS from node_modules/ into book/_static_vendor/offline/.

The book must render offline: MathJax 3 (typesetting), RequireJS and the
ipywidgets HTML manager (saved widget views) and anywidget's front end (rapp's live
explorers) are served from the book itself
instead of CDNs, and so is the Font Awesome CSS of matplotlib's animation controls; axe-core,
which scripts/check_book.py injects to check every page's accessibility, comes along. `npm ci` installs the versions pinned in package-lock.json;
this script copies only the files a browser loads. _config.yml lists
book/_static_vendor in html_static_path, so Sphinx copies it to
_build/html/_static/offline/.

Usage: python scripts/vendor_js.py   (run from anywhere; paths are repo-relative)
"""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
NODE = ROOT / "node_modules"
DEST = ROOT / "book" / "_static_vendor" / "offline"

# (source under node_modules, destination under DEST); directories are copied whole.
MANIFEST = [
    # tex-chtml loads TeX extensions (autoload), its woff fonts, and the menu's
    # accessibility parts from paths relative to itself, so those come along.
    ("mathjax/es5/tex-chtml.js", "mathjax/tex-chtml.js"),
    ("mathjax/es5/input/tex/extensions", "mathjax/input/tex/extensions"),
    ("mathjax/es5/output/chtml/fonts/woff-v2", "mathjax/output/chtml/fonts/woff-v2"),
    ("mathjax/es5/a11y", "mathjax/a11y"),
    ("mathjax/es5/ui", "mathjax/ui"),
    ("mathjax/es5/sre", "mathjax/sre"),
    ("mathjax/LICENSE", "mathjax/LICENSE"),
    ("requirejs/require.js", "require.js"),
    # embed-amd.js bundles @jupyter-widgets/base, controls and output; the
    # hashed font files are the icon fonts its CSS refers to.
    ("@jupyter-widgets/html-manager/dist/embed-amd.js", "html-manager/embed-amd.js"),
    # matplotlib's to_jshtml() links Font Awesome 4 from a CDN for its animation buttons;
    # book/_ext/offline_assets.py points that link here.
    ("font-awesome/css/font-awesome.min.css", "font-awesome/css/font-awesome.min.css"),
    ("font-awesome/fonts", "font-awesome/fonts"),
    # axe-core, the accessibility engine scripts/check_book.py injects into every page (WCAG 2.1
    # A/AA rules); no page of the book loads it.
    ("axe-core/axe.min.js", "axe-core/axe.min.js"),
    ("axe-core/LICENSE", "axe-core/LICENSE"),
]
FONT_SUFFIXES = (".woff2", ".woff", ".ttf", ".eot", ".svg")

# The HTML manager finds its icon fonts relative to the RequireJS URL of its own module; by
# default that is the page's folder. Loaded between require.js and embed-amd.js
# (nb_ipywidgets_js in _config.yml), this points the module at the vendored copy, whatever the
# depth of the page.
REQUIRE_CONFIG = """\
// Written by scripts/vendor_js.py: map the widget manager's AMD modules to this folder.
(function () {
  var here = document.currentScript.src.replace(/[^/]*$/, "");
  require.config({ paths: {
    "@jupyter-widgets/html-manager/dist": here + "html-manager",
    // anywidget's front end (the AMD build its Python package ships), for rapp's live explorers.
    "anywidget": here + "anywidget/index"
  } });
})();
"""


def anywidget_amd() -> Path | None:
    """anywidget's AMD front end, from the anywidget Python package pinned in environment.txt.

    Its npm package ships ES modules only; the Python wheel carries the AMD build that the
    classic notebook (and so the ipywidgets HTML manager, through RequireJS) loads. Looked up in
    the interpreter running this script, then in the repository's .venv.
    """
    try:
        import anywidget  # noqa: F401  (only its location is needed)

        found = Path(anywidget.__file__).parent / "nbextension" / "index.js"
        if found.is_file():
            return found
    except ImportError:
        pass
    for found in sorted(ROOT.glob(".venv/lib/python3*/site-packages/anywidget/nbextension/index.js")):
        return found
    return None


def main() -> int:
    if not NODE.is_dir():
        print(f"vendor_js: {NODE} is missing; run `npm ci` first", file=sys.stderr)
        return 1
    if DEST.exists():
        shutil.rmtree(DEST)
    DEST.mkdir(parents=True)
    missing = []
    for src_rel, dst_rel in MANIFEST:
        src, dst = NODE / src_rel, DEST / dst_rel
        if not src.exists():
            missing.append(src_rel)
            continue
        dst.parent.mkdir(parents=True, exist_ok=True)
        if src.is_dir():
            shutil.copytree(src, dst)
        else:
            shutil.copy2(src, dst)
    dist = NODE / "@jupyter-widgets/html-manager/dist"
    for font in sorted(dist.glob("*")) if dist.is_dir() else []:
        if font.suffix in FONT_SUFFIXES:
            shutil.copy2(font, DEST / "html-manager" / font.name)
    amd = anywidget_amd()
    if amd is None:
        missing.append("anywidget (pip install -r environment.txt)")
    else:
        (DEST / "anywidget").mkdir(parents=True, exist_ok=True)
        shutil.copy2(amd, DEST / "anywidget" / "index.js")
    (DEST / "require-config.js").write_text(REQUIRE_CONFIG, encoding="utf-8")
    if missing:
        print("vendor_js: missing in node_modules: " + ", ".join(missing), file=sys.stderr)
        return 1
    n = sum(1 for p in DEST.rglob("*") if p.is_file())
    print(f"vendor_js: {n} files in {DEST.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
