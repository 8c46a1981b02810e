"""How each kind of result is drawn: :func:`picture` (a PNG) and :func:`show` (polyscope), one registry.

The results of the applications find these two functions at call time (``Result._repr_png_``,
``Result.show``; see :mod:`dhlb._result`), so that no application imports the render layer.
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

from dhlb.conformal.result import ConformalResult
from dhlb.errors import InvalidParameterError
from dhlb.fields.result import DirectionField
from dhlb.io.polylines import LoadedVortex
from dhlb.io.stripes import LoadedStripes
from dhlb.io.volume import LoadedConformal
from dhlb.stripes.result import StripePattern
from dhlb.vortex.result import VortexResult

__all__ = ["picture", "show"]


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

    mesh = result.mesh  # None: curves read back without their domain
    return render_filaments_png(path, result.filaments, None if mesh is None else mesh.points,
                                None if mesh is None else mesh.boundary_faces,
                                title=f"{len(result.filaments)} filament(s)",
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


def show(result, *, screenshot=None, **kwargs):
    """Show ``result`` in polyscope, or render it headless to ``screenshot`` (see :func:`dhlb.render.view.show`).

    Parameters
    ----------
    result : DirectionField, StripePattern, VortexResult, ConformalResult or Scene
        What to show (or a result of :func:`dhlb.io.read_result`).
    screenshot : str, optional
        A PNG to render to instead of opening a window.
    **kwargs
        ``view``, ``size``, ``isolines`` of :func:`dhlb.render.view.show`.

    Returns
    -------
    str or None
        The screenshot path, or None after the window was closed.
    """
    from dhlb.render.view import show as _show

    return _show(result, screenshot=screenshot, **kwargs)
