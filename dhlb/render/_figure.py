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

__all__ = ["Camera", "ConformalStyle", "FieldStyle", "FilamentStyle", "StripeStyle", "finish_figure", "pixels_per_unit",
           "plural", "spread_sample", "thin_out", "up_vector"]

_CAMERA = ("view", "up", "size", "dpi")   # the keywords of dhlb 0.1 that moved into Camera

# ---- the one palette of the PNG pictures, the polyscope viewer and the web views
POSITIVE = (0.85, 0.12, 0.10)
"""Colour of singularities and zeros of positive index, in every picture and in the viewer."""
NEGATIVE = (0.10, 0.25, 0.85)
"""Colour of negative index."""
BRANCH = (0.10, 0.65, 0.25)
"""Colour of the branch points of a stripe pattern."""
FACE_COLOR = (0.78, 0.80, 0.86)
"""Colour of a surface without a quantity on it (shaded)."""
GLYPH_COLOR = (0.10, 0.10, 0.10)
"""Colour of the direction glyphs."""
STRIPE_DARK, STRIPE_LIGHT = (0.10, 0.10, 0.14), (0.96, 0.94, 0.88)
"""Colours of a stripe pattern at ``cos α = −1`` and ``+1``."""
FILAMENT_COLORS = ((0.839, 0.153, 0.157), (0.122, 0.467, 0.706), (0.173, 0.627, 0.173), (0.580, 0.404, 0.741),
                   (1.000, 0.498, 0.055), (0.090, 0.745, 0.812), (0.549, 0.337, 0.294), (0.890, 0.467, 0.761),
                   (0.498, 0.498, 0.498), (0.737, 0.741, 0.133))
"""One colour per filament (matplotlib's tab10 order), cycled."""
DOMAIN_COLOR, OUTLINE_COLOR = (0.90, 0.92, 0.95), (0.353, 0.384, 0.439)
"""The domain of vortex filaments (translucent or a silhouette) and its outline."""



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


def _check_style(style, spec: dict) -> None:
    """Check the fields of a style (``spec``: field → kind), with messages naming ``Class.field``.

    Kinds: ``"color"`` (a matplotlib colour), ``"positive"`` (a finite number > 0), ``"positive?"`` (that or
    None), ``"unit"`` (a number in [0, 1]), ``"count"`` (an integer >= 1), ``"flag"`` (a bool),
    ``"callable"``, ``"colormap"`` (a name of :data:`matplotlib.colormaps`).
    """
    import math

    from dhlb._deprecation import check_choice, check_flag, check_integer, check_number

    cls = type(style).__name__
    for field, kind in spec.items():
        value, name = getattr(style, field), f"{cls}.{field}"
        if kind == "color":
            from matplotlib.colors import is_color_like

            if isinstance(value, bool) or not is_color_like(value):
                raise InvalidParameterError(f"{name} must be a matplotlib colour (a name such as 'white', '#1f77b4' "
                                            f"or an RGB tuple of numbers in [0, 1]), got {value!r}")
        elif kind in ("positive", "positive?"):
            if not (kind == "positive?" and value is None):
                check_number(value, name, "a finite number > 0", lambda x: math.isfinite(x) and x > 0)
        elif kind == "unit":
            check_number(value, name, "a number in [0, 1]", lambda x: 0.0 <= x <= 1.0)
        elif kind == "count":
            check_integer(value, name, 1)
        elif kind == "flag":
            check_flag(value, name)
        elif kind == "callable":
            if not callable(value):
                raise InvalidParameterError(f"{name} must be a function of the angle (e.g. numpy.cos), got {value!r}")
        elif kind == "colormap":
            from matplotlib import colormaps

            if not isinstance(value, str):
                raise InvalidParameterError(f"{name} must be the name of a matplotlib colormap, got {value!r}")
            check_choice(value, name, sorted(colormaps))


PNG_BYTES_PER_PIXEL = 40
"""Peak bytes per pixel of drawing a picture (matplotlib's RGBA buffers and the PNG encoder; the budget of
``dhlb stripes --size``)."""


@dataclass(frozen=True)
class Camera(_Replace):
    """An orthographic camera and the picture it takes.

    By default it is **fitted** to what it shows (:meth:`fitted`, called by every renderer and by
    the viewer): upright with ``+y`` up — the convention of OBJ, PLY and OFF files, of polyscope
    and of libigl — looking at the model's side from slightly above: mostly along the thinner of
    its two horizontal extents, a little along the longer one (a three-quarter view of an animal,
    the length of a tube, the top of a flat patch). The picture frames the whole model.

    Parameters
    ----------
    view : (3,) float, optional
        Direction from the scene toward the camera (the camera looks at the scene's centre).
        Default: fitted to the points (see above).
    up : (3,) float or {"x", "y", "z", "-x", "-y", "-z"}, optional
        The world direction shown upward (default ``+y``; replaced by a perpendicular axis when
        parallel to ``view``).
    size : (2,) int
        Width and height of the picture in pixels, each an integer in 16 .. 8192 (the picture needs about
        :data:`PNG_BYTES_PER_PIXEL` bytes a pixel, checked against the memory available).
    dpi : int
        Pixels per inch of the PNG (scales the line widths, which are in points), an integer in 10 .. 2400.

    Raises
    ------
    InvalidParameterError
        ``view`` or ``up`` is not a finite nonzero 3D direction (or an axis name); ``size`` or ``dpi`` is not
        an integer in its range.
    ResourceLimitError
        The picture would need more memory than is available (the message says how much and the largest
        square picture that fits).

    Examples
    --------
    >>> Camera(view=(0, 0, 0))
    Traceback (most recent call last):
    ...
    dhlb.errors.InvalidParameterError: view must be a nonzero 3D direction (camera position ...), got (0, 0, 0)
    >>> import numpy as np
    >>> box = np.array([[0, 0, 0], [1, 0, 0], [0, 0.5, 0], [0, 0, 3.0]])   # long along z, thin along y
    >>> Camera().fitted(box).view                                          # from +x, above, a bit along z
    (0.8, 0.6, 0.32)
    """

    view: tuple[float, float, float] | None = None
    up: tuple[float, float, float] | str | None = None
    size: tuple[int, int] = (800, 800)
    dpi: int = 100

    def __post_init__(self) -> None:
        from dhlb._memory_errors import check_memory

        size = self.size
        if (not isinstance(size, (tuple, list)) or len(size) != 2
                or not all(isinstance(v, (int, np.integer)) and not isinstance(v, bool) and 16 <= v <= 8192
                           for v in size)):
            raise InvalidParameterError(f"Camera.size must be two integers (width, height) in 16 .. 8192 pixels, "
                                        f"got {size!r}")
        if not (isinstance(self.dpi, (int, np.integer)) and not isinstance(self.dpi, bool) and 10 <= self.dpi <= 2400):
            raise InvalidParameterError(f"Camera.dpi must be an integer in 10 .. 2400, got {self.dpi!r}")
        check_memory("size", tuple(int(v) for v in size), PNG_BYTES_PER_PIXEL * int(size[0]) * int(size[1]),
                     largest=lambda room: int((room / PNG_BYTES_PER_PIXEL) ** 0.5) or None,
                     advice=f"a picture takes about {PNG_BYTES_PER_PIXEL} bytes a pixel while it is drawn")
        if self.view is not None:
            w = np.asarray(self.view, float).reshape(-1)
            if w.shape != (3,) or not np.all(np.isfinite(w)) or not np.any(w):
                raise InvalidParameterError("view must be a nonzero 3D direction (camera position relative to the "
                                            f"mesh), got {self.view!r}")
        if self.up is not None:
            up_vector(self.up)

    def fitted(self, points) -> Camera:
        """A copy with ``view`` and ``up`` chosen for ``points`` where they are None.

        Parameters
        ----------
        points : (k, 3) float array
            What the picture shows (mesh vertices, curve points).

        Returns
        -------
        Camera
            ``up`` as given or ``+y``; ``view`` as given, or ``0.8 a + 0.32 b + 0.6 up`` with ``a``
            the thinner and ``b`` the longer of the two bounding-box axes perpendicular to ``up``
            (for a tilted ``up``: the principal axes of the points in its orthogonal plane).

        Examples
        --------
        >>> import numpy as np
        >>> Camera(up="z").fitted(np.eye(3)).up
        (0.0, 0.0, 1.0)
        """
        up = up_vector("y" if self.up is None else self.up)
        if self.view is not None:
            return dataclasses.replace(self, up=tuple(up.tolist()))
        P = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        P = P[np.all(np.isfinite(P), axis=1)]
        # the two horizontal axes: the coordinate axes perpendicular to a coordinate ``up``, else a basis
        axes = [np.eye(3)[i] for i in range(3) if abs(up[i]) < 1e-12]
        if len(axes) != 2:
            a = np.cross(up, [1.0, 0.0, 0.0] if abs(up[0]) < 0.9 else [0.0, 1.0, 0.0])
            axes = [a / np.linalg.norm(a), np.cross(up, a / np.linalg.norm(a))]
        extent = [float(np.ptp(P @ e)) if len(P) else 0.0 for e in axes]
        thin, long = (axes[0], axes[1]) if extent[0] <= extent[1] else (axes[1], axes[0])
        view = 0.8 * thin + 0.32 * long + 0.6 * up
        return dataclasses.replace(self, view=tuple(float(v) for v in np.round(view, 12)), up=tuple(up.tolist()))

    def behind(self, points) -> Camera:
        """The same camera walked around the model to its other side (turned by 180° about ``up``).

        The height above the model is kept (a view from above stays one), unlike negating ``view``.

        Parameters
        ----------
        points : (k, 3) float array
            What the picture shows (used when the view is still to be fitted).

        Returns
        -------
        Camera
            With ``view`` reflected in ``up``: ``2 (view · up) up − view`` (``−view`` when ``view ∥ up``).

        Examples
        --------
        >>> Camera(view=(1.0, 0.5, 0.0), up="y").behind(None).view
        (-1.0, 0.5, 0.0)
        """
        cam = self.fitted(points)
        v, u = np.asarray(cam.view, dtype=np.float64), up_vector(cam.up)
        back = 2.0 * (v @ u) * u - v
        if np.linalg.norm(np.cross(v, u)) < 1e-9 * np.linalg.norm(v):
            back = -v
        return dataclasses.replace(cam, view=tuple(float(x) for x in back))

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
        if self.view is None:
            raise InvalidParameterError("this camera has no view direction yet: call camera.fitted(points) first")
        w = _unit(np.asarray(self.view, float).reshape(-1))
        u = up_vector("y" if self.up is None else self.up)
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
        Length of a glyph in world units (default: 0.45 × mean edge length, or × the spacing of the glyphs
        when a fine mesh carries them on a subset of its vertices, :func:`dhlb.render.png.glyph_sites`).
    glyph_width : float
        Line width of the glyphs in points.
    glyph_color, face_color, background : matplotlib colours
        Of the glyphs, of the (shaded) faces and of the picture.
    ambient : float in [0, 1]
        The light every face gets whatever its orientation (Lambert shading for the rest).
    max_glyphs : int
        At most this many vertices get glyphs (an evenly spread subset if there are more, or if their
        vertices are closer than :data:`dhlb.render.png.GLYPH_SPACING` on the picture).
    dot_radius : float, optional
        Radius of a singularity dot (default: the larger of 0.35 × mean edge length and 0.6 % of the picture).

    Raises
    ------
    InvalidParameterError
        A field of the wrong kind or out of its range (the message names ``FieldStyle.field``).

    Examples
    --------
    >>> FieldStyle(glyph_color="red").max_glyphs
    40000
    """

    glyph_length: float | None = None
    glyph_width: float = 0.7
    glyph_color: Any = GLYPH_COLOR
    face_color: Any = FACE_COLOR
    ambient: float = 0.3
    max_glyphs: int = 40000
    dot_radius: float | None = None
    background: Any = "white"

    def __post_init__(self) -> None:
        _check_style(self, {'glyph_length': 'positive?', 'glyph_width': 'positive', 'glyph_color': 'color',
                            'face_color': 'color', 'ambient': 'unit', 'max_glyphs': 'count',
                            'dot_radius': 'positive?', 'background': 'color'})


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

    Raises
    ------
    InvalidParameterError
        A field of the wrong kind or out of its range (the message names ``StripeStyle.field``).

    Examples
    --------
    >>> StripeStyle(mark_singularities=True).ambient
    0.35
    """

    dark: Any = STRIPE_DARK
    light: Any = STRIPE_LIGHT
    fn: Callable[[np.ndarray], np.ndarray] = np.cos
    ambient: float = 0.35
    max_triangles: int = 400_000
    mark_singularities: bool = False
    background: Any = "white"

    def __post_init__(self) -> None:
        _check_style(self, {'dark': 'color', 'light': 'color', 'fn': 'callable', 'ambient': 'unit',
                            'max_triangles': 'count', 'mark_singularities': 'flag', 'background': 'color'})


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

    Raises
    ------
    InvalidParameterError
        A field of the wrong kind or out of its range (the message names ``FilamentStyle.field``).

    Examples
    --------
    >>> FilamentStyle(line_width=3.0).fill
    (0.9, 0.92, 0.95)
    """

    line_width: float = 2.2
    fill: Any = DOMAIN_COLOR
    outline_color: Any = OUTLINE_COLOR
    background: Any = "white"

    def __post_init__(self) -> None:
        _check_style(self, {'line_width': 'positive', 'fill': 'color', 'outline_color': 'color',
                            'background': 'color'})


@dataclass(frozen=True)
class ConformalStyle(_Replace):
    """How :func:`~dhlb.render.render_conformal_png` colours the distortion.

    Parameters
    ----------
    colormap : str
        A matplotlib colormap name (distortion 1 at its low end).
    background : matplotlib colour

    Raises
    ------
    InvalidParameterError
        A field of the wrong kind or out of its range (the message names ``ConformalStyle.field``).

    Examples
    --------
    >>> ConformalStyle().colormap
    'viridis'
    """

    colormap: str = "viridis"
    background: Any = "white"

    def __post_init__(self) -> None:
        _check_style(self, {'colormap': 'colormap', 'background': 'color'})


_AXES = {"x": 0, "y": 1, "z": 2}


def up_vector(up) -> np.ndarray:
    """The unit up direction of an axis name (``"y"``, ``"-z"``, ...) or a 3-vector.

    Parameters
    ----------
    up : str or (3,) float array

    Returns
    -------
    (3,) float array

    Raises
    ------
    InvalidParameterError
        Neither an axis name nor a finite nonzero 3-vector.

    Examples
    --------
    >>> up_vector("-z").tolist(), up_vector((0, 2, 0)).tolist()
    ([-0.0, -0.0, -1.0], [0.0, 1.0, 0.0])
    """
    if isinstance(up, str):
        name = up.strip().lower()
        sign, axis = (-1.0, name[1:]) if name.startswith("-") else (1.0, name.lstrip("+"))
        if axis not in _AXES:
            raise InvalidParameterError(f"up must be one of x, y, z, -x, -y, -z or a 3D direction, got {up!r}")
        return sign * np.eye(3)[_AXES[axis]]
    u = np.asarray(up, dtype=np.float64).reshape(-1)
    if u.shape != (3,) or not np.all(np.isfinite(u)) or not np.any(u):
        raise InvalidParameterError(f"up must be one of x, y, z, -x, -y, -z or a nonzero 3D direction, got {up!r}")
    return u / np.linalg.norm(u)


def _matplotlib():
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.collections import PolyCollection
        from matplotlib.figure import Figure
    except ImportError:  # pragma: no cover - exercised only without matplotlib
        raise ImportError("dhlb.render needs matplotlib, a dependency of dhlb: pip install matplotlib") from None
    return Figure, FigureCanvasAgg, PolyCollection


def mean_edge_length(V, F) -> float:
    """The mean length of the triangle sides of (V, F), each interior edge counted once per face (1.0 if no face).

    The unit of the glyphs of the viewer and the web views (0.45 of it).

    Examples
    --------
    >>> mean_edge_length(np.array([[0, 0, 0], [3, 0, 0], [0, 4, 0.0]]), np.array([[0, 1, 2]]))
    4.0
    """
    P, T = np.asarray(V, dtype=np.float64), np.asarray(F, dtype=np.int64)
    return float(np.linalg.norm(P[T[:, [1, 2, 0]]] - P[T], axis=2).mean()) if len(T) else 1.0


def _unit(x):
    n = np.linalg.norm(x, axis=-1, keepdims=True)
    return x / np.where(n > 0, n, 1.0)


def face_normals(P, T) -> np.ndarray:
    """``(p1 − p0) × (p2 − p0)`` per triangle of ``T`` (rows of ``P``): the normal of length twice the area.

    The one face-normal kernel of the pictures and views (:func:`_unit` of it for unit normals).

    Examples
    --------
    >>> face_normals(np.array([[0.0, 0, 0], [2, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]])).tolist()
    [[0.0, 0.0, 2.0]]
    """
    return np.cross(P[T[:, 1]] - P[T[:, 0]], P[T[:, 2]] - P[T[:, 0]])


TITLE_SIZE = 10
"""Font size of the title of a picture, in points."""


def plural(count: int, noun: str, nouns: str | None = None) -> str:
    """``count`` and ``noun``, in the plural unless the count is one: ``"1 filament"``, ``"2 filaments"``.

    Parameters
    ----------
    count : int
    noun : str
        The singular.
    nouns : str, optional
        The plural (default: ``noun + "s"``).

    Returns
    -------
    str

    Examples
    --------
    >>> plural(1, "filament"), plural(0, "filament"), plural(2, "branch face"), plural(3, "vertex", "vertices")
    ('1 filament', '0 filaments', '2 branch faces', '3 vertices')
    """
    return f"{count} {noun if count == 1 else (nouns or noun + 's')}"


def spread_sample(points, spacing: float) -> np.ndarray:
    """An evenly spread subset of ``points``: no two closer than ``spacing``, none left far from a chosen one.

    A Poisson-disk sample on a grid of cells of side ``spacing``: in each cell the point nearest its
    centre is a candidate, and a candidate is kept unless a kept candidate of a neighbouring cell is
    closer than ``spacing`` (the cells are visited in 8 interleaved groups, so that the candidates of
    one group cannot conflict with each other). Every point lies within ``(1 + √3) spacing`` of a
    kept one.

    Parameters
    ----------
    points : (k, d) float array
        d = 2 or 3.
    spacing : float
        The least distance between two chosen points (> 0).

    Returns
    -------
    (m,) int array
        Sorted rows of ``points``.

    Examples
    --------
    >>> import numpy as np
    >>> g = np.stack(np.meshgrid(np.arange(100.0), np.arange(100.0)), -1).reshape(-1, 2)   # 10 000 points
    >>> keep = spread_sample(g, 10.0)
    >>> 80 <= len(keep) <= 130
    True
    >>> from scipy.spatial.distance import pdist
    >>> bool(pdist(g[keep]).min() >= 10.0)
    True
    """
    P = np.asarray(points, dtype=np.float64)
    P = P.reshape(len(P), -1)
    if len(P) == 0 or not spacing > 0:
        return np.arange(len(P))
    d = P.shape[1]
    lo = P.min(axis=0)
    g = np.floor((P - lo) / spacing).astype(np.int64) + 1            # cells, with a free layer around them
    dims = g.max(axis=0) + 2
    strides = np.r_[np.cumprod(dims[::-1])[::-1][1:], 1]              # row-major cell keys
    key = g @ strides
    off_centre = np.linalg.norm(P - (lo + (g - 0.5) * spacing), axis=1)
    order = np.lexsort((off_centre, key))
    first = np.r_[True, key[order][1:] != key[order][:-1]]
    cand = order[first]                                              # one per cell, sorted by cell key
    ckey, cg = key[cand], g[cand]
    kept = np.zeros(len(cand), bool)
    offsets = np.array(np.meshgrid(*[[-1, 0, 1]] * d, indexing="ij")).reshape(d, -1).T
    offsets = offsets[np.any(offsets != 0, axis=1)] @ strides
    group = (cg % 2) @ (2 ** np.arange(d))
    for k in range(2 ** d):                                          # cells of one group are >= 2 cells apart
        rows = np.nonzero(group == k)[0]
        ok = np.ones(len(rows), bool)
        for off in offsets:
            at = np.searchsorted(ckey, ckey[rows] + off)
            at = np.minimum(at, len(ckey) - 1)
            hit = (ckey[at] == ckey[rows] + off) & kept[at]
            near = np.linalg.norm(P[cand[at[hit]]] - P[cand[rows[hit]]], axis=1) < spacing
            ok[np.nonzero(hit)[0][near]] = False
        kept[rows[ok]] = True
    return np.sort(cand[kept])


def thin_out(points, candidates, spacing: float, budget: int) -> tuple[np.ndarray, float]:
    """Evenly spread ``candidates`` (rows of ``points``) at least ``spacing`` apart, exactly ``budget`` if more remain.

    :func:`spread_sample` with ``spacing``; when more than ``budget`` sites remain, the spacing is
    widened (by bisection) to the widest that keeps at least ``budget``, and the sites with the
    nearest neighbours are dropped down to ``budget``: the glyph sites of the pictures and views on
    meshes too fine to carry a glyph at every vertex.

    Parameters
    ----------
    points : (N, d) float array
    candidates : (k,) int array
        Rows of ``points``.
    spacing : float
        The least distance between two sites (> 0).
    budget : int

    Returns
    -------
    sites : (m,) int array
        Rows of ``points``, ``m <= budget``.
    spacing : float
        The least distance between two sites (``spacing`` or wider).

    Examples
    --------
    >>> import numpy as np
    >>> X = np.random.default_rng(1).random((5000, 2))
    >>> sites, gap = thin_out(X, np.arange(5000), 0.01, 300)
    >>> len(sites), gap > 0.01
    (300, True)
    """
    candidates = np.asarray(candidates, dtype=np.int64)
    P = np.asarray(points, dtype=np.float64)[candidates]
    keep = spread_sample(P, spacing)
    if keep.size <= budget:
        return candidates[keep], float(spacing)
    lo, hi = float(spacing), float(spacing) * np.sqrt(keep.size / budget)
    while spread_sample(P, hi).size > budget:
        hi *= 1.5
    for _ in range(12):                                  # the widest spacing that keeps >= budget sites
        mid = np.sqrt(lo * hi)
        trial = spread_sample(P, mid)
        if trial.size >= budget:
            lo, keep = mid, trial
        else:
            hi = mid
        if keep.size == budget:
            break
    if keep.size > budget:                               # drop the most crowded sites
        from scipy.spatial import cKDTree

        gap = cKDTree(P[keep]).query(P[keep], k=2)[0][:, 1]
        keep = np.sort(keep[np.argsort(-gap, kind="stable")[:budget]])
    return candidates[keep], float(lo)


def _title_band(fig, title: str | None, dpi: int):
    """Write ``title`` at the top of ``fig`` (wrapped to its width); the share of the height it takes (0 without).

    The pictures draw below it, so that the title never covers what they show.
    """
    if not title:
        return 0.0
    import textwrap

    W, H = fig.get_size_inches() * dpi
    pad = 0.6 * TITLE_SIZE * dpi / 72.0                                # pixels above, below and left of it
    text = fig.text(pad / W, 1 - pad / H, title, va="top", ha="left", fontsize=TITLE_SIZE)
    renderer = fig.canvas.get_renderer()
    width = text.get_window_extent(renderer).width
    if width > W - 2 * pad:                                            # too long for one line: wrap it
        chars = max(8, int(len(title) * (W - 2 * pad) / width))
        text.set_text("\n".join(textwrap.wrap(title, chars, break_long_words=True)))
    return min((text.get_window_extent(renderer).height + 2 * pad) / H, 0.5)


FRAME_MARGIN = 0.53
"""Half-width of the frame of :func:`finish_figure` as a fraction of the drawing's extent (a 6 % margin)."""


def pixels_per_unit(xy, size) -> float:
    """Pixels per world unit of the framing of :func:`finish_figure` (without a title band) of the points ``xy``.

    Parameters
    ----------
    xy : (k, 2) float array
        The projected points.
    size : (int, int)
        The picture's width and height in pixels.

    Returns
    -------
    float

    Examples
    --------
    >>> round(pixels_per_unit([[0, 0], [1, 0.5]], (106, 106)), 6)     # the wider extent decides
    100.0
    """
    ext = np.maximum(np.ptp(np.asarray(xy, dtype=np.float64), axis=0), 1e-300)
    return float(min(size[0] / (2 * FRAME_MARGIN * ext[0]), size[1] / (2 * FRAME_MARGIN * ext[1])))


def finish_figure(fig, ax, path, xy, aspect, title, dpi, background) -> str:
    """Frame the projected points ``xy`` with a small margin below the title, write the PNG.

    The title (if any) takes a band at the top of the picture (:func:`_title_band`) and the points
    are framed in the rest, so that the title never overlaps the drawing.

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
    band = _title_band(fig, title, dpi)
    if band:
        ax.set_position((0, 0, 1, 1 - band))
        aspect = aspect / (1 - band)
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    mid = (lo + hi) / 2
    hx, hy = FRAME_MARGIN * np.maximum(hi - lo, 1e-12)                # a 6 % margin
    hx, hy = max(hx, hy * aspect), max(hy, hx / aspect)                # one scale on both axes
    ax.set_xlim(mid[0] - hx, mid[0] + hx)
    ax.set_ylim(mid[1] - hy, mid[1] + hy)
    return write_png(fig, path, dpi, background)


def write_png(fig, path, dpi, background) -> str:
    """Save ``fig`` as a PNG at ``path``; a failed or interrupted render leaves no half-written picture."""
    from dhlb._files import atomic_write

    out = os.fspath(path)
    with atomic_write(out, "wb") as fh:
        fig.savefig(fh, format="png", dpi=dpi, facecolor=background)
    return out
