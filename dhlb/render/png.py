"""PNG pictures of direction fields on triangle meshes (matplotlib, Agg; no pyplot state).

The mesh is drawn with an orthographic camera looking from ``view`` toward the mesh centre,
Lambert-shaded with a light near the camera. Faces pointing away from the camera are culled
on closed meshes (on meshes with boundary both sides are shown). Faces, direction glyphs (short
segments from each vertex along each of its n directions, with an arrowhead when n = 1; on a mesh
finer than the picture, from an evenly spread subset of the vertices, :func:`glyph_sites`) and
singularities (dots: red for positive index, blue for negative) are depth-sorted together and
drawn back to front in one
``PolyCollection`` (painter's algorithm), so glyphs and dots on the far side are hidden.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

import numpy as np

from dhlb._deprecation import fold_deprecated_kwargs
from dhlb.errors import NonFiniteError, ShapeError
from dhlb.mesh.arrays import mesh_arrays
from dhlb.render._figure import (
    _CAMERA,
    NEGATIVE,
    POSITIVE,
    Camera,
    FieldStyle,
    _matplotlib,
    _unit,
    face_normals,
    finish_figure,
    pixels_per_unit,
    thin_out,
)

if TYPE_CHECKING:
    from typing import Any

    from numpy.typing import ArrayLike

__all__ = ["GLYPH_SPACING", "glyph_sites", "render_field_png"]

GLYPH_SPACING = 7.2
"""The least distance between two direction glyphs on a picture, in points (10 pixels at 100 dpi).

On a mesh whose vertices are closer than that on the picture (a fine scan), the glyphs are drawn on
an evenly spread subset of the vertices, :func:`glyph_sites`: one glyph per vertex would merge into a
grey moiré.
"""

_FIELD_STYLE = ("glyph_length", "glyph_width", "glyph_color", "face_color", "ambient", "max_glyphs", "dot_radius",
                "background")


def _check(V, F, directions, singularities):
    P, T = mesh_arrays(V, F, 3)
    D = None
    if directions is not None:
        D = np.asarray(directions, float)
        if D.ndim == 2:
            D = D[:, None, :]
        if D.ndim != 3 or D.shape[0] != len(P) or D.shape[2] != 3:
            raise ShapeError("directions must have shape (n_vertices, k, 3) or (n_vertices, 3), "
                             f"got {np.shape(directions)}")
        if not np.all(np.isfinite(D)):
            v = int(np.argmax(~np.isfinite(D).all(axis=(1, 2))))
            raise NonFiniteError(f"the directions at vertex {v} are not finite")
    S = None
    if singularities is not None:
        pts, idx = (singularities.points, singularities.index) if hasattr(singularities, "points") else singularities
        pts, idx = np.asarray(pts, float).reshape(-1, 3), np.asarray(idx).reshape(-1)
        if len(pts) != len(idx):
            raise ShapeError(f"singularities: {len(pts)} points but {len(idx)} indices")
        if not np.all(np.isfinite(pts)):
            raise NonFiniteError("a singularity position is not finite")
        S = (pts, idx)
    return P, T, D, S


def glyph_sites(points, candidates, mean_edge: float, xy, size, dpi: int,
                max_glyphs: int) -> tuple[np.ndarray, float]:
    """The vertices that carry a glyph on a picture, and the spacing of the glyphs in world units.

    Every candidate when their mean edge length is at least :data:`GLYPH_SPACING` on the picture and
    they are at most ``max_glyphs``; else an evenly spread subset (:func:`dhlb.render._figure.thin_out`)
    with no two closer than that spacing in space, widened until at most ``max_glyphs`` remain.

    Parameters
    ----------
    points : (N, 3) float array
        The vertices.
    candidates : (k,) int array
        Rows of ``points`` that may carry a glyph (seen, with a direction).
    mean_edge : float
        The mean edge length of the mesh.
    xy : (N, 2) float array
        The vertices projected on the picture plane (world units), to find the scale of the picture.
    size : (int, int)
        The picture's width and height in pixels.
    dpi : int
    max_glyphs : int

    Returns
    -------
    sites : (m,) int array
        Rows of ``points``, ``m <= max_glyphs``.
    spacing : float
        ``mean_edge``, or the least distance between two sites when they were thinned out (the
        glyphs are 0.45 of it long).

    Examples
    --------
    >>> import numpy as np
    >>> g = np.stack(np.meshgrid(np.linspace(0, 1, 200), np.linspace(0, 1, 200)), -1).reshape(-1, 2)
    >>> P = np.c_[g, np.zeros(len(g))]                      # 40 000 vertices 0.005 apart
    >>> sites, spacing = glyph_sites(P, np.arange(len(P)), 0.005, g, (400, 400), 100, 40000)
    >>> len(sites) < 2000, round(spacing, 4)                 # 10 pixels: 1/38 of the picture's width
    (True, 0.0265)
    """
    candidates = np.asarray(candidates, dtype=np.int64)
    gap = GLYPH_SPACING * dpi / 72.0 / pixels_per_unit(xy, size)
    if mean_edge >= gap and candidates.size <= max_glyphs:
        return candidates, float(mean_edge)
    return thin_out(points, candidates, max(gap, float(mean_edge)), max_glyphs)


def render_field_png(
    path: str | os.PathLike[str],
    V: ArrayLike,
    F: ArrayLike,
    directions: ArrayLike | None = None,
    singularities: Any = None,
    *,
    camera: Camera | None = None,
    style: FieldStyle | None = None,
    title: str | None = None,
    **deprecated: Any,
) -> str:
    r"""Render a mesh with a direction field and its singularities to a PNG file.

    Parameters
    ----------
    path : str or path-like
        Output file (PNG).
    V : (N, 3) float array
        Vertex positions (e.g. ``mesh.points`` of a :class:`dhlb.mesh.SurfaceMesh`).
    F : (m, 3) int array
        Triangles (e.g. ``mesh.faces``).
    directions : (N, k, 3) or (N, 3) float array, optional
        Unit directions per vertex (:func:`dhlb.fields.direction_vectors`); rows of zeros
        draw nothing.
    singularities : Singularities or tuple, optional
        A :class:`dhlb.fields.Singularities` or a tuple ``(points, index)`` of shapes ``(s, 3)``
        and ``(s,)``; drawn as red (index > 0) and blue (index < 0) dots.
    camera : Camera, optional
        View direction, up direction, picture size and dpi (:class:`~dhlb.render.Camera`).
    style : FieldStyle, optional
        Glyphs, dots, colours and shading (:class:`~dhlb.render.FieldStyle`).
    title : str, optional
        Written in the top left corner.
    **deprecated
        The keywords of dhlb 0.1, with a :class:`DeprecationWarning`: ``view``, ``up``, ``size``, ``dpi``
        (→ ``camera``), ``glyph_length``, ``glyph_width``, ``glyph_color``, ``face_color``, ``ambient``,
        ``max_glyphs``, ``dot_radius``, ``background`` (→ ``style``).

    Returns
    -------
    str
        The path written.

    Examples
    --------
    >>> import os, tempfile, numpy as np
    >>> from dhlb.render import Camera, FieldStyle, render_field_png
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
    >>> F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = render_field_png(os.path.join(d, "t.png"), V, F, directions=np.tile([1.0, 0, 0], (4, 1)))
    ...     open(p, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    True
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = render_field_png(os.path.join(d, "t.png"), V, F, np.tile([1.0, 0, 0], (4, 1)),
    ...                          camera=Camera(view=(0, 0, 1), size=(64, 64)), style=FieldStyle(glyph_color="red"))
    ...     os.path.getsize(p) > 0
    True
    """
    camera, style = fold_deprecated_kwargs("render_field_png", deprecated, ("camera", camera, Camera(), _CAMERA),
                                           ("style", style, FieldStyle(), _FIELD_STYLE))
    Figure, FigureCanvasAgg, PolyCollection = _matplotlib()
    P, T, D, S = _check(V, F, directions, singularities)
    right, upv, w = camera.fitted(P).frame()
    size, dpi, background, ambient = camera.size, camera.dpi, style.background, style.ambient
    glyph_length, glyph_width, glyph_color = style.glyph_length, style.glyph_width, style.glyph_color
    face_color, max_glyphs, dot_radius = style.face_color, style.max_glyphs, style.dot_radius
    c = P.mean(axis=0)
    Q = P - c
    xy, depth = np.stack([Q @ right, Q @ upv], axis=1), Q @ w
    fn = _unit(face_normals(P, T))
    edges = np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    closed = bool(np.all(counts == 2))
    facing = fn @ w
    light = _unit(w + 0.35 * upv + 0.15 * right)
    shade = fn @ light
    keep = facing > 0 if closed else np.ones(len(T), bool)
    shade = np.where(facing < 0, -shade, shade) if not closed else shade
    lam = ambient + (1 - ambient) * np.clip(shade, 0, 1)
    from matplotlib.colors import to_rgb, to_rgba

    fcol = np.clip(np.asarray(to_rgb(face_color))[None, :] * lam[:, None], 0, 1)   # any matplotlib colour
    mean_edge = float(np.mean(np.linalg.norm(P[edges[:, 0]] - P[edges[:, 1]], axis=1)))
    # every item is a triangle (glyphs: degenerate (a, b, b); dots: fans of 10 triangles), so that
    # matplotlib takes the fast (k, 3, 2) array path; all items are depth-sorted together
    tris, zs = [xy[T[keep]]], [depth[T[keep]].mean(axis=1)]
    face_rgba = np.column_stack([fcol[keep], np.ones(keep.sum())])
    colors, edgecols = [face_rgba], [face_rgba]
    if D is not None:
        vn = np.zeros_like(P)
        np.add.at(vn, T.ravel(), np.repeat(fn, 3, axis=0))
        has = np.any(D != 0, axis=(1, 2)) & ((vn @ w > 0) if closed else True)
        verts, spacing = glyph_sites(P, np.nonzero(has)[0], mean_edge, xy, size, dpi, max_glyphs)
        ell = 0.45 * spacing if glyph_length is None else float(glyph_length)
        vv, kk = np.nonzero(np.any(D[verts] != 0, axis=2))
        vv = verts[vv]
        tip = Q[vv] + ell * D[vv, kk]
        b = np.stack([tip @ right, tip @ upv], axis=1)
        tris.append(np.stack([xy[vv], b, b], axis=1))
        zs.append(depth[vv] + 0.8 * mean_edge)
        colors.append(np.zeros((vv.size, 4)))
        edgecols.append(np.tile(to_rgba(glyph_color), (vv.size, 1)))
        if D.shape[1] == 1:                    # n = 1: a vector, not a line: an arrowhead shows which way
            along = b - xy[vv]
            length = np.linalg.norm(along, axis=1, keepdims=True)
            along = along / np.where(length > 0, length, 1.0)
            across = np.stack([-along[:, 1], along[:, 0]], axis=1)
            h = 0.35 * ell
            tris.append(np.stack([b, b - h * along + 0.45 * h * across, b - h * along - 0.45 * h * across], axis=1))
            zs.append(depth[vv] + 0.8 * mean_edge)
            colors.append(np.tile(to_rgba(glyph_color), (vv.size, 1)))
            edgecols.append(np.tile(to_rgba(glyph_color), (vv.size, 1)))
    extent = float(np.ptp(xy, axis=0).max()) or 1.0
    if S is not None and len(S[0]):
        pts, idx = S
        rad = max(0.35 * mean_edge, 0.006 * extent) if dot_radius is None else float(dot_radius)
        ang = np.linspace(0, 2 * np.pi, 11)
        ring = rad * np.stack([np.cos(ang), np.sin(ang)], axis=1)
        fan = np.stack([np.zeros((10, 2)), ring[:-1], ring[1:]], axis=1)  # (10, 3, 2)
        q = pts - c
        pxy = np.stack([q @ right, q @ upv], axis=1)
        tris.append((pxy[:, None, None, :] + fan[None]).reshape(-1, 3, 2))
        zs.append(np.repeat(q @ w + 2.5 * rad + mean_edge, 10))
        dc = np.repeat(np.where((idx > 0)[:, None], to_rgba(POSITIVE), to_rgba(NEGATIVE)), 10, axis=0)
        colors.append(dc)
        edgecols.append(dc)
    order = np.argsort(np.concatenate(zs), kind="stable")
    tris = np.concatenate(tris)[order]
    colors, edgecols = (np.concatenate(x)[order] for x in (colors, edgecols))
    W, H = size
    fig = Figure(figsize=(W / dpi, H / dpi), dpi=dpi, facecolor=background)
    FigureCanvasAgg(fig)
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_axis_off()
    # one line width for all items (per-item widths cost a dash computation each)
    ax.add_collection(PolyCollection(tris, facecolors=colors, edgecolors=edgecols, linewidths=glyph_width,
                                     closed=True, antialiaseds=True), autolim=False)
    return finish_figure(fig, ax, path, xy, W / H, title, dpi, background)
