"""PNG pictures of direction fields on triangle meshes (matplotlib, Agg; no pyplot state).

The mesh is drawn with an orthographic camera looking from ``view`` toward the mesh centre,
Lambert-shaded with a light near the camera. Faces pointing away from the camera are culled
on closed meshes (on meshes with boundary both sides are shown). Faces, direction glyphs (short
segments from each vertex along each of its n directions) and singularities (dots: red for
positive index, blue for negative) are depth-sorted together and drawn back to front in one
``PolyCollection`` (painter's algorithm), so glyphs and dots on the far side are hidden.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import InvalidParameterError, InvalidSimplexError, NonFiniteError, ShapeError

if TYPE_CHECKING:
    from collections.abc import Sequence
    from typing import Any

    from numpy.typing import ArrayLike

__all__ = ["render_field_png"]


def _matplotlib():
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.collections import PolyCollection
        from matplotlib.figure import Figure
    except ImportError:  # pragma: no cover - exercised only without matplotlib
        raise ImportError("render_field_png needs matplotlib; install it with  pip install 'dhlb[viz]'  "
                          "(or pip install matplotlib)") from None
    return Figure, FigureCanvasAgg, PolyCollection


def _unit(x):
    n = np.linalg.norm(x, axis=-1, keepdims=True)
    return x / np.where(n > 0, n, 1.0)


def _camera(view, up):
    w = np.asarray(view, float).reshape(-1)
    if w.shape != (3,) or not np.all(np.isfinite(w)) or not np.any(w):
        raise InvalidParameterError("view must be a nonzero 3D direction (camera position relative to the mesh), "
                                    f"got {view!r}")
    w = _unit(w)
    u = np.asarray(up, float).reshape(-1)
    if u.shape != (3,) or np.linalg.norm(np.cross(u, w)) < 1e-6 * np.linalg.norm(u):
        u = np.array([0.0, 1.0, 0.0]) if abs(w[1]) < 0.9 else np.array([1.0, 0.0, 0.0])
    right = _unit(np.cross(u, w))
    return right, np.cross(w, right), w


def _check(V, F, directions, singularities):
    P = np.asarray(V, dtype=float)
    if P.ndim != 2 or P.shape[1] != 3:
        raise ShapeError(f"V must have shape (n, 3), got {P.shape}")
    if not np.all(np.isfinite(P)):
        raise NonFiniteError(f"vertex {int(np.argmax(~np.isfinite(P).all(1)))} has a NaN or infinite coordinate")
    T = np.asarray(F)
    if T.ndim != 2 or T.shape[1] != 3 or T.shape[0] == 0 or not np.issubdtype(T.dtype, np.integer):
        raise InvalidSimplexError(f"F must be a non-empty integer array of shape (m, 3), got {T.shape} {T.dtype}")
    if T.min() < 0 or T.max() >= len(P):
        raise InvalidSimplexError(f"F refers to vertices outside V (rows 0 .. {len(P) - 1})")
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
    return P, T.astype(np.int64), D, S


def render_field_png(
    path: str | os.PathLike[str],
    V: ArrayLike,
    F: ArrayLike,
    directions: ArrayLike | None = None,
    singularities: Any = None,
    *,
    view: Sequence[float] = (1.0, -1.6, 1.0),
    up: Sequence[float] = (0.0, 0.0, 1.0),
    size: tuple[int, int] = (800, 800),
    dpi: int = 100,
    glyph_length: float | None = None,
    glyph_width: float = 0.7,
    glyph_color: Any = "#1a1a1a",
    face_color: Any = (0.78, 0.80, 0.86),
    ambient: float = 0.3,
    max_glyphs: int = 40000,
    dot_radius: float | None = None,
    background: Any = "white",
    title: str | None = None,
) -> str:
    r"""Render a mesh with a direction field and its singularities to a PNG file.

    Parameters
    ----------
    path : str or path-like
        Output file (PNG).
    V : (N, 3) float, F : (m, 3) int
        The mesh (e.g. ``mesh.points`` and ``mesh.faces`` of a :class:`dhlb.mesh.SurfaceMesh`).
    directions : (N, k, 3) or (N, 3) float, optional
        Unit directions per vertex (:func:`dhlb.fields.direction_vectors`); rows of zeros
        draw nothing.
    singularities : Singularities or tuple, optional
        A :class:`dhlb.fields.Singularities` or a tuple ``(points, index)`` of shapes ``(s, 3)``
        and ``(s,)``; drawn as red (index > 0) and blue (index < 0) dots.
    view, up : 3-vectors
        Camera direction (from the mesh toward the camera) and the world direction shown upward.
    size : (width, height) in pixels; dpi : int
    glyph_length : float, optional
        Length of a glyph in world units (default: 0.45 × mean edge length).
    max_glyphs : int
        At most this many vertices get glyphs (an evenly spread subset if there are more).
    dot_radius : float, optional
        Radius of a singularity dot (default: the larger of 0.35 × mean edge length and 0.6 % of the picture).

    Returns
    -------
    str
        The path written.

    Examples
    --------
    >>> import os, tempfile, numpy as np
    >>> from dhlb.render import render_field_png
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
    >>> F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = render_field_png(os.path.join(d, "t.png"), V, F, directions=np.tile([1.0, 0, 0], (4, 1)))
    ...     open(p, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    True
    """
    Figure, FigureCanvasAgg, PolyCollection = _matplotlib()
    P, T, D, S = _check(V, F, directions, singularities)
    right, upv, w = _camera(view, up)
    c = P.mean(axis=0)
    Q = P - c
    xy, depth = np.stack([Q @ right, Q @ upv], axis=1), Q @ w
    fn = _unit(np.cross(P[T[:, 1]] - P[T[:, 0]], P[T[:, 2]] - P[T[:, 0]]))
    edges = np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    closed = bool(np.all(counts == 2))
    facing = fn @ w
    light = _unit(w + 0.35 * upv + 0.15 * right)
    shade = fn @ light
    keep = facing > 0 if closed else np.ones(len(T), bool)
    shade = np.where(facing < 0, -shade, shade) if not closed else shade
    lam = ambient + (1 - ambient) * np.clip(shade, 0, 1)
    fcol = np.clip(np.asarray(face_color, float)[None, :3] * lam[:, None], 0, 1)
    mean_edge = float(np.mean(np.linalg.norm(P[edges[:, 0]] - P[edges[:, 1]], axis=1)))
    from matplotlib.colors import to_rgba
    # every item is a triangle (glyphs: degenerate (a, b, b); dots: fans of 10 triangles), so that
    # matplotlib takes the fast (k, 3, 2) array path; all items are depth-sorted together
    tris, zs = [xy[T[keep]]], [depth[T[keep]].mean(axis=1)]
    face_rgba = np.column_stack([fcol[keep], np.ones(keep.sum())])
    colors, edgecols = [face_rgba], [face_rgba]
    if D is not None:
        ell = 0.45 * mean_edge if glyph_length is None else float(glyph_length)
        vn = np.zeros_like(P)
        np.add.at(vn, T.ravel(), np.repeat(fn, 3, axis=0))
        has = np.any(D != 0, axis=(1, 2)) & ((vn @ w > 0) if closed else True)
        verts = np.nonzero(has)[0]
        if verts.size > max_glyphs:
            verts = verts[np.linspace(0, verts.size - 1, max_glyphs).astype(np.int64)]
        vv, kk = np.nonzero(np.any(D[verts] != 0, axis=2))
        vv = verts[vv]
        tip = Q[vv] + ell * D[vv, kk]
        b = np.stack([tip @ right, tip @ upv], axis=1)
        tris.append(np.stack([xy[vv], b, b], axis=1))
        zs.append(depth[vv] + 0.8 * mean_edge)
        colors.append(np.zeros((vv.size, 4)))
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
        dc = np.repeat(np.where((idx > 0)[:, None], to_rgba("#d62728"), to_rgba("#1f4fd6")), 10, axis=0)
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


def finish_figure(fig, ax, path, xy, aspect, title, dpi, background) -> str:
    """Frame the projected points ``xy`` with a small margin, add the title, write the PNG."""
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    mid, half = (lo + hi) / 2, 0.53 * max((hi - lo).max(), 1e-12)
    ax.set_xlim(mid[0] - half * max(aspect, 1), mid[0] + half * max(aspect, 1))
    ax.set_ylim(mid[1] - half / min(aspect, 1), mid[1] + half / min(aspect, 1))
    if title:
        ax.text(0.02, 0.98, title, transform=ax.transAxes, va="top", ha="left", fontsize=10)
    from dhlb._files import atomic_write

    out = os.fspath(path)
    with atomic_write(out, "wb") as fh:  # a failed or interrupted render leaves no half-written picture
        fig.savefig(fh, format="png", dpi=dpi, facecolor=background)
    return out
