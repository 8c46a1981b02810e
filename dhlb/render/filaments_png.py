"""PNG pictures of vortex filaments inside the outline of their domain (matplotlib, Agg).

Orthographic camera as in :func:`dhlb.render.render_field_png`. The domain is drawn as its
silhouette (the boundary triangles filled in one flat light colour) with its outline: the
*contour* edges of the boundary surface (one adjacent triangle faces the camera, the other
does not) and its *feature* edges (dihedral angle above 30°, e.g. the edges of a box), front
ones solid and back ones dashed. The filaments are drawn on top as polylines, one colour per
filament, segment by segment from back to front with a thin white halo, so crossings in depth
are readable; an arrowhead in the middle of each filament shows its direction.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb._coerce import curve_list
from dhlb._deprecation import fold_deprecated_kwargs
from dhlb.errors import ShapeError
from dhlb.mesh.arrays import mesh_arrays
from dhlb.render._figure import (
    _CAMERA,
    FILAMENT_COLORS,
    Camera,
    FilamentStyle,
    _matplotlib,
    _unit,
    face_normals,
    finish_figure,
    pixels_per_unit,
)

if TYPE_CHECKING:
    import os
    from collections.abc import Sequence
    from typing import Any

    from numpy.typing import ArrayLike

__all__ = ["FILAMENT_CAMERA", "feature_edges", "render_filaments_png"]

FILAMENT_CAMERA = Camera()
"""The default camera of :func:`render_filaments_png` (fitted to the domain, :meth:`Camera.fitted`)."""
_FILAMENT_STYLE = ("line_width", "fill", "outline_color", "background")

_COLORS = FILAMENT_COLORS


def _curves(filaments):
    """``curve_list`` with plain arrays taken as closed (as documented for the picture)."""
    items = filaments if isinstance(filaments, np.ndarray) else list(filaments)
    return curve_list([f if hasattr(f, "points") or isinstance(f, tuple) else (f, True) for f in items], "filaments")


def _edge_faces(F):
    """The edges of the triangles F: interior ones with their two faces, and the border edges.

    Returns ``(interior (e, 2), a (e,), b (e,), border (k, 2))``: each interior edge as a sorted vertex
    pair with the rows ``a``, ``b`` of its two faces.
    """
    E = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    face = np.tile(np.arange(F.shape[0]), 3)
    key = np.sort(E, axis=1)
    order = np.lexsort((key[:, 1], key[:, 0]))
    key, face = key[order], face[order]
    same = np.all(key[1:] == key[:-1], axis=1)
    i = np.nonzero(same)[0]  # pairs (i, i+1) of the two faces at an edge
    single = np.ones(key.shape[0], bool)
    single[i] = single[i + 1] = False
    return key[i], face[i], face[i + 1], key[single]


def feature_edges(V: ArrayLike, F: ArrayLike, angle: float = 30.0) -> np.ndarray:
    """The edges of a triangle surface where it bends by more than ``angle`` degrees, and its border.

    Parameters
    ----------
    V : (N, 3) float array
    F : (m, 3) int array
    angle : float
        Dihedral angle (between the two face normals) above which an edge is a feature edge.

    Returns
    -------
    (e, 2) int array
        Vertex pairs (e.g. the 12 edges of a box's boundary).

    Examples
    --------
    >>> from dhlb.mesh import box_tet_mesh
    >>> m = box_tet_mesh(2)
    >>> len(feature_edges(m.points, m.boundary_faces)) == 12 * 2
    True
    """
    P, T = np.asarray(V, dtype=np.float64), np.asarray(F, dtype=np.int64)
    fn = _unit(face_normals(P, T))
    inner, a, b, border = _edge_faces(T)
    bent = np.einsum("ij,ij->i", fn[a], fn[b]) < np.cos(np.radians(angle))
    return np.concatenate([inner[bent], border])


def _along(xy, closed: bool, reach: float) -> list:
    """For each segment of the projected polyline ``xy``, the other segments less than ``reach`` away along it."""
    length = np.linalg.norm(np.diff(xy, axis=0), axis=1)
    m = len(length)
    end = np.cumsum(length)
    start = end - length
    total = end[-1] if m else 0.0
    out = []
    for i in range(m):
        gap = np.maximum(start - end[i], start[i] - end)          # along the polyline, 0 for neighbours
        if closed:
            gap = np.minimum(gap, np.minimum(total - (end[i] - start), total - (end - start[i])))   # around
        j = np.nonzero(gap < reach)[0]
        out.append(j[j != i])
    return out


def _outline_edges(V, F, w):
    """Contour and feature edges of the triangle surface (V, F) seen along ``w``: (edges (e, 2), front (e,) bool)."""
    fn = _unit(face_normals(V, F))
    inner, a, b, border = _edge_faces(F)
    contour = np.sign(fn[a] @ w) != np.sign(fn[b] @ w)
    feature = np.einsum("ij,ij->i", fn[a], fn[b]) < np.cos(np.radians(30))
    keep = contour | feature
    front = contour[keep] | ((fn[a[keep]] @ w > 0) | (fn[b[keep]] @ w > 0))
    # open surfaces: their border is outline too
    return np.concatenate([inner[keep], border]), np.concatenate([front, np.ones(len(border), bool)])


def render_filaments_png(
    path: str | os.PathLike[str],
    filaments: Sequence[Any],
    V: ArrayLike | None = None,
    F: ArrayLike | None = None,
    *,
    camera: Camera | None = None,
    style: FilamentStyle | None = None,
    title: str | None = None,
    **deprecated: Any,
) -> str:
    r"""Render filaments (and optionally the boundary of their domain) to a PNG file.

    Parameters
    ----------
    path : str or path-like
        Output file (PNG).
    filaments : sequence of Filament or (m, 3) arrays
        Polylines; objects with ``.points`` and ``.closed`` (a :class:`dhlb.vortex.Filament`) or
        plain arrays (taken as closed).
    V : (N, 3) float array, optional
        Vertex positions of the boundary surface of the domain (e.g. ``mesh.points`` of a
        :class:`dhlb.mesh.TetMesh`), drawn as silhouette and outline.
    F : (b, 3) int array, optional
        Its triangles (e.g. ``mesh.boundary_faces``); give both ``V`` and ``F`` or neither.
    camera : Camera, optional
        View direction, up direction, picture size and dpi (:class:`~dhlb.render.Camera`; default
        :data:`FILAMENT_CAMERA`, looking a little lower than the other pictures).
    style : FilamentStyle, optional
        Line width and colours (:class:`~dhlb.render.FilamentStyle`).
    title : str, optional
        Written in the top left corner.
    **deprecated
        The keywords of dhlb 0.1, with a :class:`DeprecationWarning`: ``view``, ``up``, ``size``, ``dpi``
        (→ ``camera``), ``line_width``, ``fill``, ``outline_color``, ``background`` (→ ``style``).

    Returns
    -------
    str
        The path written.

    Raises
    ------
    ShapeError
        A filament is not an ``(m, 3)`` array of points; ``V`` is not ``(N, 3)``; only one of ``V`` and ``F``.
    NonFiniteError
        A filament point or a vertex is NaN or infinite.
    InvalidSimplexError
        ``F`` is not a non-empty ``(b, 3)`` integer array of rows of ``V``.

    Examples
    --------
    >>> import os, tempfile
    >>> from dhlb.mesh import box_tet_mesh
    >>> from dhlb.render import FILAMENT_CAMERA, FilamentStyle
    >>> from dhlb.vortex import hopf_link
    >>> mesh = box_tet_mesh(2, lower=-1.5, upper=2.5)
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = render_filaments_png(os.path.join(d, "f.png"), hopf_link(n=40), mesh.points, mesh.boundary_faces,
    ...                              camera=FILAMENT_CAMERA.replace(size=(200, 200)), style=FilamentStyle(line_width=3))
    ...     open(p, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    True
    """
    camera, style = fold_deprecated_kwargs("render_filaments_png", deprecated,
                                           ("camera", camera, FILAMENT_CAMERA, _CAMERA),
                                           ("style", style, FilamentStyle(), _FILAMENT_STYLE))
    size, dpi, background, line_width = camera.size, camera.dpi, style.background, style.line_width
    fill, outline_color = style.fill, style.outline_color
    Figure, FigureCanvasAgg, PolyCollection = _matplotlib()
    from matplotlib.collections import LineCollection
    from matplotlib.colors import to_rgba

    curves = _curves(filaments)
    pts = [P for P, _ in curves]
    P = Ft = None
    if V is not None or F is not None:
        if V is None or F is None:
            raise ShapeError("give both V and F for the domain outline (or neither)")
        P, Ft = mesh_arrays(V, F, 3)
        pts = pts + [P[np.unique(Ft)]]
    allp = np.concatenate(pts) if pts else np.zeros((1, 3))
    right, upv, w = camera.fitted(allp).frame()
    c = 0.5 * (allp.min(axis=0) + allp.max(axis=0))

    def proj(X):
        Q = X - c
        return np.stack([Q @ right, Q @ upv], axis=1), Q @ w

    W, H = size
    fig = Figure(figsize=(W / dpi, H / dpi), dpi=dpi, facecolor=background)
    FigureCanvasAgg(fig)
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_axis_off()
    xy_all = [proj(allp)[0]]
    if P is not None:
        xy, _ = proj(P)
        ax.add_collection(PolyCollection(xy[Ft], facecolors=[fill], edgecolors=[fill], linewidths=0.3,
                                         zorder=0), autolim=False)
        edges, front = _outline_edges(P, Ft, w)
        for sel, style in ((~front, (0, (3, 3))), (front, "solid")):
            if np.any(sel):
                ax.add_collection(LineCollection(xy[edges[sel]], colors=outline_color, linewidths=0.8,
                                                 linestyles=style, zorder=1), autolim=False)
    pixels = pixels_per_unit(xy_all[0], size)
    reach = 1.5 * ((line_width + 2.0) / 2 * dpi / 72.0 + 1.0) / pixels   # of a halo's round cap, with room
    segs, depth, cols, near = [], [], [], []
    for k, (X, closed) in enumerate(curves):
        if X.shape[0] < 2:
            continue
        Y = np.concatenate([X, X[:1]]) if closed else X
        xy, d = proj(Y)
        base = sum(len(x) for x in segs)
        segs.append(np.stack([xy[:-1], xy[1:]], axis=1))
        depth.append(0.5 * (d[:-1] + d[1:]))
        cols.append(np.tile(to_rgba(_COLORS[k % len(_COLORS)]), (xy.shape[0] - 1, 1)))
        near += [base + j for j in _along(xy, closed, reach)]
        mid = (Y.shape[0] - 1) // 2
        ax.annotate("", xy=xy[mid + 1], xytext=xy[mid], zorder=4,
                    arrowprops={"arrowstyle": "-|>", "color": _COLORS[k % len(_COLORS)], "lw": 0,
                                "mutation_scale": 14})
    if segs:
        S, D, C = np.concatenate(segs), np.concatenate(depth), np.concatenate(cols)
        order = np.argsort(D, kind="stable")
        # back to front, each segment: its halo, then in colour the segments of its own filament that the
        # halo's cap reaches (along the filament) and itself last, with round caps: a halo covers what the
        # segment passes in front of, never its own filament's joints (no white notch across the line)
        rows = np.concatenate([np.r_[i, near[i], i] for i in order.tolist()])
        halo = np.concatenate([np.r_[True, np.zeros(len(near[i]) + 1, bool)] for i in order.tolist()])
        inter, icol = S[rows], C[rows]
        icol[halo] = to_rgba(background)
        widths = np.where(halo, line_width + 2.0, float(line_width))
        ax.add_collection(LineCollection(inter, colors=icol, linewidths=widths, capstyle="round", joinstyle="round",
                                         zorder=3), autolim=False)
    return finish_figure(fig, ax, path, np.concatenate(xy_all), W / H, title, dpi, background)
