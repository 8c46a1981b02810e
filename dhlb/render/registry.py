"""How each kind of result is drawn: :func:`picture` (a PNG), :func:`show` (polyscope or web), :func:`to_html`.

The results of the applications find these functions at call time (``Result._repr_png_``,
``Result.show``, ``Result.to_html``, ``Result._repr_html_`` through :func:`web_view`; see
:mod:`dhlb._result`), so that no application imports the render layer.
A new kind of result registers its picture with ``@picture.register``. A result read back from its
files (:func:`dhlb.io.read_result`) draws through the same function as the result that was written.

Examples
--------
>>> import os, tempfile
>>> from dhlb.io import example_path, read_surface
>>> from dhlb.fields import direction_field
>>> res = direction_field(*read_surface(example_path("torus.obj")), n=4)
>>> with tempfile.TemporaryDirectory() as d:
...     path = picture(res, os.path.join(d, "f.png"), (160, 160))
...     os.path.getsize(path) > 1000
True
"""

from __future__ import annotations

import functools
import os

from dhlb._install import install_hint
from dhlb.conformal.result import ConformalResult
from dhlb.errors import InvalidParameterError
from dhlb.fields.result import DirectionField
from dhlb.io.polylines import LoadedVortex
from dhlb.io.stripes import LoadedStripes
from dhlb.io.volume import LoadedConformal
from dhlb.stripes.result import StripePattern
from dhlb.vortex.result import VortexResult

__all__ = ["picture", "show", "to_html", "web_view"]


@functools.singledispatch
def picture(result, path: str | os.PathLike[str], size: tuple[int, int] = (320, 320)) -> str:
    """Draw ``result`` into the PNG ``path`` (the picture notebooks show) and return the path.

    Parameters
    ----------
    result : DirectionField, StripePattern, VortexResult or ConformalResult
        A result of one of the applications, or one read back by :func:`dhlb.io.read_result`.
    path : str or path-like
        The PNG to write (atomically).
    size : (int, int)
        Pixels, width × height.

    Returns
    -------
    str
        ``path``.

    Raises
    ------
    InvalidParameterError
        No picture is registered for this kind of object.
    """
    raise InvalidParameterError(f"no picture is registered for a {type(result).__name__}; register one with "
                                "@dhlb.render.registry.picture.register")


@picture.register
def _(result: DirectionField, path, size=(320, 320)) -> str:
    from dhlb.render import Camera, FieldStyle, render_field_png

    return render_field_png(path, result.mesh.points, result.mesh.faces, result.directions, result.singularities,
                            camera=Camera(size=size), style=FieldStyle(max_glyphs=4000))


@picture.register(StripePattern)
@picture.register(LoadedStripes)
def _(result, path, size=(320, 320)) -> str:
    from dhlb.render import Camera, StripeStyle, render_stripes_png

    return render_stripes_png(path, result.texture, camera=Camera(size=size),
                              style=StripeStyle(mark_singularities=True, max_triangles=150_000))


@picture.register(VortexResult)
@picture.register(LoadedVortex)
def _(result, path, size=(320, 320)) -> str:
    import dataclasses

    from dhlb.render import FILAMENT_CAMERA, render_filaments_png
    from dhlb.render._figure import plural

    mesh = result.mesh  # None: curves read back without their domain
    return render_filaments_png(path, result.filaments, None if mesh is None else mesh.points,
                                None if mesh is None else mesh.boundary_faces,
                                title=plural(len(result.filaments), "filament"),
                                camera=dataclasses.replace(FILAMENT_CAMERA, size=size))


@picture.register(ConformalResult)
@picture.register(LoadedConformal)
def _(result, path, size=(320, 320)) -> str:
    import dataclasses

    from dhlb.render import CONFORMAL_CAMERA, boundary_distortion, render_conformal_png

    if not getattr(result, "input_known", True):
        raise InvalidParameterError("this conformal deformation was read back without its input mesh: there is no "
                                    "'before' to draw (keep the input mesh beside the output, or save the .npz)")
    F, dF = boundary_distortion(result)
    return render_conformal_png(path, result.mesh.points, result.points, F, dF,
                                camera=dataclasses.replace(CONFORMAL_CAMERA, size=size))


def show(result, *, backend: str = "polyscope", screenshot=None, **kwargs):
    """Show ``result`` in polyscope (or render it headless to ``screenshot``), or inline in a notebook.

    Parameters
    ----------
    result : DirectionField, StripePattern, VortexResult, ConformalResult or Scene
        What to show (or a result of :func:`dhlb.io.read_result`).
    backend : {"polyscope", "web"}
        ``"polyscope"``: :func:`dhlb.render.view.show`. ``"web"``: a :class:`WebView` that Jupyter
        displays inline (:func:`dhlb.render.web.notebook_view`); without plotly it displays the PNG
        picture with a note naming the extra ``dhlb[web]``.
    screenshot : str, optional
        polyscope: a PNG to render to instead of opening a window.
    **kwargs
        ``view``, ``size``, ``isolines`` of :func:`dhlb.render.view.show`; ``height``, ``camera``,
        ``isolines`` of :func:`dhlb.render.web.notebook_view`.

    Returns
    -------
    str, None or WebView
        The screenshot path, None after the window was closed, or the view to display.

    Raises
    ------
    InvalidParameterError
        An unknown backend, or a screenshot asked of the web view.
    """
    if backend == "web":
        if screenshot is not None:
            raise InvalidParameterError("the web view draws in the browser: write a page with "
                                        "result.to_html(path), or use backend='polyscope' for a screenshot")
        return WebView(result, **kwargs)
    if backend != "polyscope":
        raise InvalidParameterError(f"backend must be 'polyscope' or 'web', got {backend!r}")
    from dhlb.render.view import show as _show

    return _show(result, screenshot=screenshot, **kwargs)


def to_html(result, path: str | os.PathLike[str], **kwargs) -> str:
    """Write a page with the interactive view of ``result`` (:func:`dhlb.render.web.to_html`).

    Parameters
    ----------
    result : a result, a result read back, or a Scene
    path : str or path-like
    **kwargs
        Of :func:`dhlb.render.web.to_html`.

    Returns
    -------
    str
        The path written.

    Raises
    ------
    OverwriteError
        ``path`` is a file the result was read from (:func:`dhlb._result.mark_read_from`).
    """
    from dhlb._files import refuse_overwrite
    from dhlb.render.web import to_html as _to_html

    refuse_overwrite([path], getattr(result, "_read_from", ()), role="a file this result was read from")
    return _to_html(result, path, **kwargs)


def web_view(result, **kwargs) -> str | None:
    """The notebook HTML of the interactive view of ``result``, or None when plotly is missing.

    Parameters
    ----------
    result : a result, a result read back, or a Scene
    **kwargs
        Of :func:`dhlb.render.web.notebook_view`.

    Returns
    -------
    str or None
    """
    from dhlb.render.web import notebook_view

    try:
        return notebook_view(result, **kwargs)
    except ImportError:
        return None


class WebView:
    """What ``result.show(backend="web")`` returns: Jupyter displays it inline as an interactive view.

    Without plotly it displays the result's PNG picture (``Result._repr_png_``) and a note naming the
    extra ``dhlb[web]``; a Scene, which has no picture, then raises the ``ImportError``.

    Parameters
    ----------
    result : a result, a result read back, or a Scene
    **kwargs
        Of :func:`dhlb.render.web.notebook_view` (``height``, ``camera``, ``isolines``, ...).

    Attributes
    ----------
    interactive : bool
        Whether plotly was there to draw the interactive view.

    Raises
    ------
    ImportError
        plotly is missing and ``result`` has no PNG picture to fall back to (a Scene).
    """

    def __init__(self, result, **kwargs):
        self.result = result
        self.html = web_view(result, **kwargs)
        self.interactive = self.html is not None
        if not self.interactive and not hasattr(result, "_repr_png_"):
            from dhlb.render.web import WEB_EXTRA

            raise ImportError(WEB_EXTRA)

    def save(self, path: str | os.PathLike[str], **kwargs) -> str:
        """Write the view as a page that opens offline (:func:`dhlb.render.web.to_html`); return its path.

        Parameters
        ----------
        path : str or path-like
        **kwargs
            Of :func:`dhlb.render.web.to_html`.

        Returns
        -------
        str
        """
        return to_html(self.result, path, **kwargs)

    def open(self) -> str:
        """Outside a notebook: write the page into a temporary folder and open it in the web browser.

        Returns
        -------
        str
            The page's path (it stays until the system cleans its temporary folder).

        Raises
        ------
        ViewerUnavailableError
            No web browser can be started here (write the page with :meth:`save` and open it elsewhere).
        """
        import tempfile
        import webbrowser

        from dhlb.errors import ViewerUnavailableError

        page = self.save(os.path.join(tempfile.mkdtemp(prefix="dhlb-view-"), "view.html"))
        if not webbrowser.open("file://" + os.path.abspath(page)):
            raise ViewerUnavailableError(f"no web browser could be started here; the page is {page}: copy it to a "
                                         "machine with a browser, or write it where you like with .save(path)")
        return page

    def _repr_mimebundle_(self, include=None, exclude=None):
        if self.interactive:
            return {"text/html": self.html}
        import base64

        png = self.result._repr_png_()
        note = f"for an interactive view: {install_hint('plotly', 'web')}"
        img = base64.b64encode(png).decode("ascii")
        return {"image/png": png, "text/html": f"<img src='data:image/png;base64,{img}'/><p><small>{note}</small></p>",
                "text/plain": f"<picture of the result; {note}>"}

    def __repr__(self) -> str:
        kind = "interactive view" if self.interactive else "picture (plotly is missing)"
        return (f"<WebView: {kind} of a {type(self.result).__name__}; Jupyter displays it, .open() shows it in "
                "a web browser, .save(path) writes the page>")
