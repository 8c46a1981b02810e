"""A self-contained HTML page showing a set of pictures with one-line captions (no external resources).

A picture may come with an interactive view (a page of :func:`dhlb.render.web.to_html` beside it):
its card then has a button that puts the view in place of the picture, in an ``<iframe>``. At most
:data:`LIVE_VIEWS` views are live at once (a browser gives a page only so many WebGL contexts);
opening one more turns the oldest back into its picture.
"""

from __future__ import annotations

import html
import os
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from collections.abc import Sequence
    from typing import Any

__all__ = ["LIVE_VIEWS", "write_gallery"]

LIVE_VIEWS = 8
"""Interactive views live at once on a gallery page."""

_STYLE = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 1200px; color: #222; }
h1 { font-weight: 600; }
.grid { display: grid; grid-template-columns: repeat(auto-fill, minmax(340px, 1fr)); gap: 1.2em; }
figure { margin: 0; border: 1px solid #ddd; border-radius: 6px; padding: 0.5em; background: #fafafa; }
figure img { width: 100%; height: auto; display: block; }
figcaption { font-size: 0.9em; margin-top: 0.4em; }
table { border-collapse: collapse; margin: 1em 0 2em; font-size: 0.9em; }
td, th { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: left; }
.frame { position: relative; }
iframe.dhlb-web-frame { width: 100%; aspect-ratio: 1 / 1; border: 0; display: block; }
button.dhlb-rotate { position: absolute; right: 0.4em; bottom: 0.4em; font-size: 0.85em; cursor: pointer;
  border: 1px solid #888; border-radius: 4px; background: rgba(255, 255, 255, 0.9); padding: 0.2em 0.6em; }
"""

_SCRIPT = """
(function () {
  var live = [];
  function still(card) {
    var frame = card.querySelector('iframe.dhlb-web-frame');
    if (frame) { frame.remove(); }
    card.querySelector('img').style.display = '';
    card.querySelector('button.dhlb-rotate').textContent = card.dataset.label;
    live = live.filter(function (c) { return c !== card; });
  }
  window.dhlbRotate = function (button) {
    var card = button.closest('.frame');
    if (card.querySelector('iframe.dhlb-web-frame')) { still(card); return; }
    if (live.length >= %d) { still(live[0]); }
    var frame = document.createElement('iframe');
    frame.className = 'dhlb-web-frame';
    frame.src = button.dataset.view;
    frame.title = 'interactive view';
    card.querySelector('img').style.display = 'none';
    card.insertBefore(frame, button);
    button.textContent = 'picture';
    live.push(card);
  };
})();
"""


def write_gallery(
    path: str | os.PathLike[str], title: str, pictures: Sequence[Any], *, table: Any = None, intro: str = ""
) -> str:
    """Write ``path`` (an HTML file) showing ``pictures`` = [(file, caption[, link[, view]]), ...].

    Picture files are referenced relative to the page's directory (they must lie beside it or
    below). ``link`` (or None) is a page the picture links to; ``view`` (or None) a page with the
    interactive view of the same result, which a button on the card puts in place of the picture.

    Parameters
    ----------
    path : str or path-like
        The HTML file (written atomically).
    title : str
        The page's title and heading.
    pictures : sequence of tuple
        ``(file, caption)``, ``(file, caption, link)`` or ``(file, caption, link, view)`` per picture.
    table : sequence of sequence, optional
        Rows of a table above the pictures (the first row is the header).
    intro : str, optional
        A paragraph under the heading.

    Returns
    -------
    str
        The path written.

    Examples
    --------
    >>> import os, tempfile
    >>> from dhlb.render.gallery import write_gallery
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = write_gallery(os.path.join(d, "index.html"), "demo", [(os.path.join(d, "a.png"), "a <b>")])
    ...     "a &lt;b&gt;" in open(p).read()
    True
    """
    base = os.path.dirname(os.path.abspath(path))
    parts = [f"<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
             f"<title>{html.escape(title)}</title>",
             f"<style>{_STYLE}</style>\n</head>\n<body>\n<h1>{html.escape(title)}</h1>"]
    if intro:
        parts.append(f"<p>{html.escape(intro)}</p>")
    if table:
        head, *rows = table
        parts.append("<table>\n<tr>" + "".join(f"<th>{html.escape(str(c))}</th>" for c in head) + "</tr>")
        parts += ["<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in row) + "</tr>" for row in rows]
        parts.append("</table>")
    parts.append("<div class=\"grid\">")
    def rel(file):
        return html.escape(os.path.relpath(os.path.abspath(file), base).replace(os.sep, "/"))

    views = 0
    for file, caption, *more in pictures:
        link, view = (list(more) + [None, None])[:2]
        img = f"<img src=\"{rel(file)}\" alt=\"{html.escape(caption)}\">"
        if link:  # e.g. a page of views from several angles
            img = f"<a href=\"{rel(link)}\">{img}</a>"
        if view:
            views += 1
            label = "rotate in 3-D"
            img = (f"<div class=\"frame\" data-label=\"{label}\">{img}<button class=\"dhlb-rotate\" type=\"button\" "
                   f"data-view=\"{rel(view)}\" onclick=\"dhlbRotate(this)\">{label}</button></div>")
            caption_html = f"{html.escape(caption)} (<a href=\"{rel(view)}\">interactive view alone</a>)"
        else:
            caption_html = html.escape(caption)
        parts.append(f"<figure>{img}<figcaption>{caption_html}</figcaption></figure>")
    parts.append("</div>")
    if views:
        parts.append(f"<script>{_SCRIPT % LIVE_VIEWS}</script>")
    parts.append("</body>\n</html>\n")
    from dhlb._files import atomic_write

    with atomic_write(os.fspath(path)) as fh:
        fh.write("\n".join(parts))
    return str(path)
