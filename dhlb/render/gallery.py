"""A self-contained HTML page showing a set of pictures with one-line captions (no external resources)."""

from __future__ import annotations

import html
import os
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from collections.abc import Sequence
    from typing import Any

__all__ = ["write_gallery"]

_STYLE = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 1200px; color: #222; }
h1 { font-weight: 600; }
.grid { display: grid; grid-template-columns: repeat(auto-fill, minmax(340px, 1fr)); gap: 1.2em; }
figure { margin: 0; border: 1px solid #ddd; border-radius: 6px; padding: 0.5em; background: #fafafa; }
figure img { width: 100%; height: auto; display: block; }
figcaption { font-size: 0.9em; margin-top: 0.4em; }
table { border-collapse: collapse; margin: 1em 0 2em; font-size: 0.9em; }
td, th { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: left; }
"""


def write_gallery(
    path: str | os.PathLike[str], title: str, pictures: Sequence[Any], *, table: Any = None, intro: str = ""
) -> str:
    """Write ``path`` (an HTML file) showing ``pictures`` = [(file, caption), ...] or [(file, caption, link), ...].

    Picture files are referenced relative to the page's directory (they must lie beside it or
    below).

    Parameters
    ----------
    path : str or path-like
        The HTML file (written atomically).
    title : str
        The page's title and heading.
    pictures : sequence of tuple
        ``(file, caption)`` or ``(file, caption, link)`` per picture.
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
    for file, caption, *link in pictures:
        rel = os.path.relpath(os.path.abspath(file), base).replace(os.sep, "/")
        img = f"<img src=\"{html.escape(rel)}\" alt=\"{html.escape(caption)}\">"
        if link and link[0]:  # e.g. a page of views from several angles
            href = os.path.relpath(os.path.abspath(link[0]), base).replace(os.sep, "/")
            img = f"<a href=\"{html.escape(href)}\">{img}</a>"
        parts.append(f"<figure>{img}<figcaption>{html.escape(caption)}</figcaption></figure>")
    parts.append("</div>\n</body>\n</html>\n")
    with open(path, "w", encoding="utf-8") as fh:
        fh.write("\n".join(parts))
    return str(path)
