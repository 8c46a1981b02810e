"""How results present themselves: ``show()`` (polyscope), and a picture and a table in notebooks.

A result class mixes in :class:`Presentable` and implements two small hooks:

``_render_png(path, size)``
    Write a picture of the result to ``path`` with one of the :mod:`dhlb.render` functions and
    return the path.
``_summary_rows()``
    The summary numbers, as ``(label, value)`` pairs.

The mixin turns them into ``_repr_png_`` and ``_repr_html_`` (what Jupyter displays when a result
is the last expression of a cell) and ``show()``.  The render layer is imported only when a
picture is asked for, so the applications do not depend on it.

Examples
--------
>>> class Answer(Presentable):
...     def _summary_rows(self):
...         return [("answer", 42)]
>>> "<th style='text-align:left'>answer</th><td>42</td>" in Answer()._summary_table()
True
"""

from __future__ import annotations

__all__ = ["Presentable"]

PICTURE_SIZE = (320, 320)
"""Pixels of the notebook picture."""


class Presentable:
    """Mixin: ``show()``, ``_repr_png_`` and ``_repr_html_`` from ``_render_png`` and ``_summary_rows``."""

    def _render_png(self, path: str, size: tuple[int, int]) -> str:  # pragma: no cover - each result has its own
        raise NotImplementedError

    def _summary_rows(self) -> list[tuple[str, object]]:  # pragma: no cover - each result has its own
        raise NotImplementedError

    def show(self, *, screenshot=None, **kwargs):
        """Show the result in polyscope (``pip install 'dhlb[view]'``), or render it to ``screenshot`` (PNG).

        See :func:`dhlb.render.view.show`; raises ``ImportError`` or
        :class:`~dhlb.errors.ViewerUnavailableError` saying what is missing.
        """
        from dhlb.render.view import show

        return show(self, screenshot=screenshot, **kwargs)

    def _repr_png_(self) -> bytes:
        """A small picture for notebooks."""
        import os
        import tempfile

        with tempfile.TemporaryDirectory() as d:
            path = self._render_png(os.path.join(d, "result.png"), PICTURE_SIZE)
            with open(path, "rb") as fh:
                return fh.read()

    def _summary_table(self) -> str:
        import html

        return "".join(f"<tr><th style='text-align:left'>{html.escape(str(k))}</th><td>{html.escape(str(v))}</td></tr>"
                       for k, v in self._summary_rows())

    def _repr_html_(self) -> str:
        """The picture of :meth:`_repr_png_` beside a table of the summary numbers (notebooks)."""
        import base64

        png = base64.b64encode(self._repr_png_()).decode("ascii")
        return (f"<div style='display:flex;gap:1em;align-items:center'><img src='data:image/png;base64,{png}' "
                f"width='{PICTURE_SIZE[0]}'/><table>{self._summary_table()}</table></div>")
