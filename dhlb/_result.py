"""The base of every application's result: a summary, a file, a picture — without importing the layers above.

A result (:class:`~dhlb.fields.DirectionField`, :class:`~dhlb.stripes.StripePattern`,
:class:`~dhlb.vortex.VortexResult`, :class:`~dhlb.conformal.ConformalResult`) derives from
:class:`Result` and implements two methods:

``to_json() -> dict``
    A JSON-ready summary (plain numbers, lists and strings).
``summary_rows() -> list[tuple[str, object]]``
    The headline numbers, as ``(label, value)`` pairs (the table of ``dhlb`` commands and notebooks).

The base turns them into ``save(path)`` (format chosen by the extension), ``show()`` (polyscope, or
an interactive view inline in a notebook with ``backend="web"``), ``to_html(path)`` (a page with the
interactive view) and ``_repr_png_`` / ``_repr_html_`` (what Jupyter displays when a result ends a
cell: the PNG picture, or the interactive view after :func:`set_notebook_display` ``("web")``).
Writing files is the io layer's job and pictures are the render layer's, both *above* the
applications; so the base finds them at call time through the entry-point group ``dhlb.plugins``
(names ``write``, ``picture``, ``show``, ``html``, ``web``; the pattern of pandas' plotting
backends), which the package declares for its own :func:`dhlb.io.results.write` and
:mod:`dhlb.render.registry`. Another package may declare its own.

Examples
--------
>>> class Answer(Result):
...     def to_json(self):
...         return {"answer": 42}
...     def summary_rows(self):
...         return [("answer", 42)]
>>> "<th style='text-align:left'>answer</th><td>42</td>" in Answer()._summary_table()
True
"""

from __future__ import annotations

import importlib
import os

__all__ = ["PICTURE_SIZE", "Result", "plugin", "set_notebook_display"]

PICTURE_SIZE = (320, 320)
"""Pixels of the notebook picture."""

_DEFAULTS = {
    "write": "dhlb.io.results:write",
    "picture": "dhlb.render.registry:picture",
    "show": "dhlb.render.registry:show",
    "html": "dhlb.render.registry:to_html",
    "web": "dhlb.render.registry:web_view",
}
_CACHE: dict[str, object] = {}
_DISPLAY = {"notebook": "png"}


def set_notebook_display(kind: str) -> str:
    """What a result shows when it ends a notebook cell: ``"png"`` (default) or ``"web"`` (interactive).

    ``"web"`` needs plotly (``pip install "dhlb[web]"``); without it the PNG picture is shown.

    Parameters
    ----------
    kind : {"png", "web"}

    Returns
    -------
    str
        The previous setting.

    Raises
    ------
    ValueError
        Another kind.

    Examples
    --------
    >>> old = set_notebook_display("web")
    >>> set_notebook_display(old)
    'web'
    """
    if kind not in ("png", "web"):
        raise ValueError(f"the notebook display is 'png' or 'web', got {kind!r}")
    old, _DISPLAY["notebook"] = _DISPLAY["notebook"], kind
    return old


def plugin(name: str):
    """The function registered for ``name`` in the entry-point group ``dhlb.plugins`` (default: dhlb's own).

    Parameters
    ----------
    name : {"write", "picture", "show"}
        What the result asks for: write a file, draw a picture, open the viewer.

    Returns
    -------
    callable
        ``write(result, path) -> list[str]``, ``picture(result, path, size) -> str`` or
        ``show(result, **kwargs)``.

    Raises
    ------
    KeyError
        ``name`` is not one of the three.
    """
    if name not in _CACHE:
        target = _DEFAULTS[name]
        try:
            from importlib.metadata import entry_points

            found = [ep for ep in entry_points(group="dhlb.plugins") if ep.name == name]
        except Exception:  # pragma: no cover - broken metadata: fall back to dhlb's own
            found = []
        if found:
            _CACHE[name] = found[0].load()
        else:  # running from a source tree without installed metadata
            module, attr = target.split(":")
            _CACHE[name] = getattr(importlib.import_module(module), attr)
    return _CACHE[name]


def mark_read_from(result, paths) -> None:
    """Remember the files ``result`` was read from: ``save`` and ``to_html`` never write over them.

    Parameters
    ----------
    result : Result
        A result made by a reader (:func:`dhlb.io.read_result`); frozen dataclasses included.
    paths : iterable of str or path-like
        The files read (missing ones are ignored when compared).

    Examples
    --------
    >>> class R(Result):
    ...     pass
    >>> r = R(); mark_read_from(r, ["a.npz", "a.json"]); r._read_from
    ('a.npz', 'a.json')
    """
    object.__setattr__(result, "_read_from", tuple(os.fspath(p) for p in paths if p))


class Result:
    """Base of the applications' results: ``to_json``, ``summary_rows``, ``save``, ``show`` and notebook display."""

    _read_from: tuple = ()   # the files a reader made this result from: the writers never replace them

    def to_json(self) -> dict:  # pragma: no cover - each result has its own
        """A JSON-ready summary of the result.

        Returns
        -------
        dict
            Plain numbers, lists and strings (``json.dumps`` accepts it).
        """
        raise NotImplementedError

    def summary_rows(self) -> list[tuple[str, object]]:  # pragma: no cover - each result has its own
        """The headline numbers of the result.

        Returns
        -------
        list of (str, object)
            ``(label, value)`` pairs.
        """
        raise NotImplementedError

    def save(self, path: str | os.PathLike[str]) -> list[str]:
        """Write the result to ``path``; the extension chooses the format (see :func:`dhlb.io.results.write`).

        Parameters
        ----------
        path : str or path-like
            ``.json`` (every result) or a format of the result's kind (``.npz``, ``.ply``, ``.obj``,
            ``.vtu``, ``.mesh``, ...).

        Returns
        -------
        list of str
            The paths written (atomically; an input file is never replaced).

        Raises
        ------
        InvalidParameterError
            An extension this kind of result cannot be written as (the message lists those it can).
        OutputError
            The file cannot be written.
        OverwriteError
            ``path`` is a file this result was read from.
        """
        return plugin("write")(self, path)

    def show(self, *, backend: str = "polyscope", screenshot=None, **kwargs):
        """Show the result: in polyscope (``dhlb[view]``), or inline in a notebook (``backend="web"``, ``dhlb[web]``).

        Parameters
        ----------
        backend : {"polyscope", "web"}
            ``"polyscope"``: a window, or a PNG rendered headless to ``screenshot``. ``"web"``: an
            interactive view that Jupyter displays inline (rotate, zoom, hover); without plotly the
            PNG picture, with a note naming the extra.
        screenshot : str, optional
            polyscope: render headless to this PNG instead of opening a window.
        **kwargs
            Passed to :func:`dhlb.render.view.show` or :func:`dhlb.render.web.notebook_view`.

        Returns
        -------
        str, None or WebView
            The screenshot path, None after the window was closed, or the view to display.

        Raises
        ------
        ImportError, ViewerUnavailableError
            polyscope, or a display / EGL for a screenshot, is missing (the message says what to install).
        """
        return plugin("show")(self, backend=backend, screenshot=screenshot, **kwargs)

    def to_html(self, path: str | os.PathLike[str], **kwargs) -> str:
        """Write a page with the interactive 3-D view of the result; it opens offline (``dhlb[web]``).

        Parameters
        ----------
        path : str or path-like
            The HTML file (written atomically).
        **kwargs
            Passed to :func:`dhlb.render.web.to_html` (``plotlyjs="inline"`` or ``"directory"``,
            ``camera``, ``title``, ...).

        Returns
        -------
        str
            The path written.

        Raises
        ------
        ImportError
            plotly is not installed (the message names the extra).
        OverwriteError
            ``path`` is a file this result was read from.
        """
        return plugin("html")(self, path, **kwargs)

    def _repr_png_(self) -> bytes:
        """A small picture for notebooks."""
        import tempfile

        with tempfile.TemporaryDirectory() as d:
            path = plugin("picture")(self, os.path.join(d, "result.png"), PICTURE_SIZE)
            with open(path, "rb") as fh:
                return fh.read()

    def _summary_table(self) -> str:
        import html

        return "".join(f"<tr><th style='text-align:left'>{html.escape(str(k))}</th><td>{html.escape(str(v))}</td></tr>"
                       for k, v in self.summary_rows())

    def _repr_html_(self) -> str:
        """The picture of :meth:`_repr_png_` (or the interactive view) beside a table of the summary numbers."""
        import base64

        if _DISPLAY["notebook"] == "web":
            view = plugin("web")(self)
            if view is not None:  # None: plotly is missing, the picture instead
                return f"<div>{view}<table>{self._summary_table()}</table></div>"
        png = base64.b64encode(self._repr_png_()).decode("ascii")
        return (f"<div style='display:flex;gap:1em;align-items:center'><img src='data:image/png;base64,{png}' "
                f"width='{PICTURE_SIZE[0]}'/><table>{self._summary_table()}</table></div>")
