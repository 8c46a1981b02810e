"""What every picture of :mod:`dhlb.render` shares: a camera, a style, the matplotlib plumbing.

The :class:`Camera`, the style of each kind of picture (:class:`FieldStyle`, :class:`StripeStyle`,
:class:`FilamentStyle`, :class:`ConformalStyle`) and the matplotlib plumbing (an Agg figure without
pyplot state, framing, atomic PNG writing).

Examples
--------
>>> from dhlb.render import Camera
>>> right, up, toward = Camera(view=(0, 0, 1), up=(0, 1, 0)).frame()
>>> right.tolist(), up.tolist(), toward.tolist()
([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0])
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from dhlb.errors import InvalidParameterError

__all__ = ["Camera", "ConformalStyle", "FieldStyle", "FilamentStyle", "StripeStyle", "finish_figure"]

_CAMERA = ("view", "up", "size", "dpi")   # the keywords of dhlb 0.1 that moved into Camera


class _Replace:
    def replace(self, **changes: Any):
        """A copy with some fields changed (:func:`dataclasses.replace`; validated again).

        Parameters
        ----------
        **changes
            Field names and their new values.

        Returns
        -------
        The same class.

        Examples
        --------
        >>> from dhlb.render import Camera
        >>> Camera().replace(dpi=200).dpi
        200
        """
        return dataclasses.replace(self, **changes)


@dataclass(frozen=True)
class Camera(_Replace):
    """An orthographic camera and the picture it takes.

    Parameters
    ----------
    view : (3,) float
        Direction from the scene toward the camera (the camera looks at the scene's centre).
    up : (3,) float
        The world direction shown upward (replaced by a perpendicular axis when parallel to ``view``).
    size : (2,) int
        Width and height of the picture in pixels.
    dpi : int
        Pixels per inch of the PNG (scales the line widths, which are in points).

    Raises
    ------
    InvalidParameterError
        ``view`` is not a finite nonzero 3D direction.

    Examples
    --------
    >>> Camera(view=(0, 0, 0))
    Traceback (most recent call last):
    ...
    dhlb.errors.InvalidParameterError: view must be a nonzero 3D direction (camera position ...), got (0, 0, 0)
    """

    view: tuple[float, float, float] = (1.0, -1.6, 1.0)
    up: tuple[float, float, float] = (0.0, 0.0, 1.0)
    size: tuple[int, int] = (800, 800)
    dpi: int = 100

    def __post_init__(self) -> None:
        w = np.asarray(self.view, float).reshape(-1)
        if w.shape != (3,) or not np.all(np.isfinite(w)) or not np.any(w):
            raise InvalidParameterError("view must be a nonzero 3D direction (camera position relative to the mesh), "
                                        f"got {self.view!r}")

    def frame(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The orthonormal frame of the camera: screen right, screen up, toward the camera.

        Returns
        -------
        right, up, toward : (3,) float arrays

        Examples
        --------
        >>> [v.tolist() for v in Camera(view=(0, 0, 5), up=(0, 0, 1)).frame()]   # up ∥ view: y is up
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
        """
        w = _unit(np.asarray(self.view, float).reshape(-1))
        u = np.asarray(self.up, float).reshape(-1)
        if u.shape != (3,) or np.linalg.norm(np.cross(u, w)) < 1e-6 * np.linalg.norm(u):
            u = np.array([0.0, 1.0, 0.0]) if abs(w[1]) < 0.9 else np.array([1.0, 0.0, 0.0])
        right = _unit(np.cross(u, w))
        return right, np.cross(w, right), w


@dataclass(frozen=True)
class FieldStyle(_Replace):
    """How :func:`~dhlb.render.render_field_png` draws a direction field.

    Parameters
    ----------
    glyph_length : float, optional
        Length of a glyph in world units (default: 0.45 × mean edge length).
    glyph_width : float
        Line width of the glyphs in points.
    glyph_color, face_color, background : matplotlib colours
        Of the glyphs, of the (shaded) faces and of the picture.
    ambient : float in [0, 1]
        The light every face gets whatever its orientation (Lambert shading for the rest).
    max_glyphs : int
        At most this many vertices get glyphs (an evenly spread subset if there are more).
    dot_radius : float, optional
        Radius of a singularity dot (default: the larger of 0.35 × mean edge length and 0.6 % of the picture).

    Examples
    --------
    >>> FieldStyle(glyph_color="red").max_glyphs
    40000
    """

    glyph_length: float | None = None
    glyph_width: float = 0.7
    glyph_color: Any = "#1a1a1a"
    face_color: Any = (0.78, 0.80, 0.86)
    ambient: float = 0.3
    max_glyphs: int = 40000
    dot_radius: float | None = None
    background: Any = "white"


@dataclass(frozen=True)
class StripeStyle(_Replace):
    """How :func:`~dhlb.render.render_stripes_png` colours a stripe pattern.

    Parameters
    ----------
    dark, light : RGB colours
        Of ``fn(α) = −1`` and ``+1``.
    fn : callable
        The periodic profile (even for line fields).
    ambient : float in [0, 1]
        As in :class:`FieldStyle`.
    max_triangles : int
        Budget of sub-triangles for the automatic subdivision ``k``.
    mark_singularities : bool
        Dots at the zeros (red: index > 0, blue: < 0) and branch points (green).
    background : matplotlib colour

    Examples
    --------
    >>> StripeStyle(mark_singularities=True).ambient
    0.35
    """

    dark: Any = (0.10, 0.10, 0.14)
    light: Any = (0.96, 0.94, 0.88)
    fn: Callable[[np.ndarray], np.ndarray] = np.cos
    ambient: float = 0.35
    max_triangles: int = 400_000
    mark_singularities: bool = False
    background: Any = "white"


@dataclass(frozen=True)
class FilamentStyle(_Replace):
    """How :func:`~dhlb.render.render_filaments_png` draws filaments and their domain.

    Parameters
    ----------
    line_width : float
        Width of the filament lines in points.
    fill : matplotlib colour
        Of the domain's silhouette.
    outline_color : matplotlib colour
        Of the domain's contour and feature edges.
    background : matplotlib colour

    Examples
    --------
    >>> FilamentStyle(line_width=3.0).fill
    (0.9, 0.92, 0.95)
    """

    line_width: float = 2.2
    fill: Any = (0.90, 0.92, 0.95)
    outline_color: Any = "#5a6270"
    background: Any = "white"


@dataclass(frozen=True)
class ConformalStyle(_Replace):
    """How :func:`~dhlb.render.render_conformal_png` colours the distortion.

    Parameters
    ----------
    colormap : str
        A matplotlib colormap name (distortion 1 at its low end).
    background : matplotlib colour

    Examples
    --------
    >>> ConformalStyle().colormap
    'viridis'
    """

    colormap: str = "viridis"
    background: Any = "white"


def _matplotlib():
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.collections import PolyCollection
        from matplotlib.figure import Figure
    except ImportError:  # pragma: no cover - exercised only without matplotlib
        raise ImportError("dhlb.render needs matplotlib; install it with  pip install 'dhlb[viz]'  "
                          "(or pip install matplotlib)") from None
    return Figure, FigureCanvasAgg, PolyCollection


def _unit(x):
    n = np.linalg.norm(x, axis=-1, keepdims=True)
    return x / np.where(n > 0, n, 1.0)


def finish_figure(fig, ax, path, xy, aspect, title, dpi, background) -> str:
    """Frame the projected points ``xy`` with a small margin, add the title, write the PNG.

    Parameters
    ----------
    fig, ax : matplotlib Figure and Axes
    path : str or path-like
        The PNG file (written atomically).
    xy : (k, 2) float array
        The projected points to frame.
    aspect : float
        Width / height of the picture.
    title : str or None
    dpi : int
    background : matplotlib colour

    Returns
    -------
    str
        The path written.
    """
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    mid, half = (lo + hi) / 2, 0.53 * max((hi - lo).max(), 1e-12)
    ax.set_xlim(mid[0] - half * max(aspect, 1), mid[0] + half * max(aspect, 1))
    ax.set_ylim(mid[1] - half / min(aspect, 1), mid[1] + half / min(aspect, 1))
    if title:
        ax.text(0.02, 0.98, title, transform=ax.transAxes, va="top", ha="left", fontsize=10)
    return write_png(fig, path, dpi, background)


def write_png(fig, path, dpi, background) -> str:
    """Save ``fig`` as a PNG at ``path``; a failed or interrupted render leaves no half-written picture."""
    from dhlb._files import atomic_write

    out = os.fspath(path)
    with atomic_write(out, "wb") as fh:
        fig.savefig(fh, format="png", dpi=dpi, facecolor=background)
    return out
