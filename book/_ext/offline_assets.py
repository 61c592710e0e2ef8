"""Sphinx extension: point CDN links inside saved notebook outputs at vendored copies.

matplotlib's ``Animation.to_jshtml()`` writes a ``<link>`` to Font Awesome 4 on a CDN for its
play/step buttons; offline, the buttons would be blank squares. scripts/vendor_js.py copies
Font Awesome into ``_static/offline/font-awesome/``, and this extension rewrites the link in every
page's body to that copy (relative to the page, so the book works from file:// too).
"""

from __future__ import annotations

import re

# Any Font Awesome 4.x stylesheet on a CDN (matplotlib uses maxcdn 4.4.0).
FONT_AWESOME_CDN = re.compile(
    r"https?://[a-z0-9.\-]+/(?:ajax/libs/)?font-awesome/4\.[0-9.]+/css/font-awesome(?:\.min)?\.css"
)
LOCAL = "_static/offline/font-awesome/css/font-awesome.min.css"


def _rewrite(app, pagename, templatename, context, doctree):
    body = context.get("body")
    if body and "font-awesome" in body:
        context["body"] = FONT_AWESOME_CDN.sub(context["pathto"](LOCAL, 1), body)


def setup(app):
    app.connect("html-page-context", _rewrite)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1.0"}
